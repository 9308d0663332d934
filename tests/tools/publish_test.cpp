// `nestwalk publish`: a bench-patrol run on the bundled scene published as a site, whose run.json
// holds frames.csv's path in the local frame (map minus the GLB's map origin) and results.geojson's
// contacts; then the page in Debian's Chromium (tools/web/drive_page.mjs, playwright-core,
// software WebGL): it loads with no console error, the time slider at t puts the walker where
// frames.csv has it at t, and clicking the first contact moves the camera to the contact's frame and
// shows its unit's name; at the poses the offscreen renderer drew, the page's picture has the same
// sky line. Opened as a file, the page loads where the browser allows it and says what to do where
// it does not. A folder that is not a run's is refused naming what is missing; an existing site is
// kept unless --overwrite.
#include "tests/common/build_paths.h"
#include "tests/common/gltf_validator.h"
#include "tests/common/png_readback.h"
#include "tests/common/run_command.h"
#include "tests/common/temp_folder.h"
#include "tests/common/test_data.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <sstream>

namespace nestwalk::test {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

constexpr double kPositionToleranceM = 0.01;  // the page's float32 scene against frames.csv's 4 decimals
constexpr const char* kAxes[] = {"x", "y", "z"};
// The page's picture against the offscreen renderer's frame of the same pose: the sky line (per
// column, the first row from the top that is not sky) within kSkyLinePx on at least
// kSkyLineColumns of the columns, and sky / not sky disagreeing on at most kSkyMaskPixels of the
// pixels. The two differ in the terrain's level of detail (the page draws one static cut, the
// renderer refines by view), in the sky's gradient and in the equipment's shading; outlines and the
// terrain's silhouette against the sky are what must agree.
constexpr int kSkyLinePx = 3;
constexpr double kSkyLineColumns = 0.99, kSkyMaskPixels = 0.005;

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
      EXPECT_NEAR(doc["frames"][kAxes[k]][i].get<double>(), rows[i][1 + k] - origin[k].get<double>(), 1e-9);
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
    EXPECT_NEAR(p["at_time"]["walker"][kAxes[c]].get<double>(), want, kPositionToleranceM) << "axis " << c;
  }
  const std::string unit = contacts[0]["unit"];
  EXPECT_NE(p["contact"]["info"].get<std::string>().find(unit), std::string::npos) << p["contact"].dump(1);
  const double contactTime = contacts[0]["time_s"];
  std::size_t row = 0;
  while (row + 1 < rows.size() && rows[row + 1][0] <= contactTime) ++row;
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(p["contact"]["pose"][kAxes[c]].get<double>(), rows[row][1 + c] - origin[c].get<double>(),
                kPositionToleranceM)
        << "axis " << c;
}

/// Sky: bluish and bright (the renderer's gradient from the horizon colour to the zenith's, the
/// page's horizon colour), which neither the terrain's ochres and greys nor the equipment are.
bool isSky(const testing::Colour& c) { return c.b - c.r >= 26 && c.b >= 140; }

struct PictureAgreement {
  double skyLineColumns = 0, skyMaskDisagreement = 0;
};

PictureAgreement compareSky(const osg::Image& a, const osg::Image& b) {
  PictureAgreement out;
  if (a.s() != b.s() || a.t() != b.t()) return out;
  const int w = a.s(), h = a.t();
  std::size_t within = 0, disagree = 0;
  for (int x = 0; x < w; ++x) {
    int lineA = -1, lineB = -1;  // rows from the top
    for (int row = 0; row < h; ++row) {
      const bool sa = isSky(testing::pixelAt(a, x, h - 1 - row)), sb = isSky(testing::pixelAt(b, x, h - 1 - row));
      if (!sa && lineA < 0) lineA = row;
      if (!sb && lineB < 0) lineB = row;
      if (sa != sb) ++disagree;
    }
    if (lineA < 0) lineA = h;
    if (lineB < 0) lineB = h;
    if (std::abs(lineA - lineB) <= kSkyLinePx) ++within;
  }
  out.skyLineColumns = double(within) / w;
  out.skyMaskDisagreement = double(disagree) / (double(w) * h);
  return out;
}

