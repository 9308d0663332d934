// `nestwalk bench contact --quick --json` on a box model written here (a 2 x 2 x 2 m cube, 12
// triangles): every method meets the body on each of the 8 quick approaches (4 sides, on the
// ground and at half height) and on the 4 pressing sweeps after each, so 40 contacts each; ours
// with its memory of free paths and each step alone answer every sweep alike (the second target);
// FCL's sampled times of contact are within 0.1 mm of ours, and wherever a peer differs from ours
// by more than that, conservative advancement sides with ours (the third target is met). The ratio
// columns are the stated quotients of the p50 and p99 times. Times are not asserted. A model that
// cannot be read is an error naming it.
#include "tests/common/box_model.h"
#include "tests/common/run_command.h"
#include "tests/common/temp_folder.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace nestwalk::test {
namespace {

TEST(BenchContact, QuickJsonRunOnACubeAgreesWithThePeers) {
  const TempFolder dir;
  writeBoxModel(dir / "cube.osgt", {-1, -1, 0}, {1, 1, 2});
  const CommandResult r = runNestwalk("bench contact --quick --json --models " + (dir / "cube.osgt").string() + ":1:z");
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["models"].size(), 4u);
  const nlohmann::json& ours = j["models"][0];
  EXPECT_EQ(ours["method"], "nestwalk");
  EXPECT_EQ(j["models"][1]["method"], "alone");
  for (const auto& row : j["models"]) {
    SCOPED_TRACE(row["method"].get<std::string>());
    EXPECT_EQ(row["triangles"], 12);
    EXPECT_EQ(row["contacts"], 40);
    if (row["method"] == "nestwalk") continue;
    EXPECT_DOUBLE_EQ(row["ratio"]["p50"].get<double>(), row["us"]["p50"].get<double>() / ours["us"]["p50"].get<double>());
    EXPECT_DOUBLE_EQ(row["ratio"]["p99"].get<double>(), row["us"]["p99"].get<double>() / ours["us"]["p99"].get<double>());
    if (row["method"] == "alone") continue;
    EXPECT_EQ(row["apart_mm"]["over"], row["apart_mm"]["ours_right"]);
    if (row["method"] == "FCL") {
      EXPECT_LE(row["apart_mm"]["max"].get<double>(), 0.1);
    }
  }
  ASSERT_EQ(j["targets"].size(), 3u);
  EXPECT_TRUE(j["targets"][1]["met"].get<bool>()) << j["targets"][1].dump();
  EXPECT_TRUE(j["targets"][2]["met"].get<bool>()) << j["targets"][2].dump();
}

TEST(BenchContact, AnUnreadableModelIsNamed) {
  const TempFolder dir;
  writeBoxModel(dir / "cube.osgt", {-1, -1, 0}, {1, 1, 2});
  const CommandResult units = runNestwalk("bench contact --quick --models " + (dir / "cube.osgt").string() + ":0:z");
  EXPECT_NE(units.exitCode, 0);
  EXPECT_NE((units.out + units.err).find("cube.osgt:0:z: the units '0' are not a positive number"), std::string::npos)
      << units.out << units.err;
  const CommandResult missing = runNestwalk("bench contact --quick --models " + (dir / "missing.osgt").string());
  EXPECT_NE(missing.exitCode, 0);
  EXPECT_NE((missing.out + missing.err).find("missing.osgt"), std::string::npos) << missing.out << missing.err;
}

}  // namespace
}  // namespace nestwalk::test
