// `nestwalk bench walker --quick --json`: a smoke run of the walker benchmark a user runs. Times
// are not asserted; what it checks is measured: the broad phase finds the same hits as btDbvt and
// FCL (the run fails otherwise), and every hierarchy gives the same contacts on the bundled
// flythroughs (the fACT Table 2 part), with the template hierarchy as the 100 % row.
#include "tests/common/run_command.h"

#include <nlohmann/json.hpp>

#include <filesystem>

namespace nestwalk::test {
namespace {

TEST(BenchWalker, QuickJsonRunHasStepsBroadPhaseAndTable2) {
  const CommandResult r = runNestwalk("bench walker --quick --json");
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["walker_steps"].size(), 2u);
  for (const auto& s : j["walker_steps"]) {
    EXPECT_GT(s["steps"].get<long>(), 1000);
    EXPECT_LE(s["p50_us"].get<double>(), s["p99_us"].get<double>());
  }
  ASSERT_TRUE(j.contains("broad_phase"));
  if (std::filesystem::exists(std::filesystem::path(NESTWALK_BUNDLED_SCENE_DIR) / "scene.json")) {
    ASSERT_TRUE(j.contains("table2"));
    EXPECT_TRUE(j["table2_identical_contacts"].get<bool>());
    EXPECT_EQ(j["table2"][0]["hierarchy"], "template");
    EXPECT_DOUBLE_EQ(j["table2"][0]["percent_of_template"].get<double>(), 100.0);
    EXPECT_EQ(j["table2"].size(), 13u);
  }
}

}  // namespace
}  // namespace nestwalk::test
