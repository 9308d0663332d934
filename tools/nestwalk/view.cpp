// nestwalk view SCENE [--script FILE] [--size WxH] [--fullscreen] [--method M] ...: the scene in a
// window (osgViewer on X, GLX; works under `xvfb-run`), walked by hand with the same walker and the
// same view graph as `nestwalk run` (engine/viewer: the manipulator, the HUD, the recording).
//
// Keys: H shows them all (engine/viewer/hud.cpp, viewerHelpText). Here: V toggles the nested
// volumes, H the help, P writes a screenshot (OSG's ScreenCaptureHandler, the frame without the
// HUD: the view as `run --render` draws it), R starts and stops a recording (a script and an
// AnimationPath in --record DIR: walk_001.txt, walk_001.path, ...). With --script the window plays
// the script in real time (K pauses, L steps) and lists its expectations as they come.
//
// Standard output gets one line per event, for people and tests alike: the window, each block
// ("blocked by NAME at E N H"), each screenshot with its pose, each recording, and at the end the
// final pose and the frame rate ("frames N in T s: F fps, frame ms p50 A p95 B").
// Exit: 0; 1 for bad input and for no display (the message says to use xvfb-run or run --render);
// 3 when a played script's expectation failed.
#include "nestwalk/core/angles.h"
#include "nestwalk/core/input_error.h"
#include "nestwalk/core/output_file.h"
#include "nestwalk/core/statistics.h"
#include "nestwalk/render/view_graph.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/viewer/hud.h"
#include "nestwalk/viewer/walk_manipulator.h"
#include "nestwalk/viewer/walk_recording.h"
#include "nestwalk/walker/flythrough.h"
#include "nestwalk/walker/script_file.h"
#include "tools/nestwalk/commands.h"
#include "tools/nestwalk/walk_options.h"

#include <osg/Timer>
#include <osgDB/WriteFile>
#include <osgViewer/Viewer>
#include <osgViewer/ViewerEventHandlers>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>

namespace nestwalk::tools {
namespace {

struct ViewArgs {
  std::string scene, script, record = "recordings", screenshots = ".";
  std::string size = "1280x720";
  std::vector<double> start;  // X Y [HEADING]
  bool fullscreen = false, overwrite = false, fly = false, volumes = false;
  double hz = 60.0, seconds = 0;
  int frames = 0;
  MethodOverrides method;
  TerrainArgs terrain;
};

/// Seconds between two updates of the HUD's text.
constexpr double kHudSeconds = 0.25;

void say(const std::string& line) {
  std::printf("view: %s\n", line.c_str());
  std::fflush(stdout);
}

std::string poseText(const ViewPose& p) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "eye %.17g %.17g %.17g heading %.17g pitch %.17g", p.eye.x(), p.eye.y(), p.eye.z(),
                p.headingDeg, p.pitchDeg);
  return buf;
}

// Writes each capture to the next free screenshot_NNN.png in the folder, through a temporary file.
struct ScreenshotWriter : osgViewer::ScreenCaptureHandler::CaptureOperation {
  std::string folder;
  int next = 1;
  std::string lastFile;
  bool overwrite = false;
  void operator()(const osg::Image& image, const unsigned int) override {
    namespace fs = std::filesystem;
    std::string target;
    do {
      char name[64];
      std::snprintf(name, sizeof name, "screenshot_%03d.png", next++);
      target = (fs::path(folder) / name).string();
    } while (!overwrite && fs::exists(target));
    OutputFile out(target, ".png");
    if (!osgDB::writeImageFile(image, out.tempPath())) {
      say(target + ": could not write the screenshot");
      return;
    }
    out.commit();
    lastFile = target;
  }
};

