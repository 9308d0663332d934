// `nestwalk run --render` on the bundled scene: the walker's view rendered offscreen (no display)
// into numbered PNG frames and an MP4 video (ffprobe counts its frames), render times in the same
// CSV and summary, rendered columns deterministic between runs, and bad options refused with a
// message.
#include "tests/common/build_paths.h"
#include "tests/common/run_command.h"

#include <nlohmann/json.hpp>
#include <osg/Image>
#include <osgDB/ReadFile>

#include <algorithm>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>

namespace nestwalk::test {
namespace {

namespace fs = std::filesystem;

const fs::path kScene = fs::path(nestwalk::test::build::bundledSceneDir()) / "scene.json";
const fs::path kFlight = fs::path(nestwalk::test::build::bundledSceneDir()) / "scripts" / "low_flight.txt";

std::string commandOutput(const std::string& command) {
  std::string out;
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  if (!pipe) return out;
  char buf[256];
  while (std::fgets(buf, sizeof buf, pipe.get())) out += buf;
  return out;
}

/// Rows of the CSV as fields, split at every comma (the low flight's blocked_by names hold none).
std::vector<std::vector<std::string>> csvRows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::stringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream ls(line);
    std::string field;
    while (std::getline(ls, field, ',')) f.push_back(field);
    if (!line.empty() && line.back() == ',') f.push_back("");
    rows.push_back(f);
  }
  return rows;
}

class RenderRun : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(kScene)) GTEST_SKIP() << kScene << " is absent: build the bundled_scene target";
  }
};

TEST_F(RenderRun, WritesFramesVideoAndRenderTimes) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const std::string base = "run " + quoted(kScene) + " --script " + quoted(kFlight) +
                           " --headless --quiet --render --size 320x180 --every 60 --out ";
  const auto a = runNestwalk(base + quoted(dir / "a"));
  ASSERT_EQ(a.exitCode, 0) << a.out << a.err;
  EXPECT_NE(a.out.find("rendered "), std::string::npos) << a.out;

  const auto summary = nlohmann::json::parse(readText(dir / "a" / "summary.json"));
  const long frames = summary["frames"].get<long>();
  const long expectedRendered = (frames + 59) / 60;  // steps 1, 61, 121, ...
  ASSERT_TRUE(summary.contains("render"));
  EXPECT_EQ(summary["render"]["frames"].get<long>(), expectedRendered);
  EXPECT_EQ(summary["render"]["size"][0], 320);
  EXPECT_GT(summary["render"]["ms"]["total"]["p50"].get<double>(), 0.0);
  EXPECT_LE(summary["render"]["max_terrain_error_px"].get<double>(), 1.0 + 1e-9);

  // One PNG per rendered step, named by the step, of the asked size.
  std::size_t pngs = 0;
  for (const auto& e : fs::directory_iterator(dir / "a" / "frames")) {
    ++pngs;
    EXPECT_EQ(e.path().extension(), ".png");
  }
  EXPECT_EQ(long(pngs), expectedRendered);
  for (const char* name : {"frame_000001.png", "frame_000061.png"}) {
    osg::ref_ptr<osg::Image> image = osgDB::readImageFile((dir / "a" / "frames" / name).string());
    ASSERT_TRUE(image.valid()) << name;
    EXPECT_EQ(image->s(), 320);
    EXPECT_EQ(image->t(), 180);
  }

  // The video holds the same frames.
  ASSERT_TRUE(fs::exists(dir / "a" / "flythrough.mp4"));
  const std::string probe = commandOutput(
      "ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames,width,height "
      "-of csv=p=0 " + quoted(dir / "a" / "flythrough.mp4"));
  EXPECT_EQ(probe, "320,180," + std::to_string(expectedRendered) + "\n");

  // The CSV marks the rendered steps and times them.
  const auto rows = csvRows(readText(dir / "a" / "frames.csv"));
  ASSERT_EQ(long(rows.size()), frames + 1);
  const auto& header = rows[0];
  auto column = [&](const std::string& name) {
    return std::size_t(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const std::size_t rendered = column("rendered"), total = column("us_render_total"), tris = column("triangles");
  ASSERT_LT(total, header.size());
  long marked = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const bool expected = (i - 1) % 60 == 0;
    ASSERT_EQ(rows[i][rendered], expected ? "1" : "0") << "row " << i;
    if (expected) {
      ++marked;
      EXPECT_GT(std::stod(rows[i][total]), 0.0);
      EXPECT_GT(std::stol(rows[i][tris]), 0);
    }
  }
  EXPECT_EQ(marked, expectedRendered);

  // Same inputs, same rendered columns (everything before the timings).
  const auto b = runNestwalk(base + quoted(dir / "b") + " --no-video --no-frames");
  ASSERT_EQ(b.exitCode, 0) << b.out << b.err;
  const auto rowsB = csvRows(readText(dir / "b" / "frames.csv"));
  const std::size_t firstTiming = column("us_ground");
  ASSERT_EQ(rowsB.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t k = 0; k < firstTiming; ++k) ASSERT_EQ(rows[i][k], rowsB[i][k]) << "row " << i << " " << header[k];
  EXPECT_FALSE(fs::exists(dir / "b" / "frames"));
  EXPECT_FALSE(fs::exists(dir / "b" / "flythrough.mp4"));

  // Existing frames and video are kept unless --overwrite.
  const auto again = runNestwalk(base + quoted(dir / "a"));
  EXPECT_EQ(again.exitCode, 1);
  EXPECT_NE(again.err.find("--overwrite"), std::string::npos) << again.err;
}

