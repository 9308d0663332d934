// Plays a flythrough script (script.h) on a walker: turns each command into fixed steps, checks
// the expectations where they stand in the script, and hands every step to a callback (records,
// rendering). Deterministic: the same script, scene and options give the same steps.
//
// Motion: `goto` turns the view toward the target at kTurnRate, then walks (or flies) straight at
// the current speed, re-aiming every step; `move D` goes to the point D ahead of the heading at
// its start; `move DX DY [DZ]` to the offset point, keeping the heading. A timed `goto ... by T`
// takes S = round((start time + T - now) / dt) steps (at least one, at whatever speed that needs)
// of equal length to its target, so that it arrives within half a step of T when nothing blocks it;
// it does not stop to turn (the view turns at kTurnRate while it walks, and not at all toward a
// target closer than kTimedViewDistance); a target already reached stands for the S steps. A
// motion ends at its target (within kArrivalTolerance) or after kBlockedTimeout seconds without
// progress. `turn`,
// `heading` and `look` run at kTurnRate / kPitchRate in whole steps; the rest (less than one
// step's turn) turns the view at once, the body following at the next step. `wait` stands for
// ceil(T / dt) steps.
//
// Ownership: the player keeps references to `script` and `walker`; both must outlive it.
// Thread safety: one thread (run() steps the walker); onStep runs on that thread.
#pragma once

#include "nestwalk/walker/frame_record.h"
#include "nestwalk/walker/script.h"
#include "nestwalk/walker/walker.h"

#include <functional>
#include <limits>
#include <vector>

namespace nestwalk {

inline constexpr double kTurnRate = 90.0;          // degrees per second
inline constexpr double kPitchRate = 60.0;         // degrees per second
inline constexpr double kArrivalTolerance = 1e-6;  // metres
inline constexpr double kProgressEpsilon = 1e-6;   // metres per step that count as progress
inline constexpr double kLastStepSlack = 0.01;     // a rest up to 1 % over a step is taken in one
inline constexpr double kTimedViewDistance = 0.5;  // metres: a timed goto this short keeps the view

class ScriptPlayer {
 public:
  using StepCallback = std::function<void(const Walker&, const StepReport&)>;

  ScriptPlayer(const Script& script, Walker& walker);

  // Runs the whole script; calls onStep after every step. Throws InputError (file:line) when a
  // `start` (or a switch to walking) puts the viewer where it cannot be.
  void run(const StepCallback& onStep);

  const std::vector<ExpectationResult>& expectations() const { return results_; }
  bool allMet() const;
  std::uint64_t steps() const { return steps_; }

 private:
  void stepOnce(const Eigen::Vector3d& move, double headingDeg, double pitchDeg, const StepCallback& onStep);
  void turnTo(double headingDeg, const StepCallback& onStep);
  void pitchTo(double pitchDeg, const StepCallback& onStep);
  // arriveAt: the walker time (WalkerState::time) at which a timed goto arrives; NaN: untimed.
  void goTo(const Eigen::Vector3d& target, bool hasZ, bool aim, const StepCallback& onStep,
            double arriveAt = std::numeric_limits<double>::quiet_NaN());
  void expect(const ScriptCommand& c);
  std::string where(const ScriptCommand& c) const;

  const Script& script_;
  Walker& walker_;
  double speed_;
  std::vector<ExpectationResult> results_;
  std::uint64_t steps_ = 0;
  double startTime_ = 0;  // the walker's time at `start` (timed gotos count from it)
};

}  // namespace nestwalk
