#include "nestwalk/walker/script_player.h"

#include "nestwalk/core/angles.h"
#include "nestwalk/core/input_error.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace nestwalk {
namespace {

/// Metres: closer than this horizontally, the direction to a target is no longer re-aimed every
/// step (it would swing wildly over the last millimetres); the motion still ends at the target.
constexpr double kReaimDistance = 0.01;
/// Seconds: sums of dt round; a wait that reached kBlockedTimeout up to this much counts as reached.
constexpr double kTimeSlack = 1e-9;
/// Steps: T / dt for a T of a whole number of steps may round a hair above it; not an extra step.
constexpr double kStepCountSlack = 1e-9;
/// Metres: `expect clearance at least C` allows this much rounding of the feet's height above the
/// ground (the walker keeps exactly C, computed in double at map magnitudes).
constexpr double kClearanceSlack = 1e-9;

bool nameMatches(const std::string& name, const std::string& want) {
  return name == want || (name.size() > want.size() && name.compare(0, want.size(), want) == 0 &&
                          name[want.size()] == '/');
}

std::string fmt(const char* f, double a) {
  char buf[96];
  std::snprintf(buf, sizeof buf, f, a);
  return buf;
}

}  // namespace

ScriptPlayer::ScriptPlayer(const Script& script, Walker& walker)
    : script_(script), walker_(walker), speed_(walker.options().viewer.speed) {}

bool ScriptPlayer::allMet() const {
  for (const auto& r : results_)
    if (!r.met) return false;
  return true;
}

std::string ScriptPlayer::where(const ScriptCommand& c) const {
  return script_.path + ":" + std::to_string(c.line) + ": " + scriptOpName(c.op);
}

void ScriptPlayer::stepOnce(const Eigen::Vector3d& move, double headingDeg, double pitchDeg,
                            const StepCallback& onStep) {
  StepInput in;
  in.move = move;
  in.headingDeg = headingDeg;
  in.pitchDeg = pitchDeg;
  const StepReport report = walker_.step(in);
  ++steps_;
  if (onStep) onStep(walker_, report);
}

void ScriptPlayer::turnTo(double headingDeg, const StepCallback& onStep) {
  // Whole steps at the turn rate; the last part (less than a step's turn) is applied to the view
  // at once and the body follows at the next step.
  const double maxTurn = kTurnRate * walker_.options().dt;
  double left = turnBetween(walker_.state().headingDeg, headingDeg);
  while (std::abs(left) > maxTurn) {
    const double turn = std::copysign(maxTurn, left);
    stepOnce(Eigen::Vector3d::Zero(), wrapDegrees360(walker_.state().headingDeg + turn), walker_.state().pitchDeg, onStep);
    left -= turn;
  }
  walker_.setView(wrapDegrees360(headingDeg), walker_.state().pitchDeg);
}

void ScriptPlayer::pitchTo(double pitchDeg, const StepCallback& onStep) {
  const double maxPitch = kPitchRate * walker_.options().dt;
  while (std::abs(pitchDeg - walker_.state().pitchDeg) > maxPitch) {
    const double p = walker_.state().pitchDeg + std::copysign(maxPitch, pitchDeg - walker_.state().pitchDeg);
    stepOnce(Eigen::Vector3d::Zero(), walker_.state().headingDeg, p, onStep);
  }
  walker_.setView(walker_.state().headingDeg, pitchDeg);
}

