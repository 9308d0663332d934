// The nested-volume test of the mining-dump method (Ma et al., "A collision detection-based
// wandering method for equipment deploy scene in land reclamation area of mining dump",
// section 3): every object carries an outer AABB and an inner OBB, and a pair is tested in three
// stages, each run only when the one before could not separate the pair:
//   1. AABB-AABB  (outer vs outer: separates most distant pairs with six comparisons),
//   2. AABB-OBB   (the viewer's outer AABB vs the object's inner OBB, 15-axis SAT),
//   3. OBB-OBB    (inner vs inner, 15-axis SAT): its verdict is the answer.
// Both volumes of an object must contain the object; they need not contain each other.
// Thread safety: pure functions and plain value types; StageCounters is a plain accumulator (one
// per thread).
#pragma once

#include "nestwalk/core/enum_array.h"
#include "nestwalk/geometry/sat.h"

#include <array>
#include <cstdint>

namespace nestwalk {

template <class T>
struct NestedVolume {
  Aabb<T> outer;
  Obb<T> inner;

  /// The nested volume of an OBB alone: the outer box is its AABB (aabbOf).
  static NestedVolume fromObb(const Obb<T>& b) { return {aabbOf(b), b}; }
};

enum class OverlapStage : std::uint8_t { AabbAabb = 0, AabbObb = 1, ObbObb = 2 };
inline constexpr int kStageCount = 3;
const char* stageName(OverlapStage s);  // "aabb-aabb", "aabb-obb", "obb-obb"

/// A count per stage, indexed by the stage: tests run at each stage are the Nv terms of the cost
/// model T = Nv Cv + Np Cp + Nu Cu, stage by stage.
using StageCounts = EnumArray<OverlapStage, kStageCount, std::uint64_t>;

struct NestedResult {
  bool overlap;
  OverlapStage stage;  // the stage that decided
  std::int8_t axis;    // the separating axis in that stage's numbering (see sat.h), or kNoAxis
};

/// Bounding-volume tests run per stage: the Nv terms of the cost model T = Nv Cv + Np Cp + Nu Cu.
struct StageCounters {
  std::array<std::uint64_t, kStageCount> tests{};      // tests run at each stage
  std::array<std::uint64_t, kStageCount> separated{};  // pairs that stage separated
  void add(const NestedResult& r) {
    for (int s = 0; s <= int(r.stage); ++s) ++tests[s];
    if (!r.overlap) ++separated[int(r.stage)];
  }
};

/// The three-stage test of a viewer against an object.
template <class T>
inline NestedResult testNested(const NestedVolume<T>& viewer, const NestedVolume<T>& object) {
  const SatResult s1 = satAabbAabb(viewer.outer, object.outer);
  if (!s1.overlap) return {false, OverlapStage::AabbAabb, s1.axis};
  const SatResult s2 = satAabbObb(viewer.outer, object.inner);
  if (!s2.overlap) return {false, OverlapStage::AabbObb, s2.axis};
  const SatResult s3 = satObbObb(viewer.inner, object.inner);
  return {s3.overlap, OverlapStage::ObbObb, s3.axis};
}

/// Two boxes given as OBBs, possibly in map coordinates, each nested in its AABB (aabbOf).
/// The pair is moved to a local frame centred on A, so millimetre gaps at UTM magnitudes are
/// decided as at the origin (the shift's rounding, at most half an ulp of |cB - cA|, is covered by
/// the tests' rounding slack and aabbOf's outward rounding). A box whose axes are exactly the
/// identity is an AABB: the cascade stops at the first stage that is exact for the pair
/// (AABB-AABB when both are AABBs, AABB-OBB when one is). When only B is an AABB the roles in
/// stage 2 are swapped; the reported axis is still named relative to (A, B). The verdict is the
/// OBB-OBB answer except inside the rounding slack (sat.h): an exact earlier stage may separate a
/// pair that satObbObb's slack would call touching.
NestedResult testBoxPair(const Obb<double>& a, const Obb<double>& b);

}  // namespace nestwalk
