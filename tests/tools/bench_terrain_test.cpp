// `nestwalk bench terrain --quick --json`: a smoke run of the terrain benchmark a user runs. Times
// are not asserted; the agreement it measures is: every peer finds the same vertical hits as
// nestwalk's groundHeight, and the LOD table is monotone.
#include "tests/common/run_command.h"

#include <nlohmann/json.hpp>

namespace nestwalk::test {
namespace {

TEST(BenchTerrain, QuickJsonRunHasPeersTargetsAndLevels) {
  const CommandResult r = runNestwalk("bench terrain --quick --json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.contains("benchmarks"));
  ASSERT_TRUE(j.contains("targets"));
  ASSERT_TRUE(j.contains("lod_levels"));
  EXPECT_FALSE(j["benchmarks"].empty());
  double previousError = -1.0;
  for (const auto& level : j["lod_levels"]) {
    const double e = level["max_error_m"].get<double>();
    EXPECT_GE(e, previousError) << "coarser levels never have a smaller recorded error";
    previousError = e;
  }
}

}  // namespace
}  // namespace nestwalk::test
