// `nestwalk demo`, the README's main job for now: it runs and its verdicts follow from the
// station's geometry (far away: free; the body's centre on the mast: blocked).
#include "tests/common/run_command.h"

#include <map>
#include <vector>

namespace nestwalk::test {
namespace {

TEST(Demo, RunsAndReportsVerdicts) {
  const CommandResult r = runNestwalk("demo");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("48 vertices, 72 triangles"), std::string::npos) << r.out;
  // Each verdict line: distance, verdict, stage, axis.
  std::map<std::string, std::vector<std::string>> rows;
  std::stringstream ss(r.out);
  for (std::string line; std::getline(ss, line);) {
    std::stringstream ls(line);
    std::vector<std::string> cols;
    for (std::string c; ls >> c;) cols.push_back(c);
    if (cols.size() >= 3 && (cols[1] == "free" || cols[1] == "blocked")) rows[cols[0]] = cols;
  }
  ASSERT_EQ(rows.size(), 8u) << r.out;
  EXPECT_EQ(rows["20.00"], (std::vector<std::string>{"20.00", "free", "aabb-aabb", "x"}));
  EXPECT_EQ(rows["0.00"], (std::vector<std::string>{"0.00", "blocked", "obb-obb"}));
  EXPECT_EQ(r.err, "") << "no warnings from loading the bundled model";
}

}  // namespace
}  // namespace nestwalk::test
