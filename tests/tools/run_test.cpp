// `nestwalk run` on the bundled mining-dump scene (generated at build time into
// build/assets/mining_dump): every bundled flythrough meets its expectations, the per-frame CSV is
// byte-identical between runs once the timing columns are cut, every hierarchy gives the same
// contacts, and bad input and failed expectations end with their messages and exit codes.
#include "tests/common/build_paths.h"
#include "tests/common/run_command.h"

#include <nlohmann/json.hpp>

#include <filesystem>

namespace nestwalk::test {
namespace {

namespace fs = std::filesystem;

const fs::path kScene = fs::path(nestwalk::test::build::bundledSceneDir()) / "scene.json";
const fs::path kScripts = fs::path(nestwalk::test::build::bundledSceneDir()) / "scripts";
const char* const kScriptNames[] = {"bench_patrol.txt", "ramp_descent.txt", "low_flight.txt", "equipment_walk.txt",
                                    "equipment_fly.txt"};

/// The CSV with the columns from `firstCut` on removed (the timing columns come last).
std::string cutColumns(const std::string& csv, const std::string& firstCut) {
  std::stringstream in(csv);
  std::string line, out;
  std::getline(in, line);
  std::size_t keep = 0;
  {
    std::stringstream h(line);
    std::string col;
    while (std::getline(h, col, ',') && col != firstCut) ++keep;
  }
  in.clear();
  in.seekg(0);
  while (std::getline(in, line)) {
    std::size_t pos = 0;
    for (std::size_t i = 0; i < keep && pos != std::string::npos; ++i) {
      pos = line.find(',', pos);
      if (pos != std::string::npos) ++pos;
    }
    out += (pos == std::string::npos ? line : line.substr(0, pos)) + "\n";
  }
  return out;
}

class BundledRun : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override {
    if (!fs::exists(kScene)) GTEST_SKIP() << kScene << " is absent: build the bundled_scene target";
  }
};

TEST_P(BundledRun, MeetsItsExpectationsAndIsDeterministic) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const fs::path script = kScripts / GetParam();
  const auto a = runNestwalk("run " + quoted(kScene) + " --script " + quoted(script) + " --headless --out " +
                             quoted(dir / "a"));
  ASSERT_EQ(a.exitCode, 0) << a.out << a.err;
  EXPECT_NE(a.out.find("expectations: "), std::string::npos);
  const auto summary = nlohmann::json::parse(readText(dir / "a" / "summary.json"));
  EXPECT_GT(summary["frames"].get<long>(), 10);
  for (const char* f : {"frames.csv", "summary.json", "frame_times.png", "camera.path"})
    EXPECT_TRUE(fs::exists(dir / "a" / f)) << f;
  const auto b = runNestwalk("run " + quoted(kScene) + " --script " + quoted(script) + " --headless --out " +
                             quoted(dir / "b"));
  ASSERT_EQ(b.exitCode, 0) << b.out << b.err;
  const std::string csvA = readText(dir / "a" / "frames.csv"), csvB = readText(dir / "b" / "frames.csv");
  EXPECT_NE(csvA, "");
  EXPECT_EQ(cutColumns(csvA, "us_ground"), cutColumns(csvB, "us_ground"));
  // Existing outputs are kept unless --overwrite.
  const auto again = runNestwalk("run " + quoted(kScene) + " --script " + quoted(script) + " --headless --out " +
                                 quoted(dir / "a"));
  EXPECT_EQ(again.exitCode, 1);
  EXPECT_NE(again.err.find("--overwrite"), std::string::npos) << again.err;
}

TEST_P(BundledRun, EveryHierarchyGivesTheSameContacts) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const fs::path script = kScripts / GetParam();
  std::string reference;
  int n = 0;
  for (std::string h : {"--hierarchy template", "--hierarchy auto --degree 2 --split-axis longest --split-point mean",
                        "--hierarchy auto --degree 4 --split-axis splatter --split-point median",
                        "--hierarchy auto --degree 8 --split-axis longest --split-point median",
                        "--hierarchy auto --degree 8 --split-axis splatter --split-point mean"}) {
    const fs::path out = dir / std::to_string(n++);
    const auto r = runNestwalk("run " + quoted(kScene) + " --script " + quoted(script) + " --headless --quiet --out " +
                               quoted(out) + " " + h);
    ASSERT_EQ(r.exitCode, 0) << h << "\n" << r.out << r.err;
    // Contacts and positions: every column before the counters.
    const std::string c = cutColumns(readText(out / "frames.csv"), "node_tests");
    if (reference.empty()) reference = c;
    EXPECT_EQ(c, reference) << h;
  }
}

