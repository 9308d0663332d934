// The walk window (walk_window.h): the osgViewer window, its screenshot handler and key commands
// around a walk session, and the frame loop.
#include "nestwalk/session/walk_window.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/core/output_file.h"
#include "nestwalk/viewer/hud.h"
#include "nestwalk/viewer/walk_manipulator.h"

#include <osg/Timer>
#include <osgDB/WriteFile>
#include <osgViewer/Viewer>
#include <osgViewer/ViewerEventHandlers>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>

namespace nestwalk {
namespace {

/// Seconds between two layouts of the HUD's text: a few times a second is as often as a person
/// reads it (measured: 0.3 ms a frame saved at 1280 x 720 on llvmpipe).
constexpr double kHudSeconds = 0.25;

// Writes each capture to the next free screenshot_NNN.png in the folder, through a temporary file.
struct ScreenshotWriter : osgViewer::ScreenCaptureHandler::CaptureOperation {
  std::string folder;
  int next = 1;
  std::string lastFile;
  bool overwrite = false;
  std::function<void(const std::string&)> say;
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
      if (say) say(target + ": could not write the screenshot");
      return;
    }
    out.commit();
    lastFile = target;
  }
};

}  // namespace

bool runWalkWindow(const WalkWindowOptions& o) {
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display)
    throw InputError("view: no display (DISPLAY is not set): run it under X, or `xvfb-run -a nestwalk view ...`; "
                     "`nestwalk run --render` renders a script's frames without any display");
  auto say = [&o](const std::string& line) {
    if (o.session.say) o.session.say(line);
  };
  WalkSession session(o.session);
  const int width = o.view.width, height = o.view.height;

  RenderOptions ro = o.view;
  ro.volumes = true;  // drawn, then shown or hidden with V
  ViewGraph graph(session.scene(), ro);
  osg::Node* volumes = graph.parts().volumes.get();
  if (volumes) volumes->setNodeMask(o.showVolumes ? ~0u : 0u);
  Hud hud(graph.overlayLayer(), width, height);

  osg::ref_ptr<osgViewer::Viewer> viewer = new osgViewer::Viewer;
  viewer->setThreadingModel(osgViewer::Viewer::SingleThreaded);
  if (o.fullscreen) viewer->setUpViewOnSingleScreen(0);
  else viewer->setUpViewInWindow(40, 40, width, height);
  graph.attachTo(*viewer);
  viewer->getCamera()->setViewport(0, 0, width, height);
  viewer->setSceneData(graph.root());
  osg::ref_ptr<WalkManipulator> manipulator = new WalkManipulator(session.walker());
  if (session.playsScript()) manipulator->setPlayback(session.played().records);
  viewer->setCameraManipulator(manipulator.get(), false);

  osg::ref_ptr<ScreenshotWriter> shots = new ScreenshotWriter;
  shots->folder = o.screenshots;
  shots->overwrite = o.session.overwrite;
  shots->say = say;
  osg::ref_ptr<osgViewer::ScreenCaptureHandler> capture = new osgViewer::ScreenCaptureHandler(shots.get(), 1);
  capture->setKeyEventTakeScreenShot(-1);  // P, below: the HUD is hidden first
  capture->setKeyEventToggleContinuousCapture(-1);
  viewer->addEventHandler(capture.get());

  bool screenshotArmed = false;
  ViewPose shotPose;
  manipulator->onStep([&](const StepInput& in, const StepReport& report) { session.recordStep(in, report); });
  manipulator->onCommandKey([&](int key) {
    switch (key) {
      case 'v':
        if (volumes) volumes->setNodeMask(volumes->getNodeMask() ? 0u : ~0u);
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
        session.toggleRecording();
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
  for (osgViewer::GraphicsWindow* w : windows) w->setWindowName("nestwalk view: " + o.session.scene);
  say("window " + std::to_string(width) + "x" + std::to_string(height) + " on " + display + ", scene " +
      o.session.scene + ", method " + volumeMethodName(session.method().volumes) +
      (session.playsScript() ? ", playing " + o.session.script : ""));

  osg::Timer* timer = osg::Timer::instance();
  const osg::Timer_t started = timer->tick();
  osg::Timer_t last = started, lastHud = 0;
  std::string lastStatus = "\x01";  // never a status: the first frame updates the HUD
  while (!viewer->done()) {
    // One frame: events first (keys, mouse, and the manipulator's steps for the time gone by),
    // then the graph follows the pose they left, so the overlay, the culling and the camera
    // agree; the HUD shows the previous frame's times.
    viewer->advance();
    viewer->eventTraversal();
    if (viewer->done()) break;
    WalkFrame f;
    f.pose = manipulator->pose();
    f.shown = manipulator->currentRecord();
    f.lastStep = &manipulator->lastReport();
    f.stepsThisFrame = manipulator->stepsLastFrame();
    f.paused = manipulator->paused();
    f.walkerMessage = manipulator->message();
    f.terrain = graph.pagedTerrain().lastStats();
    f.terrainBudgetBytes = graph.pagedTerrain().budgetBytes();
    if (screenshotArmed) shotPose = f.pose;
    const HudState h = session.frame(f);
    const osg::Timer_t hudTick = timer->tick();
    if (timer->delta_s(lastHud, hudTick) >= kHudSeconds || h.status != lastStatus) {
      hud.update(h);
      lastHud = hudTick;
      lastStatus = h.status;
    }
    if (const osg::Viewport* vp = viewer->getCamera()->getViewport()) graph.setViewportSize(int(vp->width()), int(vp->height()));
    graph.update(*viewer->getCamera(), f.pose);
    viewer->updateTraversal();
    viewer->renderingTraversals();
    const osg::Timer_t now = timer->tick();
    session.frameDrawn(timer->delta_m(last, now));
    last = now;
    if (screenshotArmed) {
      screenshotArmed = false;
      hud.setVisible(true);
      say("screenshot " + shots->lastFile + " " + poseText(shotPose) +
          (shotPose.blocked ? " blocked by " + shotPose.blockedBy : ""));
    }
    if (o.frames > 0 && int(session.framesDrawn()) >= o.frames) break;
    if (o.seconds > 0 && timer->delta_s(started, now) >= o.seconds) break;
  }
  session.finish(manipulator->pose(), manipulator->currentRecord(), timer->delta_s(started, last));
  return session.expectationsMet();
}

}  // namespace nestwalk
