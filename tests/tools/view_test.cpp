// `nestwalk view` end to end, in a real window on a real X server (Xvfb, started here) driven by
// xdotool: hold Shift+W towards the bench-2 mast, record the walk, take a screenshot, quit. The
// log's block and final pose are checked against the engine (the gap to the mast by bisection on
// the static test), the screenshot against the offscreen renderer's frame of the same pose, and the
// recording by `nestwalk run` (same contact, final position within 1 mm). Also: no display, and a
// recording folder that exists.
#include "nestwalk/core/angles.h"
#include "nestwalk/render/view_renderer.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/walker/script_file.h"
#include "nestwalk/walker/walker.h"

#include "tests/common/build_paths.h"
#include "tests/common/run_command.h"
#include "tests/common/temp_folder.h"
#include "tests/common/test_data.h"

#include <osgDB/ReadFile>

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;
using test::quoted;

bool onPath(const std::string& program) {
  return std::system(("command -v " + program + " >/dev/null 2>&1").c_str()) == 0;
}

// An Xvfb server on a display number it picks itself (-displayfd), stopped on destruction.
class XServer {
 public:
  XServer() {
    int fds[2];
    if (pipe(fds) != 0) return;
    pid_ = fork();
    if (pid_ == 0) {
      close(fds[0]);
      const std::string fd = std::to_string(fds[1]);
      execlp("Xvfb", "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "1600x900x24", "-nolisten", "tcp",
             static_cast<char*>(nullptr));
      _exit(127);
    }
    close(fds[1]);
    std::string number;
    char c = 0;
    while (read(fds[0], &c, 1) == 1 && c != '\n') number += c;
    close(fds[0]);
    if (!number.empty()) display_ = ":" + number;
  }
  ~XServer() {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      waitpid(pid_, nullptr, 0);
    }
  }
  const std::string& display() const { return display_; }

 private:
  pid_t pid_ = -1;
  std::string display_;
};

struct Pose {
  Eigen::Vector3d eye = Eigen::Vector3d::Zero();
  double heading = 0, pitch = 0;
};

// "eye X Y Z heading H pitch P" in a log line.
std::optional<Pose> poseIn(const std::string& line) {
  static const std::regex re(R"(eye (\S+) (\S+) (\S+) heading (\S+) pitch (\S+))");
  std::smatch m;
  if (!std::regex_search(line, m, re)) return std::nullopt;
  Pose p;
  p.eye = {std::stod(m[1]), std::stod(m[2]), std::stod(m[3])};
  p.heading = std::stod(m[4]);
  p.pitch = std::stod(m[5]);
  return p;
}

std::string lineWith(const std::string& log, const std::string& start) {
  std::istringstream in(log);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(start, 0) == 0) return line;
  return {};
}

class ViewWindow : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(test::bundledSceneFile())) GTEST_SKIP() << test::bundledSceneFile() << " is absent";
    if (!onPath("Xvfb") || !onPath("xdotool"))
      GTEST_SKIP() << "Xvfb or xdotool is not installed (tools/setup-deps.sh installs both)";
  }
};

