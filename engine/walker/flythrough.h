// One flythrough: a script played on a scene's walker, with a record per step (what `nestwalk run`
// writes, what the report and the benchmarks aggregate). No files here: the report side writes them (engine/report).
// Ownership: runFlythrough's walker refers to the scene's terrain and to `world` for the call only;
// nothing is kept after it returns. onRecord runs on the calling thread.
// Thread safety: a play sweeps `world`, which keeps scratch and a last-sweep cache despite the
// const reference (collision_world.h): plays on different threads need different worlds.
#pragma once

#include "nestwalk/walker/animation_path.h"
#include "nestwalk/walker/frame_record.h"
#include "nestwalk/walker/script.h"
#include "nestwalk/walker/walker.h"

#include <functional>
#include <vector>

namespace nestwalk {

struct Scene;

struct FlythroughResult {
  std::vector<FrameRecord> records;
  std::vector<ExpectationResult> expectations;
  std::vector<CameraSample> camera;  // eye, heading and pitch per step (for the .path file)
  bool expectationsMet() const;
};

// Plays `script` on a walker over `scene` and `world`; calls `onRecord` after each step with the
// step's record (as kept in the result; a renderer draws the frame from it).
// Throws InputError (script file and line) for a start that cannot be.
FlythroughResult runFlythrough(const Scene& scene, const CollisionWorld& world, const Script& script,
                               const WalkerOptions& options,
                               const std::function<void(const FrameRecord&)>& onRecord = {});

// The record of the walker's current state after a step.
FrameRecord makeFrameRecord(const Walker& walker, const StepReport& report);

}  // namespace nestwalk
