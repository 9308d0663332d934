// `nestwalk publish`: a bench-patrol run on the bundled scene published as a site, whose run.json
// holds frames.csv's path in the local frame (map minus the GLB's map origin) and results.geojson's
// contacts; then the page in Debian's Chromium (tools/web/drive_page.mjs, playwright-core,
// software WebGL): it loads with no console error, the time slider at t puts the walker where
// frames.csv has it at t, and clicking the first contact moves the camera to the contact's frame and
// shows its unit's name. A folder that is not a run's is refused naming what is missing; an existing
// site is kept unless --overwrite.
#include "tests/common/build_paths.h"
#include "tests/common/gltf_validator.h"
#include "tests/common/run_command.h"
#include "tests/common/temp_folder.h"
#include "tests/common/test_data.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>

namespace nestwalk::test {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

constexpr double kPositionToleranceM = 0.01;
constexpr const char* kAxes[] = {"x", "y", "z"};  // the page's float32 scene against frames.csv's 4 decimals

std::string readAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// frames.csv's rows as {time, x, y, z} (map frame).
std::vector<std::array<double, 4>> framesOf(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);  // frame,time,x,y,z,...
  std::vector<std::array<double, 4>> rows;
  while (std::getline(in, line)) {
    std::stringstream s(line);
    std::string field;
    std::array<double, 5> v{};
    for (double& x : v) {
      std::getline(s, field, ',');
      x = std::stod(field);
    }
    rows.push_back({v[1], v[2], v[3], v[4]});
  }
  return rows;
}

/// A recorded run of the bundled bench patrol, written into `dir` / run.
fs::path recordRun(const TempFolder& dir) {
  const fs::path run = dir / "run";
  const CommandResult r = runNestwalk("run " + quoted(bundledSceneFile()) + " --script " +
                                      quoted(bundledScript("bench_patrol.txt")) + " --out " + quoted(run));
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  return run;
}

TEST(Publish, SiteHoldsTheRunAndThePagePlaysItInChromium) {
  if (!fs::exists(bundledSceneFile())) GTEST_SKIP() << "build the bundled_scene target";
  const TempFolder dir;
  const fs::path run = recordRun(dir), site = dir / "site";
  const CommandResult r = runNestwalk("publish " + quoted(run) + " --out " + quoted(site));
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  std::printf("%s", r.out.c_str());
  for (const char* f : {"index.html", "walkthrough.js", "scene.glb", "run.json", "top_down.png", "frame_times.png"})
    EXPECT_TRUE(fs::exists(site / f)) << f;

  // run.json: frames.csv in the local frame of the GLB's map origin; the contacts of results.geojson.
  const Json doc = Json::parse(readAll(site / "run.json"));
  const Json origin = glbJson(readAll(site / "scene.glb"))["asset"]["extras"]["nestwalk"]["map_origin"];
  ASSERT_EQ(origin.size(), 3u);
  const std::vector<std::array<double, 4>> rows = framesOf(run / "frames.csv");
  ASSERT_EQ(doc["frames"]["t"].size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); i += 97) {
    EXPECT_DOUBLE_EQ(doc["frames"]["t"][i].get<double>(), rows[i][0]);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(doc["frames"][kAxes[k]][i].get<double>(),
                  rows[i][1 + k] - origin[k].get<double>(), 1e-9);
  }
  const Json results = Json::parse(readAll(run / "results.geojson"));
  std::vector<Json> contacts;
  for (const Json& f : results["features"])
    if (f["properties"].value("feature", "") == "contact") contacts.push_back(f["properties"]);
  ASSERT_EQ(doc["contacts"].size(), contacts.size());
  ASSERT_FALSE(contacts.empty()) << "the bench patrol is blocked by a station mast";

  // The page in Chromium: at a time between two frames, and after clicking the first contact.
  const std::size_t k = rows.size() / 3;
  const double t = 0.25 * rows[k][0] + 0.75 * rows[k + 1][0];
  const fs::path web = fs::path(build::sourceDir()) / "tools" / "web";
  ASSERT_TRUE(fs::exists(web / "node_modules" / "playwright-core")) << "run tools/setup-deps.sh (npm ci in tools/web)";
  const CommandResult page = runCommand("node " + quoted(web / "drive_page.mjs") + " " + quoted(site) + " --time " +
                                        std::to_string(t) + " --contact 0 --fps-ms 2000");
  ASSERT_EQ(page.exitCode, 0) << page.out << page.err;
  const Json p = Json::parse(page.out);
  EXPECT_TRUE(p["console_errors"].empty()) << p["console_errors"].dump(1);
  std::printf("page: loaded in %.2f s, %.1f frames per second while playing at 1280 x 720 (headless Chromium, %s)\n",
              p["load_seconds"].get<double>(), p["fps"].get<double>(), p["webgl_renderer"].get<std::string>().c_str());
  const double a = (t - rows[k][0]) / (rows[k + 1][0] - rows[k][0]);
  for (int c = 0; c < 3; ++c) {
    const double want = rows[k][1 + c] + a * (rows[k + 1][1 + c] - rows[k][1 + c]) - origin[c].get<double>();
    EXPECT_NEAR(p["at_time"]["walker"][kAxes[c]].get<double>(), want,
                kPositionToleranceM) << "axis " << c;
  }
  const std::string unit = contacts[0]["unit"];
  EXPECT_NE(p["contact"]["info"].get<std::string>().find(unit), std::string::npos) << p["contact"].dump(1);
  const double contactTime = contacts[0]["time_s"];
  std::size_t row = 0;
  while (row + 1 < rows.size() && rows[row + 1][0] <= contactTime) ++row;
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(p["contact"]["pose"][kAxes[c]].get<double>(),
                rows[row][1 + c] - origin[c].get<double>(), kPositionToleranceM) << "axis " << c;
}

TEST(Publish, ANonRunFolderIsRefusedAndAnExistingSiteKept) {
  if (!fs::exists(bundledSceneFile())) GTEST_SKIP() << "build the bundled_scene target";
  const TempFolder dir;
  fs::create_directories(dir / "empty");
  const CommandResult r = runNestwalk("publish " + quoted(dir / "empty") + " --out " + quoted(dir / "site"));
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find((dir / "empty").string() + ": is not a run's folder: summary.json missing"), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "site"));

  fs::create_directories(dir / "site");
  writeText(dir / "site" / "keep.txt", "mine");
  const fs::path run = recordRun(dir);
  const CommandResult again = runNestwalk("publish " + quoted(run) + " --out " + quoted(dir / "site"));
  EXPECT_EQ(again.exitCode, 1);
  EXPECT_NE(again.err.find("exists; pass --overwrite to replace it"), std::string::npos) << again.err;
  EXPECT_EQ(readAll(dir / "site" / "keep.txt"), "mine");
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"empty", "run", "site"}));  // nothing left half-written
}

}  // namespace
}  // namespace nestwalk::test
