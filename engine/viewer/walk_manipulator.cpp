// The walker as a camera manipulator (walk_manipulator.h).
#include "nestwalk/viewer/walk_manipulator.h"

#include "nestwalk/walker/flythrough.h"

#include <osgGA/GUIEventAdapter>

#include <cctype>

namespace nestwalk {

using Key = osgGA::GUIEventAdapter::KeySymbol;

WalkManipulator::WalkManipulator(Walker& walker)
    : walker_(walker), controls_(walker.options().viewer.speed, walker.options().dt) {
  controls_.setView(walker.state().headingDeg, walker.state().pitchDeg);
}

void WalkManipulator::setPlayback(std::vector<FrameRecord> records) {
  playback_ = std::move(records);
  playIndex_ = 0;
  paused_ = false;
}

const FrameRecord* WalkManipulator::currentRecord() const {
  return playback_.empty() ? nullptr : &playback_[std::min(playIndex_, playback_.size() - 1)];
}

ViewPose WalkManipulator::pose() const {
  ViewPose p;
  if (const FrameRecord* r = currentRecord()) {
    p.eye = r->eye;
    p.headingDeg = r->headingDeg;
    p.pitchDeg = r->pitchDeg;
    p.blocked = r->blocked;
    p.blockedBy = r->blockedBy;
    return p;
  }
  const WalkerState& s = walker_.state();
  p.eye = walker_.eye();
  p.headingDeg = s.headingDeg;
  p.pitchDeg = s.pitchDeg;
  p.blocked = s.blocked;
  if (s.blocked)
    p.blockedBy = s.reason == BlockReason::Equipment && s.blockedUnit >= 0 ? walker_.world().name(std::size_t(s.blockedUnit))
                                                                          : blockReasonName(s.reason);
  return p;
}

osg::Matrixd WalkManipulator::getInverseMatrix() const { return walkerViewMatrix(pose()); }
osg::Matrixd WalkManipulator::getMatrix() const { return osg::Matrixd::inverse(getInverseMatrix()); }

bool WalkManipulator::key(int k, bool down) {
  const int lower = (k >= 'A' && k <= 'Z') ? k - 'A' + 'a' : k;
  auto set = [&](WalkKey w) {
    if (down) controls_.press(w);
    else controls_.release(w);
    return true;
  };
  switch (lower) {
    case 'w': case Key::KEY_Up: return set(WalkKey::Forward);
    case 's': case Key::KEY_Down: return set(WalkKey::Back);
    case 'a': return set(WalkKey::Left);
    case 'd': return set(WalkKey::Right);
    case 'q': case Key::KEY_Page_Up: return set(WalkKey::Up);
    case 'e': case Key::KEY_Page_Down: return set(WalkKey::Down);
    case Key::KEY_Shift_L: case Key::KEY_Shift_R: return set(WalkKey::Run);
    default: break;
  }
  if (!down) return false;
  switch (lower) {
    case 'f':
      toggleFlying();
      return true;
    case 'g':
      walker_.setSlide(!walker_.options().slide);
      message_ = walker_.options().slide ? "sliding on" : "sliding off";
      return true;
    case 'm':
      captured_ = !captured_;
      message_ = captured_ ? "mouse captured (M releases it)" : "mouse released";
      return true;
    case 'k':
      if (!playing()) return false;
      paused_ = !paused_;
      return true;
    case 'l':
      if (!playing()) return false;
      paused_ = true;
      ++singleSteps_;
      return true;
    default:
      return onCommandKey_ ? onCommandKey_(lower) : false;
  }
}

void WalkManipulator::toggleFlying() {
  if (playing()) return;
  const WalkerState& s = walker_.state();
  if (!s.flying) {
    walker_.setFlying(true, walker_.options().viewer.flyClearance);
    message_ = "flying";
    return;
  }
  // Landing: the viewer is placed on the ground below, as the scripts' `mode walk` does (a place
  // that fails changes nothing).
  const std::string why = walker_.place(walker_.eye(), false, s.headingDeg, false, s.clearance);
  message_ = why.empty() ? "walking" : "cannot land here: " + why;
}

void WalkManipulator::frame(double time, osgGA::GUIActionAdapter&) {
  const double elapsed = lastTime_ < 0 ? 0.0 : time - lastTime_;
  lastTime_ = time;
  stepsLastFrame_ = 0;
  if (playing()) {
    int n = controls_.stepsFor(elapsed);
    if (paused_) n = singleSteps_;
    singleSteps_ = 0;
    const std::size_t last = playback_.size() - 1;
    const std::size_t next = std::min(last, playIndex_ + std::size_t(n));
    stepsLastFrame_ = int(next - playIndex_);
    playIndex_ = next;
    return;
  }
  const int n = controls_.stepsFor(elapsed);
  for (int i = 0; i < n; ++i) {
    const StepInput in = controls_.input(walker_.state().flying);
    lastReport_ = walker_.step(in);
    ++stepsLastFrame_;
    if (onStep_) onStep_(in, lastReport_);
  }
}

bool WalkManipulator::handle(const osgGA::GUIEventAdapter& ea, osgGA::GUIActionAdapter& aa) {
  using E = osgGA::GUIEventAdapter;
  switch (ea.getEventType()) {
    case E::FRAME:
      frame(ea.getTime(), aa);
      return false;
    case E::KEYDOWN:
      return key(ea.getKey(), true);
    case E::KEYUP:
      return key(ea.getKey(), false);
    case E::PUSH:
      if (ea.getButtonMask() & E::LEFT_MOUSE_BUTTON) {
        dragging_ = true;
        lastX_ = ea.getX();
        lastY_ = ea.getY();
      }
      return false;
    case E::RELEASE:
      dragging_ = false;
      return false;
    case E::DRAG:
    case E::MOVE: {
      if (playing()) return false;
      // Pointer motion up turns the view up, whichever way the window counts y.
      const float up = ea.getMouseYOrientation() == E::Y_INCREASING_UPWARDS ? 1.0f : -1.0f;
      if (captured_) {
        const float cx = 0.5f * (ea.getXmin() + ea.getXmax()), cy = 0.5f * (ea.getYmin() + ea.getYmax());
        const float dx = ea.getX() - cx, dy = up * (ea.getY() - cy);
        if (dx != 0 || dy != 0) {
          controls_.look(dx, dy);
          walker_.setView(controls_.headingDeg(), controls_.pitchDeg());
          aa.requestWarpPointer(cx, cy);
        }
        return true;
      }
      if (!dragging_ || ea.getEventType() != E::DRAG) return false;
      controls_.look(ea.getX() - lastX_, up * (ea.getY() - lastY_));
      walker_.setView(controls_.headingDeg(), controls_.pitchDeg());
      lastX_ = ea.getX();
      lastY_ = ea.getY();
      return true;
    }
    default:
      return false;
  }
}

}  // namespace nestwalk