TEST_F(ViewWindow, HeldKeysWalkIntoTheMastAndTheScreenshotAndRecordingAgree) {
  const test::TempFolder folder;
  XServer x;
  ASSERT_FALSE(x.display().empty()) << "Xvfb did not start";
  const Script patrol = readScript(test::bundledScript("bench_patrol.txt").string());
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  double heading = 0;
  std::string blocker;
  for (const ScriptCommand& c : patrol.commands) {
    if (c.op == ScriptOp::Start) start = c.v, heading = c.heading;
    if (c.op == ScriptOp::ExpectBlocked && blocker.empty()) blocker = c.name;
  }
  const fs::path log = folder / "view.log";
  const std::string env = "DISPLAY=" + x.display() + " ";
  const std::string view = env + quoted(std::string(nestwalk::test::build::nestwalkProgram())) + " view " + quoted(test::bundledSceneFile()) +
                           " --start " + std::to_string(start.x()) + " " + std::to_string(start.y()) + " " +
                           std::to_string(heading) + " --record " + quoted(folder / "rec") + " --screenshots " +
                           quoted(folder.path()) + " --terrain-loading complete --seconds 90 > " + quoted(log) + " 2>&1 &";
  ASSERT_EQ(std::system(view.c_str()), 0);
  // Find the window, give it the keyboard, record, run at the mast (about 40 m: 10 s at 4.2 m/s),
  // stop recording, screenshot, quit.
  const std::string xdo = env + "timeout 60 xdotool ";
  ASSERT_EQ(std::system((xdo + "search --sync --name 'nestwalk view' windowfocus --sync %1").c_str()), 0) << test::readText(log);
  ASSERT_EQ(std::system((xdo + "key r keydown shift+w sleep 16 keyup shift+w sleep 0.5 key r sleep 0.5 key p sleep 1.5 "
                               "key Escape").c_str()),
            0);
  std::string text;
  for (int i = 0; i < 100; ++i) {  // up to 10 s for the window to close and the log to end
    text = test::readText(log);
    if (text.find("view: frames ") != std::string::npos) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_NE(text.find("view: frames "), std::string::npos) << text;

  // Blocked by the mast, and stopped half a millimetre short of it.
  const std::string blocked = lineWith(text, "view: blocked by ");
  EXPECT_NE(blocked.find("view: blocked by " + blocker), std::string::npos) << text;
  const std::optional<Pose> end = poseIn(lineWith(text, "view: stopped "));
  ASSERT_TRUE(end.has_value()) << text;
  const Scene scene = loadScene(test::bundledSceneFile().string());
  const CollisionWorld world = CollisionWorld::fromScene(scene, scene.spec.method);
  WalkerOptions options;
  options.viewer = scene.spec.viewer;
  Walker walker(*scene.terrain, world, scene.origin, options);
  ASSERT_EQ(walker.place(end->eye, false, end->heading, false, 0), "");
  EXPECT_NEAR(walker.eye().z(), end->eye.z(), 1e-9);  // walking: on the ground, as the window said
  const auto [sn, cs] = sinCosDegrees(end->heading);
  const Eigen::Vector3d dir(sn, cs, 0);
  auto overlaps = [&](double t) {
    CollisionCounters c;
    return world.overlapping(walker.bodyVolume(walker.state().feet + t * dir, end->heading), c) >= 0;
  };
  ASSERT_TRUE(overlaps(0.01));
  double lo = 0, hi = 0.01;
  for (int i = 0; i < 60; ++i) (overlaps(0.5 * (lo + hi)) ? hi : lo) = 0.5 * (lo + hi);
  EXPECT_NEAR(hi, kStopDistance, 0.1e-3) << "gap " << hi * 1e3 << " mm";
  std::printf("stopped %.4f mm short of %s\n", hi * 1e3, blocked.c_str());

  // The screenshot against the offscreen renderer's frame of the same pose.
  const std::string shotLine = lineWith(text, "view: screenshot ");
  const std::optional<Pose> shot = poseIn(shotLine);
  ASSERT_TRUE(shot.has_value()) << text;
  const fs::path shotFile = folder / "screenshot_001.png";
  osg::ref_ptr<osg::Image> window = osgDB::readImageFile(shotFile.string());
  ASSERT_TRUE(window) << shotFile;
  ASSERT_EQ(window->s(), 1280);
  ASSERT_EQ(window->t(), 720);
  RenderOptions ro;
  ro.terrainLoading = TerrainLoading::Complete;  // as the window drew it
  ViewRenderer renderer(scene, ro);
  const std::size_t by = shotLine.find(" blocked by ");
  renderer.render({shot->eye, shot->heading, shot->pitch, by != std::string::npos,
                   by != std::string::npos ? shotLine.substr(by + 12) : std::string()});
  const osg::Image& offscreen = renderer.image();
  std::size_t close = 0, channels = 0;
  for (int y = 0; y < 720; ++y)
    for (int x = 0; x < 1280; ++x)
      for (int k = 0; k < 3; ++k) {
        const int a = window->data(x, y)[k], b = offscreen.data(x, y)[k];
        close += std::abs(a - b) <= 2;
        ++channels;
      }
  std::printf("screenshot: %.4f %% of channels within 2 levels of the offscreen frame\n",
              100.0 * double(close) / double(channels));
  EXPECT_GE(double(close) / double(channels), 0.99) << close << " of " << channels << " channels within 2 levels";

  // The recording, played by `nestwalk run`: met expectations (the block), the same end.
  const fs::path recorded = folder / "rec" / "walk_001.txt";
  ASSERT_TRUE(fs::exists(recorded)) << text;
  EXPECT_TRUE(fs::exists(folder / "rec" / "walk_001.path"));
  const std::string script = test::readText(recorded);
  EXPECT_NE(script.find("expect blocked by " + blocker), std::string::npos) << script;
  const auto run = test::runNestwalk("run " + quoted(test::bundledSceneFile()) + " --script " + quoted(recorded) +
                                     " --quiet --out " + quoted(folder / "replay"));
  EXPECT_EQ(run.exitCode, 0) << run.out << run.err;
  std::ifstream csv(folder / "replay" / "frames.csv");
  std::string last, line;
  while (std::getline(csv, line))
    if (!line.empty()) last = line;
  std::vector<double> f;
  std::stringstream ss(last);
  for (std::string cell; std::getline(ss, cell, ',');) f.push_back(std::strtod(cell.c_str(), nullptr));
  ASSERT_GE(f.size(), 5u) << last;
  const double apart = (Eigen::Vector3d(f[2], f[3], f[4]) - end->eye).norm();
  std::printf("replayed recording ends %.3g m from the window's end\n", apart);
  EXPECT_LE(apart, 1e-3) << last;
}

TEST_F(ViewWindow, AScriptPlaysInRealTimeAndPausesAndSteps) {
  const test::TempFolder folder;
  XServer x;
  ASSERT_FALSE(x.display().empty()) << "Xvfb did not start";
  const fs::path script = test::bundledScript("bench_patrol.txt");
  const fs::path log = folder / "view.log";
  const std::string env = "DISPLAY=" + x.display() + " ";
  const std::string view = env + quoted(std::string(nestwalk::test::build::nestwalkProgram())) + " view " + quoted(test::bundledSceneFile()) +
                           " --script " + quoted(script) + " --seconds 60 > " + quoted(log) + " 2>&1; echo $? >> " +
                           quoted(log);
  const std::string background = "( " + view + " ) &";
  ASSERT_EQ(std::system(background.c_str()), 0);
  const std::string xdo = env + "timeout 60 xdotool ";
  ASSERT_EQ(std::system((xdo + "search --sync --name 'nestwalk view' windowfocus --sync %1").c_str()), 0) << test::readText(log);
  // Two seconds of play, pause, three single steps, quit.
  ASSERT_EQ(std::system((xdo + "sleep 2 key k sleep 0.5 key l sleep 0.3 key l sleep 0.3 key l sleep 0.5 key Escape").c_str()), 0);
  std::string text;
  for (int i = 0; i < 100; ++i) {
    text = test::readText(log);
    if (text.find("view: frames ") != std::string::npos && text.back() == '\n' && text.find("\n0\n") != std::string::npos) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_NE(text.find("view: frames "), std::string::npos) << text;
  EXPECT_NE(text.find("\n0\n"), std::string::npos) << "exit status: " << text;
  const std::string stopped = lineWith(text, "view: stopped ");
  static const std::regex frameRe(R"(at frame (\d+) of (\d+))");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(stopped, m, frameRe)) << text;
  const int frame = std::stoi(m[1]), frames = std::stoi(m[2]);
  // Paused after about 2 s of real time (120 steps at 60 Hz), then three steps: short of the end.
  EXPECT_GT(frame, 3);
  EXPECT_LT(frame, frames);
  // The pose shown is the one `nestwalk run` computes for that frame.
  const auto run = test::runNestwalk("run " + quoted(test::bundledSceneFile()) + " --script " + quoted(script) +
                                     " --quiet --out " + quoted(folder / "run"));
  ASSERT_EQ(run.exitCode, 0) << run.out << run.err;
  std::ifstream csv(folder / "run" / "frames.csv");
  std::string line;
  std::getline(csv, line);  // header
  std::optional<Eigen::Vector3d> eye;
  while (std::getline(csv, line)) {
    std::vector<double> f;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) f.push_back(std::strtod(cell.c_str(), nullptr));
    if (f.size() >= 5 && int(f[0]) == frame) eye = Eigen::Vector3d(f[2], f[3], f[4]);
  }
  ASSERT_TRUE(eye.has_value()) << "frame " << frame;
  const std::optional<Pose> shown = poseIn(stopped);
  ASSERT_TRUE(shown.has_value());
  EXPECT_LE((shown->eye - *eye).norm(), 1e-3);
}

TEST_F(ViewWindow, NoDisplaySaysToUseXvfbOrRunRender) {
  const auto r = test::runCommand("env -u DISPLAY " + quoted(std::string(nestwalk::test::build::nestwalkProgram())) + " view " +
                                  quoted(test::bundledSceneFile()));
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find("xvfb-run"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("run --render"), std::string::npos) << r.err;
}

TEST_F(ViewWindow, AnExistingRecordingFolderIsNotOverwritten) {
  const test::TempFolder folder;
  test::writeText(folder / "walk_001.txt", "mine\n");
  const auto r = test::runCommand("DISPLAY=:0 " + quoted(std::string(nestwalk::test::build::nestwalkProgram())) + " view " +
                                  quoted(test::bundledSceneFile()) + " --record " + quoted(folder.path()));
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find(folder.path().string() + ": the recording folder exists; pass --overwrite"), std::string::npos)
      << r.err;
  EXPECT_EQ(test::readText(folder / "walk_001.txt"), "mine\n");
}

}  // namespace
}  // namespace nestwalk