void runView(const ViewArgs& args) {
  namespace fs = std::filesystem;
  const auto [width, height] = parseFrameSize(args.size);
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display)
    throw InputError("view: no display (DISPLAY is not set): run it under X, or `xvfb-run -a nestwalk view ...`; "
                     "`nestwalk run --render` renders a script's frames without any display");
  if (!args.record.empty() && fs::exists(args.record) && !args.overwrite && args.record != "recordings")
    throw InputError(args.record + ": the recording folder exists; pass --overwrite to write into it");

  const Scene scene = loadScene(args.scene);
  const MethodSpec method = applyMethodOverrides(args.method, scene.spec.method);
  CollisionWorld world = CollisionWorld::fromScene(scene, method);
  WalkerOptions options;
  options.viewer = scene.spec.viewer;
  options.dt = 1.0 / args.hz;

  // A played script: computed first on its own walker (the same steps `nestwalk run` takes), then
  // shown in real time.
  FlythroughResult played;
  if (!args.script.empty()) played = runFlythrough(scene, world, readScript(args.script), options);

  Walker walker(*scene.terrain, world, scene.origin, options);
  if (args.script.empty()) {
    // --start, or the terrain's centre; where that has no ground or stands in equipment, the
    // nearest free ground on rings around it (every 5 m, 16 directions).
    const terrain::Heightfield& hf = *scene.terrain;
    // Sample (0, 0) is the north-west corner; rows run south.
    const Eigen::Vector3d centre(hf.origin().x() + 0.5 * (hf.cols() - 1) * hf.dx(),
                                 hf.origin().y() - 0.5 * (hf.rows() - 1) * hf.dy(), 0);
    const Eigen::Vector3d at = args.start.size() >= 2 ? Eigen::Vector3d(args.start[0], args.start[1], 0) : centre;
    const double heading = args.start.size() >= 3 ? args.start[2] : 0.0;
    std::string why = walker.place(at, false, heading, args.fly, options.viewer.flyClearance);
    if (!why.empty() && args.start.size() >= 2)
      throw InputError("--start " + std::to_string(at.x()) + " " + std::to_string(at.y()) + ": " + why);
    const double reach = 0.5 * std::max(hf.cols() * hf.dx(), hf.rows() * hf.dy());
    for (double r = 5.0; !why.empty() && r <= reach; r += 5.0)
      for (int k = 0; k < 16 && !why.empty(); ++k) {
        const auto [sn, cs] = sinCosDegrees(22.5 * k);
        why = walker.place(at + r * Eigen::Vector3d(sn, cs, 0), false, heading, args.fly, options.viewer.flyClearance);
      }
    if (!why.empty()) throw InputError(args.scene + ": no free ground to start on near the terrain's centre; give --start X Y");
  }

  RenderOptions ro;
  ro.width = width;
  ro.height = height;
  ro.volumes = true;  // drawn, then shown or hidden with V
  applyTerrainArgs(args.terrain, ro);
  ViewGraph graph(scene, ro);
  if (graph.parts().volumes) graph.parts().volumes->setNodeMask(args.volumes ? ~0u : 0u);
  Hud hud(graph.overlayLayer(), width, height);

  osg::ref_ptr<osgViewer::Viewer> viewer = new osgViewer::Viewer;
  viewer->setThreadingModel(osgViewer::Viewer::SingleThreaded);
  if (args.fullscreen) viewer->setUpViewOnSingleScreen(0);
  else viewer->setUpViewInWindow(40, 40, width, height);
  graph.attachTo(*viewer);
  viewer->getCamera()->setViewport(0, 0, width, height);
  viewer->setSceneData(graph.root());
  osg::ref_ptr<WalkManipulator> manipulator = new WalkManipulator(walker);
  if (!args.script.empty()) manipulator->setPlayback(played.records);
  viewer->setCameraManipulator(manipulator.get(), false);

  osg::ref_ptr<ScreenshotWriter> shots = new ScreenshotWriter;
  shots->folder = args.screenshots;
  shots->overwrite = args.overwrite;
  osg::ref_ptr<osgViewer::ScreenCaptureHandler> capture = new osgViewer::ScreenCaptureHandler(shots.get(), 1);
  capture->setKeyEventTakeScreenShot(-1);  // P, below: the HUD is hidden first
  capture->setKeyEventToggleContinuousCapture(-1);
  viewer->addEventHandler(capture.get());

  std::unique_ptr<WalkRecording> recording;
  int recordings = 0;
  bool recordFolderMade = false;
  bool screenshotArmed = false;
  std::string status;
  ViewPose shotPose;
  auto stopRecording = [&]() {
    char name[32];
    std::snprintf(name, sizeof name, "walk_%03d", ++recordings);
    const fs::path script = fs::path(args.record) / (std::string(name) + ".txt");
    const fs::path path = fs::path(args.record) / (std::string(name) + ".path");
    writeFileAtomically(script.string(), recording->scriptText());
    writeAnimationPath(path.string(), recording->camera());
    status = "recorded " + script.string();
    say("recording written " + script.string() + " and " + path.string() + " (" + std::to_string(recording->steps()) +
        " steps, " + std::to_string(recording->contacts().size()) + " contacts)");
    recording.reset();
  };
  manipulator->onStep([&](const StepInput& in, const StepReport&) {
    if (recording) recording->add(in, walker);
  });
  manipulator->onCommandKey([&](int key) {
    switch (key) {
      case 'v':
        if (graph.parts().volumes) graph.parts().volumes->setNodeMask(graph.parts().volumes->getNodeMask() ? 0u : ~0u);
        return true;
      case 'h':
        hud.setHelpVisible(!hud.helpVisible());
        return true;
      case 'p':
        hud.setVisible(false);
        capture->captureNextFrame(*viewer);
        screenshotArmed = true;
        return true;
      case 'r':
        if (manipulator->playing()) return true;
        if (recording) {
          stopRecording();
          return true;
        }
        if (!recordFolderMade) {
          if (fs::exists(args.record) && !args.overwrite) {
            status = args.record + " exists: restart with --overwrite or --record NEW_FOLDER";
            say("recording not started: " + status);
            return true;
          }
          std::error_code ec;
          fs::create_directories(args.record, ec);
          if (ec) {
            status = args.record + ": cannot create the folder: " + ec.message();
            say("recording not started: " + status);
            return true;
          }
          recordFolderMade = true;
        }
        recording = std::make_unique<WalkRecording>(walker, args.scene, volumeMethodName(method.volumes));
        status = "RECORDING";
        say("recording started");
        return true;
      default:
        return false;  // unknown keys are ignored
    }
  });

  viewer->realize();
  if (!viewer->isRealized())
    throw InputError(std::string("view: cannot open a window on display ") + display +
                     " (no GLX?); `nestwalk run --render` renders without a display");
  // The window's title names the program and the scene (xdotool finds it by name).
  osgViewer::Viewer::Windows windows;
  viewer->getWindows(windows);
  for (osgViewer::GraphicsWindow* w : windows) w->setWindowName("nestwalk view: " + args.scene);
  say("window " + std::to_string(width) + "x" + std::to_string(height) + " on " + display + ", scene " + args.scene +
      ", method " + volumeMethodName(method.volumes) + (args.script.empty() ? "" : ", playing " + args.script));

  const std::string crs = terrain::crsName(scene.terrain->crsWkt());
  std::vector<double> frameMs;
  osg::Timer_t started = osg::Timer::instance()->tick(), last = started;
  bool wasBlocked = false;
  osg::Timer_t lastHud = 0;
  std::string lastStatus = "\x01";  // never a status: the first frame updates the HUD
  std::size_t expectationsShown = 0;
  while (!viewer->done()) {
    // One frame: events first (keys, mouse, and the manipulator's steps for the time gone by),
    // then the graph follows the pose they left, so the overlay, the culling and the camera
    // agree; the HUD shows the previous frame's times.
    viewer->advance();
    viewer->eventTraversal();
    if (viewer->done()) break;
    HudState h;
    const ViewPose pose = manipulator->pose();
    if (screenshotArmed) shotPose = pose;
    h.frameMs = frameMs.empty() ? 0 : frameMs.back();
    h.fps = h.frameMs > 0 ? 1000.0 / h.frameMs : 0;
    const StepReport& r = manipulator->lastReport();
    h.stepMicros = r.micros[StepPart::Total];
    h.stepsThisFrame = manipulator->stepsLastFrame();
    h.stageTests = r.counters.stageTests;
    h.primitiveTests = r.counters.primitiveTests;
    h.eye = pose.eye;
    h.crs = crs;
    h.headingDeg = pose.headingDeg;
    h.pitchDeg = pose.pitchDeg;
    const std::optional<double> ground = scene.terrain->groundHeight(pose.eye.x(), pose.eye.y());
    h.hasGround = ground.has_value();
    h.ground = ground.value_or(0);
    h.flying = walker.state().flying;
    h.sliding = walker.options().slide;
    h.method = volumeMethodName(method.volumes);
    const PagedTerrainStats& terrain = graph.pagedTerrain().lastStats();
    h.terrainChunks = terrain.chunksDrawn;
    h.terrainLoading = terrain.chunksWanted;
    h.terrainErrorPx = terrain.maxErrorPx;
    h.terrainMiB = double(terrain.residentBytes) / (1 << 20);
    h.terrainBudgetMiB = double(graph.pagedTerrain().budgetBytes()) / (1 << 20);
    h.status = manipulator->paused() ? "PAUSED (K resumes, L steps)" : status;
    if (!manipulator->message().empty() && status.empty()) h.status = manipulator->message();
    if (const FrameRecord* rec = manipulator->currentRecord()) {
      for (const ExpectationResult& e : played.expectations)
        if (e.frame <= rec->frame) {
          h.expectations.push_back("line " + std::to_string(e.line) + ": " + e.text + (e.met ? ": met" : ": FAILED (" + e.detail + ")"));
        }
      for (; expectationsShown < h.expectations.size(); ++expectationsShown) say(h.expectations[expectationsShown]);
    }
    // The text is laid out again on every change: a few times a second is as often as a person
    // reads it (measured: 0.3 ms a frame saved at 1280 x 720 on llvmpipe).
    const osg::Timer_t nowTick = osg::Timer::instance()->tick();
    if (osg::Timer::instance()->delta_s(lastHud, nowTick) >= kHudSeconds || h.status != lastStatus) {
      hud.update(h);
      lastHud = nowTick;
      lastStatus = h.status;
    }
    if (pose.blocked && !wasBlocked) {
      char at[128];
      std::snprintf(at, sizeof at, " at %.3f %.3f %.3f", pose.eye.x(), pose.eye.y(), pose.eye.z());
      say("blocked by " + pose.blockedBy + at);
    }
    wasBlocked = pose.blocked;
    if (const osg::Viewport* vp = viewer->getCamera()->getViewport()) graph.setViewportSize(int(vp->width()), int(vp->height()));
    graph.update(*viewer->getCamera(), pose);
    viewer->updateTraversal();
    viewer->renderingTraversals();
    const osg::Timer_t now = osg::Timer::instance()->tick();
    frameMs.push_back(osg::Timer::instance()->delta_m(last, now));
    last = now;
    if (screenshotArmed) {
      screenshotArmed = false;
      hud.setVisible(true);
      say("screenshot " + shots->lastFile + " " + poseText(shotPose) + (shotPose.blocked ? " blocked by " + shotPose.blockedBy : ""));
    }
    if (args.frames > 0 && int(frameMs.size()) >= args.frames) break;
    if (args.seconds > 0 && osg::Timer::instance()->delta_s(started, now) >= args.seconds) break;
  }
  if (recording) stopRecording();
  const double seconds = osg::Timer::instance()->delta_s(started, last);
  // The first frame compiles the scene's GL objects: left out of the rate.
  std::vector<double> steady(frameMs.size() > 1 ? frameMs.begin() + 1 : frameMs.begin(), frameMs.end());
  double steadyMs = 0;
  for (double m : steady) steadyMs += m;
  char line[256];
  std::snprintf(line, sizeof line, "frames %zu in %.2f s: %.1f fps, frame ms p50 %.1f p95 %.1f (first frame %.0f ms)",
                frameMs.size(), seconds, steady.empty() ? 0.0 : 1000.0 * double(steady.size()) / steadyMs,
                percentile(steady, 50), percentile(steady, 95), frameMs.empty() ? 0.0 : frameMs.front());
  const ViewPose end = manipulator->pose();
  const FrameRecord* shown = manipulator->currentRecord();
  say("stopped " + poseText(end) +
      (shown ? " at frame " + std::to_string(shown->frame) + " of " + std::to_string(played.records.size())
             : " after " + std::to_string(walker.state().frame) + " steps") +
      (end.blocked ? ", blocked by " + end.blockedBy : ""));
  say(line);
  if (!args.script.empty() && !played.expectationsMet()) throw CLI::RuntimeError(3);
}

}  // namespace

