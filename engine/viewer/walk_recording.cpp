// A walk by hand as a script and a camera path (walk_recording.h).
#include "nestwalk/viewer/walk_recording.h"

#include "nestwalk/core/number_text.h"
#include "nestwalk/walker/script.h"

#include <cmath>

namespace nestwalk {

struct WalkRecording::WriterState {
  bool flying = false;
  double headingDeg = 0, pitchDeg = 0, speed = 0;
};

WalkRecording::WalkRecording(const Walker& walker, const std::string& sceneFile, const std::string& methodName)
    : dt_(walker.options().dt) {
  const WalkerState& s = walker.state();
  startFlying_ = s.flying;
  startClearance_ = s.clearance;
  startHeading_ = s.headingDeg;
  startPitch_ = s.pitchDeg;
  startSpeed_ = walker.options().viewer.speed;
  header_ = "# A walk recorded by `nestwalk view` on " + sceneFile + " (contact method " + methodName + ", " +
            exactText(1.0 / dt_) + " steps per second).\n# Replay: nestwalk run " + sceneFile +
            " --script THIS_FILE --headless --out DIR" + (std::abs(1.0 / dt_ - 60.0) > 1e-9 ? " --hz " + exactText(1.0 / dt_) : "") +
            "\n";
  const Eigen::Vector3d eye = walker.eye();
  start_ = s.flying ? "start " + exactText(eye.x()) + " " + exactText(eye.y()) + " " + exactText(eye.z())
                    : "start " + exactText(eye.x()) + " " + exactText(eye.y());
  start_ += " heading " + exactText(s.headingDeg) + "\n";
  camera_.push_back({s.time, eye, s.headingDeg, s.pitchDeg});
}

void WalkRecording::add(const StepInput& input, const Walker& walker) {
  const WalkerState& s = walker.state();
  ++steps_;
  camera_.push_back({s.time, walker.eye(), s.headingDeg, s.pitchDeg});
  if (walker.options().slide && s.blocked) slid_ = true;
  const bool blockedMove = s.blocked && input.move.squaredNorm() > 0;
  if (!runs_.empty()) {
    Run& open = runs_.back();
    const bool same = open.move == input.move && open.headingDeg == input.headingDeg &&
                      open.pitchDeg == input.pitchDeg && open.flying == s.flying;
    if (same && open.blocked && blockedMove) {
      ++open.pressedSteps;  // pressing on against the obstacle
      return;
    }
    if (same && !open.blocked) {
      ++open.steps;
      if (blockedMove) markBlocked(open, walker);
      return;
    }
  }
  Run r;
  r.move = input.move;
  r.headingDeg = input.headingDeg;
  r.pitchDeg = input.pitchDeg;
  r.flying = s.flying;
  r.steps = 1;
  runs_.push_back(r);
  if (blockedMove) markBlocked(runs_.back(), walker);
}

void WalkRecording::markBlocked(Run& run, const Walker& walker) {
  const WalkerState& s = walker.state();
  run.blocked = true;
  Contact c;
  c.step = steps_;
  c.feet = s.feet;
  if (s.reason == BlockReason::Equipment && s.blockedUnit >= 0) {
    c.blocker = walker.world().name(std::size_t(s.blockedUnit));
    run.expectLine = "expect blocked by " + c.blocker + "\n";
  } else {
    c.blocker = blockReasonName(s.reason);
    run.expectLine = "expect blocked\n";
  }
  contacts_.push_back(c);
}

void WalkRecording::writeRun(const Run& run, std::string& out, WriterState& state) const {
  if (run.flying != state.flying) {
    out += run.flying ? "mode fly\n" : "mode walk\n";
    state.flying = run.flying;
  }
  if (run.headingDeg != state.headingDeg) {
    out += "heading " + exactText(run.headingDeg) + "\n";
    state.headingDeg = run.headingDeg;
  }
  if (run.pitchDeg != state.pitchDeg) {
    out += "look " + exactText(run.pitchDeg) + "\n";
    state.pitchDeg = run.pitchDeg;
  }
  const double seconds = double(run.steps) * dt_;
  if (run.move.squaredNorm() == 0) {
    out += "wait " + exactText(seconds) + "\n";
    return;
  }
  // The player steps speed x dt towards the target: the speed that makes its step the hand's.
  const bool climbs = run.flying && run.move.z() != 0;
  const double perStep = climbs ? run.move.norm() : run.move.head<2>().norm();
  const double speed = perStep / dt_;
  if (speed != state.speed) {
    out += "speed " + exactText(speed) + "\n";
    state.speed = speed;
  }
  const Eigen::Vector3d total = run.move * double(run.steps);
  out += "move " + exactText(total.x()) + " " + exactText(total.y()) + (climbs ? " " + exactText(total.z()) : "") + "\n";
  if (!run.blocked) return;
  out += run.expectLine;
  // The player gives up a blocked motion after kBlockedTimeout without progress; the hand may have
  // pressed on for longer: the rest stands as a wait (the position does not change either way).
  const double pressed = double(run.pressedSteps) * dt_;
  if (pressed > kBlockedTimeout + dt_) out += "wait " + exactText(pressed - kBlockedTimeout) + "\n";
}

std::string WalkRecording::scriptText() const {
  std::string out = header_;
  if (slid_)
    out += "# Recorded with sliding on: replay with `nestwalk run --slide`; after a slide the player re-aims at\n"
           "# each move's target where the hand kept its direction, so positions may differ from the walk's.\n";
  WriterState state;
  state.flying = startFlying_;
  state.headingDeg = startHeading_;
  state.pitchDeg = startPitch_;
  state.speed = startSpeed_;
  if (startFlying_) out += "mode fly\nclearance " + exactText(startClearance_) + "\n";
  out += start_;
  if (startPitch_ != 0) out += "look " + exactText(startPitch_) + "\n";
  for (const Run& r : runs_) writeRun(r, out, state);
  return out;
}

}  // namespace nestwalk
