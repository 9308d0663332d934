// What a walker run records per step and per expectation: the walker writes these records (a
// flythrough, flythrough.h), the report side reads them (the CSV, the summary, the plots and the
// map in engine/report). No files are written here.
// Thread safety: plain value types.
#pragma once

#include "nestwalk/core/enum_array.h"
#include "nestwalk/geometry/nested.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>

namespace nestwalk {

/// The timed parts of a step, in the order they run (Total: the whole step).
enum class StepPart : std::uint8_t { Ground, BroadPhase, Narrow, Total };
inline constexpr std::size_t kStepParts = 4;
inline constexpr StepPart kAllStepParts[kStepParts] = {StepPart::Ground, StepPart::BroadPhase, StepPart::Narrow,
                                                       StepPart::Total};
const char* stepPartName(StepPart p);  // "ground", "broad", "narrow", "total"

/// Wall-clock microseconds per part of one step.
using StepTimes = EnumArray<StepPart, kStepParts>;

struct FrameRecord {
  std::uint64_t frame = 0;
  double time = 0;                                      // seconds of simulated time at the frame's end
  Eigen::Vector3d eye = Eigen::Vector3d::Zero();        // map frame
  double headingDeg = 0, pitchDeg = 0;
  double bodyYawDeg = 0;                                // the body box's heading (walker.h: bodyVolumeAt)
  bool flying = false;
  bool hasGround = false;
  double ground = 0;                                    // terrain height under the eye (map z)
  bool blocked = false;
  std::string blockedBy;                                // unit name, or "terrain:step" / "terrain:slope"
                                                        // / "terrain:edge"; "" when free
  std::uint64_t nodeTests = 0;                          // hierarchy BV tests (Nv broad phase)
  StageCounts stageTests;                               // Nv per nested stage
  std::uint64_t primitiveTests = 0;                     // Np (triangle tests; 0 for volume methods)
  std::uint64_t volumesUpdated = 0;                     // Nu (the viewer's volumes rebuilt)
  std::uint64_t groundWaits = 0;                        // paged terrain: tile reads the step waited for
  StepTimes micros;                                     // wall-clock µs per part (timing columns)
};

/// An `expect` line of a script, checked where it stands.
struct ExpectationResult {
  std::string script;     // file
  int line = 0;
  std::string text;       // the expectation as written
  bool met = false;
  std::uint64_t frame = 0;
  Eigen::Vector3d eye = Eigen::Vector3d::Zero();
  std::string detail;     // what was found, e.g. "blocked by bench2/station3/mast" or "free"
};

}  // namespace nestwalk