TEST(Run, AWalkedCameraPathCanBeFlownAsAScript) {
  if (!fs::exists(kScene)) GTEST_SKIP() << kScene << " is absent";
  const TempFolder folder;
  const fs::path dir = folder.path();
  const auto a = runNestwalk("run " + quoted(kScene) + " --script " + quoted(kScripts / "ramp_descent.txt") +
                             " --headless --quiet --out " + quoted(dir / "walk"));
  ASSERT_EQ(a.exitCode, 0) << a.out << a.err;
  const auto b = runNestwalk("run " + quoted(kScene) + " --script " + quoted(dir / "walk" / "camera.path") +
                             " --headless --quiet --out " + quoted(dir / "fly"));
  ASSERT_EQ(b.exitCode, 0) << b.out << b.err;
  const auto walked = nlohmann::json::parse(readText(dir / "walk" / "summary.json"));
  const auto flown = nlohmann::json::parse(readText(dir / "fly" / "summary.json"));
  // The path's points are flown at the recorded speed: about as many frames as the walk.
  EXPECT_NEAR(flown["frames"].get<double>(), walked["frames"].get<double>(), 0.05 * walked["frames"].get<double>());
}

INSTANTIATE_TEST_SUITE_P(Scripts, BundledRun, ::testing::ValuesIn(kScriptNames),
                         [](const auto& info) { return fs::path(info.param).stem().string(); });

TEST(Run, FailedExpectationsNameTheFrameAndPositionAndExitWith3) {
  if (!fs::exists(kScene)) GTEST_SKIP() << kScene << " is absent";
  const TempFolder folder;
  const fs::path dir = folder.path();
  // Start the bench patrol, then expect to be blocked right away (it is not).
  std::string text = readText(kScripts / "bench_patrol.txt");
  const std::size_t startLine = text.find("start ");
  ASSERT_NE(startLine, std::string::npos);
  const std::size_t eol = text.find('\n', startLine);
  const std::string head = text.substr(0, eol + 1);
  writeText(dir / "fail.txt", head + "wait 0.1\nexpect blocked by nothing/here\n");
  const auto r = runNestwalk("run " + quoted(kScene) + " --script " + quoted(dir / "fail.txt") + " --headless --out " +
                             quoted(dir / "out"));
  EXPECT_EQ(r.exitCode, 3) << r.out << r.err;
  EXPECT_NE(r.out.find("FAILED"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("at frame 6"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("eye ("), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(dir / "out" / "summary.json"));
}

TEST(Run, BadScriptsAndScenesNameTheFileAndLine) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  writeText(dir / "bad.txt", "mode walk\nstart 1 2\ngoto 5\n");
  if (fs::exists(kScene)) {
    const auto r = runNestwalk("run " + quoted(kScene) + " --script " + quoted(dir / "bad.txt") + " --headless --out " +
                               quoted(dir / "o"));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("bad.txt:3"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "o" / "frames.csv"));
  }
  writeText(dir / "scene.json", "{\"terrain\": 5}");
  writeText(dir / "ok.txt", "start 0 0\n");
  const auto r = runNestwalk("run " + quoted(dir / "scene.json") + " --script " + quoted(dir / "ok.txt") +
                             " --headless --out " + quoted(dir / "o2"));
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find("scene.json"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("terrain"), std::string::npos) << r.err;
}

TEST(Run, ASceneNamingACutModelEndsWithItsReasonAndWritesNothing) {
  // The bundled scene's terrain with one piece whose model is the bundled pickup cut in half as
  // .osgb: run, report and export end with the model named and its reason, exit 1, no output.
  if (!fs::exists(kScene)) GTEST_SKIP() << kScene << " is absent: build the bundled_scene target";
  const TempFolder folder;
  const fs::path dir = folder.path();
  const fs::path bundled = kScene.parent_path();
  ASSERT_EQ(runNestwalk("export " + quoted(kScene) + " " + quoted(dir / "whole.osgb") + " --no-terrain").exitCode, 0);
  const std::string bytes = readText(dir / "whole.osgb");
  writeText(dir / "cut.osgb", bytes.substr(0, bytes.size() / 2));
  const auto terrain = nlohmann::json::parse(readText(kScene))["terrain"].get<std::string>();
  const nlohmann::json scene = {{"terrain", (bundled / terrain).string()},
                                {"equipment", {{{"model", "cut.osgb"}, {"position", {550000.0, 4650000.0}}}}}};
  writeText(dir / "scene.json", scene.dump());
  writeText(dir / "ok.txt", "start 550010 4650010\n");
  for (const std::string& command :
       {"run " + quoted(dir / "scene.json") + " --script " + quoted(dir / "ok.txt") + " --headless --out " +
            quoted(dir / "out"),
        "report " + quoted(dir / "scene.json") + " --scripts " + quoted(dir / "ok.txt") + " --quick --out " +
            quoted(dir / "report"),
        "export " + quoted(dir / "scene.json") + " " + quoted(dir / "scene.osgb")}) {
    const auto r = runNestwalk(command);
    EXPECT_EQ(r.exitCode, 1) << command << "\n" << r.err;
    EXPECT_NE(r.err.find((dir / "cut.osgb").string() + " ("), std::string::npos) << command << "\n" << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "out"));
  EXPECT_FALSE(fs::exists(dir / "report" / "report.md"));
  EXPECT_FALSE(fs::exists(dir / "scene.osgb"));
}

}  // namespace
}  // namespace nestwalk::test
