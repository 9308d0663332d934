// A walk by hand, recorded as a flythrough script that `nestwalk run` plays back to the same
// contacts and positions, plus an OpenSceneGraph AnimationPath of the camera.
//
// The script (script.h's format): a header comment, the mode, clearance, speed and `start X Y [Z]
// heading H` of the first step, then one group of lines per run of steps with the same input (the
// same move per step, heading, pitch and mode):
//   `mode walk|fly`, `heading H`, `look P`, `speed V` where they changed, then
//   `move DX DY [DZ]` (the run's whole displacement as the keys asked for it: steps x move per
//   step; DZ when flying up or down) or `wait T` (no key held: steps x dt);
//   a run that ends blocked is followed by `expect blocked by UNIT` (equipment; `expect blocked`
//   for the terrain), and, where the hand pressed on against the obstacle for longer than the
//   player's kBlockedTimeout, by a `wait` for the rest.
// Played back, each `move` walks the same straight steps (speed x dt) and stops at the same
// contact, because its target lies on the same line as the hand's steps; turns smaller than one
// step's kTurnRate turn at once, larger ones take whole steps in place. Numbers are written with
// 17 significant digits, so positions agree to rounding (the issue asks for 1 mm).
// Not exact: a walk with sliding on (the player re-aims at each `move`'s target after a slide,
// where the hand kept its direction); the script's header says so.
//
// Units: metres (map frame), seconds, degrees. Thread safety: one thread.
#pragma once

#include "nestwalk/walker/animation_path.h"
#include "nestwalk/walker/walker.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace nestwalk {

class WalkRecording {
 public:
  // Starts a recording at the walker's current state. sceneFile and methodName go into the header.
  WalkRecording(const Walker& walker, const std::string& sceneFile, const std::string& methodName);

  // Records one step: the input given to walker.step() and the walker after it.
  void add(const StepInput& input, const Walker& walker);

  // The script so far (the open run of steps included).
  std::string scriptText() const;
  // The camera at every step (the start included), for writeAnimationPath.
  const std::vector<CameraSample>& camera() const { return camera_; }
  std::uint64_t steps() const { return steps_; }
  // Contacts: (step index from 1, unit name or terrain reason) where a run ended blocked.
  struct Contact {
    std::uint64_t step = 0;
    std::string blocker;
    Eigen::Vector3d feet = Eigen::Vector3d::Zero();
  };
  const std::vector<Contact>& contacts() const { return contacts_; }

 private:
  struct Run {
    Eigen::Vector3d move = Eigen::Vector3d::Zero();
    double headingDeg = 0, pitchDeg = 0;
    bool flying = false;
    std::uint64_t steps = 0;
    bool blocked = false;           // the run ended at a blocked step
    std::string expectLine;         // its `expect blocked ...`
    std::uint64_t pressedSteps = 0; // blocked steps after that, the same input, no progress
  };
  struct WriterState;
  void markBlocked(Run& run, const Walker& walker);
  void writeRun(const Run& run, std::string& out, WriterState& state) const;

  double dt_;
  double startClearance_;
  std::string header_, start_;
  bool startFlying_ = false;
  double startHeading_ = 0, startPitch_ = 0, startSpeed_ = 0;
  std::vector<Run> runs_;
  std::vector<CameraSample> camera_;
  std::vector<Contact> contacts_;
  std::uint64_t steps_ = 0;
  bool slid_ = false;
};

}  // namespace nestwalk
