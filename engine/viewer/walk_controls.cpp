// Keys and mouse made into walker steps (walk_controls.h).
#include "nestwalk/viewer/walk_controls.h"

#include "nestwalk/core/angles.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace nestwalk {
namespace {

/// Steps: a rest of real time this close to a whole step (in steps) counts as one; sums of frame
/// times in double drift by far less.
constexpr double kStepSlack = 1e-9;

}  // namespace

WalkControls::WalkControls(double speed, double dt) : speed_(speed), dt_(dt) {
  if (!(speed > 0) || !(dt > 0)) throw std::invalid_argument("WalkControls: speed and dt must be positive");
}

void WalkControls::setView(double headingDeg, double pitchDeg) {
  heading_ = wrapDegrees360(headingDeg);
  pitch_ = std::clamp(pitchDeg, -kMaxPitchDeg, kMaxPitchDeg);
}

void WalkControls::look(double dxPixels, double dyPixels) {
  setView(heading_ + dxPixels * kDegreesPerPixel, pitch_ + dyPixels * kDegreesPerPixel);
}

double WalkControls::speed() const {
  const bool moving = held(WalkKey::Forward) != held(WalkKey::Back) || held(WalkKey::Left) != held(WalkKey::Right) ||
                      held(WalkKey::Up) != held(WalkKey::Down);
  if (!moving) return 0;
  return held(WalkKey::Run) ? speed_ * kRunFactor : speed_;
}

StepInput WalkControls::input(bool flying) const {
  StepInput in;
  in.headingDeg = heading_;
  in.pitchDeg = pitch_;
  const double forward = double(held(WalkKey::Forward)) - double(held(WalkKey::Back));
  const double right = double(held(WalkKey::Right)) - double(held(WalkKey::Left));
  const double up = flying ? double(held(WalkKey::Up)) - double(held(WalkKey::Down)) : 0.0;
  const auto [s, c] = sinCosDegrees(heading_);
  // Forward along the heading (clockwise from north: +y at 0, +x at 90), right 90 degrees clockwise.
  const Eigen::Vector3d ahead(s, c, 0), toRight(c, -s, 0);
  Eigen::Vector3d direction = forward * ahead + right * toRight + Eigen::Vector3d(0, 0, up);
  const double n = direction.norm();
  if (n == 0) return in;
  in.move = direction * (speed() * dt_ / n);
  return in;
}

int WalkControls::stepsFor(double seconds) {
  if (seconds > 0) pending_ += seconds;
  // Whole steps, counting a rest within kStepSlack of a step as one (sums of frame times round).
  const double whole = std::max(0.0, std::floor(pending_ / dt_ + kStepSlack));
  if (whole >= kMaxStepsPerFrame) {
    pending_ = 0;  // the surplus is dropped: the walk slows down rather than bursting
    return kMaxStepsPerFrame;
  }
  pending_ = std::max(0.0, pending_ - whole * dt_);
  return int(whole);
}

}  // namespace nestwalk
