// The walker as OpenSceneGraph's camera manipulator: a person walks the scene with the same walker
// (walker.h) a script drives, at the same fixed step, so what happens by hand happens the same way
// in a script (walk_recording.h writes one).
//
// Keys (letters in either case): W/S or the Up/Down arrows forward and back, A/D sideways, Shift
// runs, F switches walking and flying, Q/E or PageUp/PageDown up and down in flight, G toggles
// sliding along contact faces. Mouse look: drag with the left button, or toggle a captured pointer
// with M (every pointer motion turns the view and the pointer goes back to the window's centre).
// Other keys go to the commandKey callback (the window's own: help, screenshot, recording, ...);
// Esc is left to osgViewer (it ends the viewer's loop).
//
// Time: each FRAME event takes as many walker steps as the real time since the last one asks
// (WalkControls::stepsFor, capped at kMaxStepsPerFrame), with the keys as they are at that frame.
// Events carry their own times (osgGA::GUIEventAdapter::getTime), so tests inject key and frame
// events with chosen times and get the steps a script would.
//
// Playback (setPlayback): instead of walking, the manipulator shows a precomputed run's records
// (a script played on the same walker beforehand, flythrough.h), one record per step in real
// time; K pauses and resumes, L steps one record while paused.
//
// The camera: the walker's eye, heading and pitch (map frame), as ViewGraph::viewMatrix.
// Ownership: keeps a reference to the walker, which must outlive it.
// Thread safety: OSG calls handle() and the matrix getters on the viewer's thread; use it there.
#pragma once

#include "nestwalk/render/view_graph.h"
#include "nestwalk/viewer/walk_controls.h"
#include "nestwalk/walker/frame_record.h"
#include "nestwalk/walker/walker.h"

#include <osgGA/CameraManipulator>

#include <functional>
#include <string>
#include <vector>

namespace nestwalk {

class WalkManipulator : public osgGA::CameraManipulator {
 public:
  using StepCallback = std::function<void(const StepInput&, const StepReport&)>;
  using CommandKeyCallback = std::function<bool(int key)>;  // true: handled

  explicit WalkManipulator(Walker& walker);

  const char* className() const override { return "nestwalk::WalkManipulator"; }
  void setByMatrix(const osg::Matrixd&) override {}         // the walker decides where the eye is
  void setByInverseMatrix(const osg::Matrixd&) override {}
  osg::Matrixd getMatrix() const override;
  osg::Matrixd getInverseMatrix() const override;
  void home(double) override {}
  void home(const osgGA::GUIEventAdapter&, osgGA::GUIActionAdapter&) override {}
  bool handle(const osgGA::GUIEventAdapter& ea, osgGA::GUIActionAdapter& aa) override;

  void onStep(StepCallback cb) { onStep_ = std::move(cb); }
  void onCommandKey(CommandKeyCallback cb) { onCommandKey_ = std::move(cb); }

  // Plays precomputed records instead of walking (see above).
  void setPlayback(std::vector<FrameRecord> records);
  bool playing() const { return !playback_.empty(); }
  bool paused() const { return paused_; }
  std::size_t playbackIndex() const { return playIndex_; }
  const FrameRecord* currentRecord() const;

  // The pose the camera shows (map frame), with the blocked state for the overlay.
  ViewPose pose() const;
  const WalkControls& controls() const { return controls_; }
  const Walker& walker() const { return walker_; }
  bool mouseCaptured() const { return captured_; }
  // Steps taken at the last FRAME event, and the last step's report.
  int stepsLastFrame() const { return stepsLastFrame_; }
  const StepReport& lastReport() const { return lastReport_; }
  // A message for the HUD about the last mode change ("flying", "cannot land here: ...").
  const std::string& message() const { return message_; }

 private:
  bool key(int key, bool down);
  void frame(double time, osgGA::GUIActionAdapter& aa);
  void toggleFlying();

  Walker& walker_;
  WalkControls controls_;
  StepCallback onStep_;
  CommandKeyCallback onCommandKey_;
  std::vector<FrameRecord> playback_;
  std::size_t playIndex_ = 0;
  bool paused_ = false;
  int singleSteps_ = 0;
  double lastTime_ = -1;
  bool dragging_ = false, captured_ = false;
  float lastX_ = 0, lastY_ = 0;
  int stepsLastFrame_ = 0;
  StepReport lastReport_;
  std::string message_;
};

}  // namespace nestwalk