void ScriptPlayer::goTo(const Eigen::Vector3d& target, bool hasZ, bool aim, const StepCallback& onStep,
                        double arriveAt) {
  const double dt = walker_.options().dt;
  const double eyeHeight = walker_.options().viewer.eyeHeight;
  // A flying target below the clearance over its ground is aimed at the lowest allowed height
  // there, so that the speed goes into the distance that can be flown.
  Eigen::Vector3d aimAt = target;
  if (hasZ && walker_.state().flying) {
    if (const std::optional<double> lowest = walker_.lowestFlyingFeet(target.x(), target.y()))
      aimAt.z() = std::max(aimAt.z(), *lowest + eyeHeight);
  }
  auto offset = [&]() {
    const WalkerState& s = walker_.state();
    Eigen::Vector3d d = aimAt - (s.feet + Eigen::Vector3d(0, 0, eyeHeight));
    if (!(hasZ && s.flying)) d.z() = 0;
    return d;
  };
  const bool timed = !std::isnan(arriveAt);
  if (aim && !timed) {
    const Eigen::Vector3d d = offset();
    if (d.head<2>().norm() > kArrivalTolerance) turnTo(headingOf(d.x(), d.y()), onStep);
  }
  // A timed goto turns the view while it walks (its time is the route's), and not at all toward a
  // target closer than kTimedViewDistance (the jitter of a GPS standing still).
  const double reaimBeyond = timed && offset().head<2>().norm() < kTimedViewDistance
                                 ? std::numeric_limits<double>::infinity()
                                 : kReaimDistance;
  double speed = speed_;
  if (timed) {
    // A timed goto: the steps left until the arrival time, at least one when there is a way to go.
    const double dist = offset().norm();
    const double stepsLeft = std::max(0.0, std::round((arriveAt - walker_.state().time) / dt));
    if (dist <= kArrivalTolerance) {
      for (double i = 0; i < stepsLeft; ++i)
        stepOnce(Eigen::Vector3d::Zero(), walker_.state().headingDeg, walker_.state().pitchDeg, onStep);
      return;
    }
    speed = dist / (std::max(1.0, stepsLeft) * dt);
  }
  double stuck = 0;
  for (;;) {
    const Eigen::Vector3d d = offset();
    const double dist = d.norm();
    if (dist <= kArrivalTolerance) break;
    const double stepLen = speed * dt;
    // The last step takes the whole rest when it is within kLastStepSlack of a step's length
    // (flying targets recorded below the clearance floor are a hair out of reach otherwise).
    const bool last = dist <= stepLen * (1.0 + kLastStepSlack);
    const Eigen::Vector3d move = last ? d : Eigen::Vector3d(d * (stepLen / dist));
    double heading = walker_.state().headingDeg;
    if (aim && d.head<2>().norm() > reaimBeyond) {
      // Re-aim (a slide may have moved the viewer off the line), within the turn rate.
      const double want = headingOf(d.x(), d.y());
      const double turn = turnBetween(heading, want);
      const double maxTurn = kTurnRate * dt;
      heading = wrapDegrees360(heading + (std::abs(turn) <= maxTurn ? turn : std::copysign(maxTurn, turn)));
    }
    const Eigen::Vector3d before = walker_.state().feet;
    stepOnce(move, heading, walker_.state().pitchDeg, onStep);
    if (last && offset().head<2>().norm() <= kArrivalTolerance) break;
    if ((walker_.state().feet - before).norm() < kProgressEpsilon) {
      // Only height left and none gained: the flying clearance holds the viewer above the target.
      if (d.head<2>().norm() <= kArrivalTolerance) break;
      stuck += dt;
      if (stuck >= kBlockedTimeout - kTimeSlack) break;
    } else {
      stuck = 0;
    }
  }
}

void ScriptPlayer::expect(const ScriptCommand& c) {
  const WalkerState& s = walker_.state();
  const CollisionWorld& world = walker_.world();
  ExpectationResult r;
  r.script = script_.path;
  r.line = c.line;
  r.frame = s.frame;
  r.eye = walker_.eye();
  std::string blocker = s.reason == BlockReason::Equipment && s.blockedUnit >= 0
                            ? world.name(std::size_t(s.blockedUnit))
                            : std::string(blockReasonName(s.reason));
  switch (c.op) {
    case ScriptOp::ExpectBlocked: {
      r.text = c.name.empty() ? "expect blocked" : "expect blocked by " + c.name;
      bool byIt = c.name.empty();
      if (!byIt && s.reason == BlockReason::Equipment && s.blockedUnit >= 0) {
        const std::size_t u = std::size_t(s.blockedUnit);
        byIt = nameMatches(world.name(u), c.name) || nameMatches(world.group(u), c.name);
      } else if (!byIt && s.reason != BlockReason::None) {
        byIt = nameMatches(blocker, c.name) || c.name == "terrain";
      }
      r.met = s.blocked && byIt;
      r.detail = s.blocked ? "blocked by " + blocker : "free";
      break;
    }
    case ScriptOp::ExpectFree:
      r.text = "expect free";
      r.met = !s.blocked;
      r.detail = s.blocked ? "blocked by " + blocker : "free";
      break;
    case ScriptOp::ExpectGround: {
      r.text = "expect ground within " + fmt("%g", c.tolerance);
      const std::optional<double> g = walker_.terrain().groundHeight(s.feet.x(), s.feet.y());
      if (!g) {
        r.detail = "no ground under the viewer";
      } else if (s.flying) {
        r.detail = "flying";
      } else {
        const double err = std::abs(s.feet.z() - *g);
        r.met = err <= c.tolerance;
        r.detail = "eye " + fmt("%.6f", err) + " m off eye height above the ground";
      }
      break;
    }
    case ScriptOp::ExpectPosition: {
      r.text = "expect position " + fmt("%.3f", c.v.x()) + " " + fmt("%.3f", c.v.y()) + " within " +
               fmt("%g", c.tolerance);
      const double dist = std::hypot(s.feet.x() - c.v.x(), s.feet.y() - c.v.y());
      r.met = dist <= c.tolerance;
      r.detail = fmt("%.4f", dist) + " m away";
      break;
    }
    case ScriptOp::ExpectClearance: {
      r.text = "expect clearance at least " + fmt("%g", c.tolerance);
      const std::optional<double> g = walker_.terrain().groundHeight(s.feet.x(), s.feet.y());
      if (!g) {
        r.detail = "no ground under the viewer";
      } else {
        const double clear = s.feet.z() - *g;
        r.met = clear >= c.tolerance - kClearanceSlack;
        r.detail = "clearance " + fmt("%.4f", clear) + " m";
      }
      break;
    }
    default:
      return;
  }
  results_.push_back(std::move(r));
}