void registerView(CLI::App& app) {
  auto args = std::make_shared<ViewArgs>();
  CLI::App* cmd = app.add_subcommand("view", "Walk a scene by hand in a window (X; xvfb-run works), with the same walker as run");
  cmd->add_option("SCENE", args->scene, "Scene file (JSON, see README)")->required();
  cmd->add_option("--script", args->script, "Play this flythrough script in the window (K pauses, L steps)")->check(CLI::ExistingFile);
  cmd->add_option("--size", args->size, "Window size, WIDTHxHEIGHT (default 1280x720)");
  cmd->add_flag("--fullscreen", args->fullscreen, "Fill the screen instead of a window");
  cmd->add_option("--start", args->start, "Start at map X Y [HEADING] (default: the terrain's centre, heading north)")
      ->expected(2, 3);
  cmd->add_flag("--fly", args->fly, "Start flying");
  cmd->add_flag("--show-volumes", args->volumes, "Start with the nested volumes shown (V toggles)");
  cmd->add_option("--record", args->record, "Folder for recordings (R): walk_NNN.txt and walk_NNN.path (default ./recordings)");
  cmd->add_option("--screenshots", args->screenshots, "Folder for screenshots (P): screenshot_NNN.png (default .)");
  cmd->add_flag("--overwrite", args->overwrite, "Write into an existing recording folder, replacing its files");
  cmd->add_option("--hz", args->hz, "Walker steps per second (fixed time step 1/hz; default 60)")->check(CLI::Range(1.0, 10000.0));
  cmd->add_option("--method", args->method.volumes, "Contact test: nested (default), aabb, obb, nested+mesh, kdop18, auto (overrides the scene)");
  addTerrainOptions(*cmd, args->terrain, "background");
  cmd->add_option("--frames", args->frames, "Quit after this many frames (0: on Esc)");
  cmd->add_option("--seconds", args->seconds, "Quit after this many seconds (0: on Esc)");
  cmd->callback([args]() { runView(*args); });
}

}  // namespace nestwalk::tools
