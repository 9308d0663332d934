// Walking by hand: which keys are held and where the mouse has turned the view, made into the
// walker's fixed steps. No window here: the manipulator (walk_manipulator.h) feeds it events, tests
// feed it directly.
//
// Motion: W/S forward and back along the heading, A/D sideways (A to the left), Q/E up and down
// (flying only), Shift runs (kRunFactor times the speed). Several keys add up and the sum is scaled
// to the speed, so a diagonal is no faster than a straight walk. Each step moves speed x dt.
// Mouse look: kDegreesPerPixel per pixel; right turns the heading clockwise, up raises the pitch
// (clamped to +-kMaxPitchDeg).
// Time: stepsFor(seconds) turns real time into whole steps of dt, keeping the rest for the next
// frame, at most kMaxStepsPerFrame a frame (a slow frame then runs slower than real time instead of
// jumping: every step is still one swept test, so nothing is tunnelled through either way).
// Units: metres, seconds, degrees (heading clockwise from north, pitch up positive).
// Thread safety: a value type, used by one thread.
#pragma once

#include "nestwalk/walker/walker.h"

#include <array>
#include <cstdint>

namespace nestwalk {

/// Speed multiplier while Shift is held.
inline constexpr double kRunFactor = 3.0;
/// Mouse look: degrees of heading or pitch per pixel of pointer motion (about 0.2, as desktop
/// first-person viewers default to).
inline constexpr double kDegreesPerPixel = 0.2;
/// The view's pitch limit, degrees: short of straight up or down, where the heading is undefined.
inline constexpr double kMaxPitchDeg = 85.0;
/// At most this many steps per drawn frame (a quarter second at 60 Hz): a frame that took longer
/// slows the walk down instead of catching up in one burst.
inline constexpr int kMaxStepsPerFrame = 15;

enum class WalkKey : std::uint8_t { Forward, Back, Left, Right, Up, Down, Run };
inline constexpr std::size_t kWalkKeys = 7;

class WalkControls {
 public:
  // speed: m/s walking (the scene's viewer speed); dt: the walker's step, seconds.
  WalkControls(double speed, double dt);

  void press(WalkKey k) { held_[std::size_t(k)] = true; }
  void release(WalkKey k) { held_[std::size_t(k)] = false; }
  void releaseAll() { held_.fill(false); }
  bool held(WalkKey k) const { return held_[std::size_t(k)]; }

  // The view: set (from the walker's state) and turned by pointer motion in pixels (x right,
  // y up).
  void setView(double headingDeg, double pitchDeg);
  void look(double dxPixels, double dyPixels);
  double headingDeg() const { return heading_; }
  double pitchDeg() const { return pitch_; }

  // The step input for one step: the held keys' motion at the current speed, the current view.
  // Walking ignores Q/E (the ground decides the height).
  StepInput input(bool flying) const;
  // The speed the held keys ask for (0 when none moves), m/s.
  double speed() const;

  // Whole steps for `seconds` of real time since the last call (see above).
  int stepsFor(double seconds);
  double dt() const { return dt_; }

 private:
  double speed_, dt_;
  std::array<bool, kWalkKeys> held_{};
  double heading_ = 0, pitch_ = 0;
  double pending_ = 0;  // real seconds not yet walked
};

}  // namespace nestwalk