void ScriptPlayer::run(const StepCallback& onStep) {
  const double dt = walker_.options().dt;
  bool started = false;
  for (const ScriptCommand& c : script_.commands) {
    const WalkerState& s = walker_.state();
    switch (c.op) {
      case ScriptOp::Mode:
        if (c.fly != s.flying) {
          if (c.fly) {
            walker_.setFlying(true, s.clearance);
          } else {
            const std::string why =
                walker_.place(s.feet + Eigen::Vector3d(0, 0, walker_.options().viewer.eyeHeight), false, s.headingDeg,
                              false, s.clearance);
            if (!why.empty()) throw InputError(where(c) + ": cannot land here: " + why);
          }
        }
        break;
      case ScriptOp::Speed:
        speed_ = c.v.x();
        break;
      case ScriptOp::Clearance:
        walker_.setFlying(s.flying, c.v.x());
        break;
      case ScriptOp::Start: {
        const double heading = c.hasHeading ? c.heading : s.headingDeg;
        const std::string why = walker_.place(c.v, c.hasZ, heading, s.flying, s.clearance);
        if (!why.empty()) throw InputError(where(c) + ": " + why);
        started = true;
        startTime_ = walker_.state().time;
        break;
      }
      case ScriptOp::Goto:
      case ScriptOp::Move:
      case ScriptOp::MoveBy: {
        if (!started) throw InputError(where(c) + ": the script moves before its `start`");
        const Eigen::Vector3d eye = walker_.eye();
        if (c.op == ScriptOp::Goto) {
          Eigen::Vector3d t = c.v;
          if (!c.hasZ) t.z() = eye.z();
          goTo(t, c.hasZ, true, onStep, c.hasTime ? startTime_ + c.time : std::numeric_limits<double>::quiet_NaN());
        } else if (c.op == ScriptOp::Move) {
          const double h = radians(s.headingDeg);
          goTo(eye + c.v.x() * Eigen::Vector3d(std::sin(h), std::cos(h), 0), false, false, onStep);
        } else {
          goTo(eye + c.v, c.hasZ, false, onStep);
        }
        break;
      }
      case ScriptOp::Turn:
        turnTo(wrapDegrees360(s.headingDeg + c.v.x()), onStep);
        break;
      case ScriptOp::Heading:
        turnTo(wrapDegrees360(c.v.x()), onStep);
        break;
      case ScriptOp::Look:
        pitchTo(c.v.x(), onStep);
        break;
      case ScriptOp::Wait: {
        const auto n = std::uint64_t(std::ceil(c.v.x() / dt - kStepCountSlack));
        for (std::uint64_t i = 0; i < n; ++i)
          stepOnce(Eigen::Vector3d::Zero(), s.headingDeg, s.pitchDeg, onStep);
        break;
      }
      case ScriptOp::ExpectBlocked:
      case ScriptOp::ExpectFree:
      case ScriptOp::ExpectGround:
      case ScriptOp::ExpectPosition:
      case ScriptOp::ExpectClearance:
        expect(c);
        break;
    }
  }
}

}  // namespace nestwalk