TEST(Publish, ThePageDrawsTheRenderersViewAtRecordedPoses) {
  if (!fs::exists(bundledSceneFile())) GTEST_SKIP() << "build the bundled_scene target";
  const TempFolder dir;
  const fs::path run = dir / "run", site = dir / "site";
  // Four frames rendered offscreen at 1280 x 720 (steps 1, 901, 1801, 2701).
  const CommandResult r =
      runNestwalk("run " + quoted(bundledSceneFile()) + " --script " + quoted(bundledScript("bench_patrol.txt")) +
                  " --out " + quoted(run) + " --render --every 900 --size 1280x720");
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  ASSERT_EQ(runNestwalk("publish " + quoted(run) + " --out " + quoted(site)).exitCode, 0);
  std::ifstream csv(run / "frames.csv");
  std::string line;
  std::getline(csv, line);
  std::vector<std::string> header;
  for (std::stringstream s(line); std::getline(s, line, ',');) header.push_back(line);
  const auto column = [&](const char* name) { return std::find(header.begin(), header.end(), name) - header.begin(); };
  const long frameCol = column("frame"), timeCol = column("time"), renderedCol = column("rendered");
  std::string shots;
  std::vector<std::pair<fs::path, fs::path>> pairs;  // (renderer's frame, page's picture)
  while (std::getline(csv, line)) {
    std::vector<std::string> f;
    for (std::stringstream s(line); std::getline(s, line, ',');) f.push_back(line);
    if (f[std::size_t(renderedCol)] != "1") continue;
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06ld.png", std::stol(f[std::size_t(frameCol)]));
    pairs.emplace_back(run / "frames" / name, dir / ("page_" + std::string(name)));
    shots += " --shot " + f[std::size_t(timeCol)] + " " + quoted(pairs.back().second);
  }
  ASSERT_EQ(pairs.size(), 4u);
  const fs::path web = fs::path(build::sourceDir()) / "tools" / "web";
  const CommandResult page = runCommand("node " + quoted(web / "drive_page.mjs") + " " + quoted(site) + shots);
  ASSERT_EQ(page.exitCode, 0) << page.out << page.err;
  for (const auto& [renderer, picture] : pairs) {
    SCOPED_TRACE(renderer.filename().string());
    const osg::ref_ptr<osg::Image> a = testing::readPng(renderer.string()), b = testing::readPng(picture.string());
    ASSERT_TRUE(a && b);
    ASSERT_EQ(a->s(), b->s());
    ASSERT_EQ(a->t(), b->t());
    const PictureAgreement agree = compareSky(*a, *b);
    std::printf("%s: sky line within %d px on %.1f %% of columns, sky mask differs on %.2f %% of pixels\n",
                renderer.filename().c_str(), kSkyLinePx, 100 * agree.skyLineColumns, 100 * agree.skyMaskDisagreement);
    EXPECT_GE(agree.skyLineColumns, kSkyLineColumns);
    EXPECT_LE(agree.skyMaskDisagreement, kSkyMaskPixels);
  }
}

TEST(Publish, OpenedAsAFileThePageLoadsWhereAllowedAndSaysWhatToDoWhereNot) {
  if (!fs::exists(bundledSceneFile())) GTEST_SKIP() << "build the bundled_scene target";
  const TempFolder dir;
  const fs::path run = recordRun(dir), site = dir / "site";
  ASSERT_EQ(runNestwalk("publish " + quoted(run) + " --out " + quoted(site)).exitCode, 0);
  const std::string drive = "node " + quoted(fs::path(build::sourceDir()) / "tools" / "web" / "drive_page.mjs") + " " +
                            quoted(site) + " --file";
  const CommandResult refused = runCommand(drive);  // Chromium's default: no reading beside a file
  ASSERT_EQ(refused.exitCode, 0) << refused.err;
  const Json a = Json::parse(refused.out);
  EXPECT_FALSE(a["file_loaded"].get<bool>());
  EXPECT_NE(a["problem"].get<std::string>().find("python3 -m http.server"), std::string::npos) << a.dump(1);
  const CommandResult allowed =
      runCommand("NESTWALK_CHROMIUM_GL='--use-angle=gl-egl --allow-file-access-from-files' " + drive);
  ASSERT_EQ(allowed.exitCode, 0) << allowed.err;
  const Json b = Json::parse(allowed.out);
  EXPECT_TRUE(b["file_loaded"].get<bool>()) << b.dump(1);
  EXPECT_TRUE(b["console_errors"].empty()) << b.dump(1);
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