/// Mean absolute difference per channel between two PNGs of one size (-1 when they differ in size).
double meanDifference(const fs::path& a, const fs::path& b) {
  osg::ref_ptr<osg::Image> x = osgDB::readImageFile(a.string()), y = osgDB::readImageFile(b.string());
  if (!x || !y || x->s() != y->s() || x->t() != y->t()) return -1;
  double sum = 0;
  for (int r = 0; r < x->t(); ++r)
    for (int c = 0; c < x->s() * 3; ++c) sum += std::abs(int(x->data(0, r)[c]) - int(y->data(0, r)[c]));
  return sum / (double(x->s()) * x->t() * 3);
}

TEST_F(RenderRun, FallsBackToAnXPbufferUnderXvfb) {
  // The fallback route where EGL cannot be had: an X pbuffer on the display xvfb-run provides.
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "xvfb-run is not installed (tools/setup-deps.sh installs it)";
  const TempFolder folder;
  const fs::path dir = folder.path();
  const std::string args = "run " + quoted(kScene) + " --script " + quoted(kFlight) +
                           " --headless --quiet --render --size 320x180 --every 300 --no-video --out ";
  const auto egl = runNestwalk(args + quoted(dir / "egl"));
  ASSERT_EQ(egl.exitCode, 0) << egl.out << egl.err;
  const auto x11 = runCommand("NESTWALK_OFFSCREEN=x11 xvfb-run -a -s '-screen 0 640x480x24' " +
                              std::string(nestwalk::test::build::nestwalkProgram()) + " " + args + quoted(dir / "x11"));
  ASSERT_EQ(x11.exitCode, 0) << x11.out << x11.err;
  EXPECT_EQ(nlohmann::json::parse(readText(dir / "egl" / "summary.json"))["render"]["route"], "egl-surfaceless");
  EXPECT_EQ(nlohmann::json::parse(readText(dir / "x11" / "summary.json"))["render"]["route"], "x11-pbuffer");
  // The same frames, up to the rasteriser's rounding.
  for (const char* frame : {"frame_000001.png", "frame_000301.png"}) {
    const double diff = meanDifference(dir / "egl" / "frames" / frame, dir / "x11" / "frames" / frame);
    EXPECT_GE(diff, 0.0) << frame;
    EXPECT_LT(diff, 1.0) << frame;
  }
  // Asking for a route that cannot be had names the variable.
  const auto none = runCommand("env -u DISPLAY NESTWALK_OFFSCREEN=x11 " + std::string(nestwalk::test::build::nestwalkProgram()) + " " + args +
                               quoted(dir / "none"));
  EXPECT_NE(none.exitCode, 0);
  EXPECT_NE(none.err.find("DISPLAY"), std::string::npos) << none.err;
}

TEST_F(RenderRun, BadRenderOptionsAreRefused) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const std::string base = "run " + quoted(kScene) + " --script " + quoted(kFlight) + " --headless --quiet --render ";
  const auto size = runNestwalk(base + "--size 12x9 --out " + quoted(dir / "o"));
  EXPECT_NE(size.exitCode, 0);
  EXPECT_NE(size.err.find("--size"), std::string::npos) << size.err;
  const auto every = runNestwalk(base + "--every 0 --out " + quoted(dir / "o"));
  EXPECT_NE(every.exitCode, 0);
  EXPECT_NE(every.err.find("--every"), std::string::npos) << every.err;
  EXPECT_FALSE(fs::exists(dir / "o" / "frames"));
}

}  // namespace
}  // namespace nestwalk::test
