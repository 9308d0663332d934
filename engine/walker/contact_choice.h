// The contact test chosen per collision unit (VolumeMethod::Auto, scene/method_spec.h): the
// mining-dump paper's own future work, "choose the test by the kind of object", decided at load
// time from each unit's own geometry instead of a label.
//
// Criterion: the nested test (AABB, then OBB) stops the body where it touches the unit's inner
// OBB; the real surface lies somewhere inside. How far inside it can lie, at worst, is the largest
// distance from a point of the OBB's surface to the unit's triangles, its gap. A body stopped on
// the box is never further than that from the real surface, so where the gap is at most
// kTightObbGap the nested test alone is kept (a cabinet, a tank, any model that is its box);
// where it is more, the exact mesh stage follows the nested one (a mast with its arm, a pole, a
// tilted panel on its frame, an L-shaped piece).
//
// Threshold: kTightObbGap = 10 mm, the limit on an early stop. What it bounds: a body
// stopped on a tight box is at most 10 mm from the real surface (the stop gap); measured along the
// motion, the distance it could still have gone is that over the cosine of the angle between the
// motion and the face's normal (10 mm head on, 20 mm at 60 degrees; a grazing motion can always
// be stopped short by more). The measurements behind it: a box's own OBB has gap 0 (to rounding),
// a bare round pole's square box 0.41 of its radius (8.3 mm at 4 cm across, 12.4 mm at 6 cm:
// contact_choice_test, shapes on both sides of the threshold checked against a dense brute
// force); on the bundled scene (`nestwalk report`, its auto table)
// every model's smallest gap is a decimetre or more (poles 95 mm, containers 100 mm: their bottom
// rails leave the box's floor empty; barriers 106 mm; logger boxes 144 mm; piezometers, panels,
// stations and pickups 225 to 450 mm), so there auto gives every unit the exact stage, and the
// report measures the early stops it leaves against the exact reference (none).
//
// The gap is found by branch and bound over the six faces. A patch of a face (a rectangle) has
// gap at most the largest distance from its four corners to T, the triangle nearest its centre
// (the distance to one triangle is convex, so over the patch it is largest at a corner, and the
// distance to the mesh is at most that to T); and at most d(c) + r (c its centre, r its half
// diagonal: the distance is 1-Lipschitz). Patches are split in four, the one with the largest
// bound first, until a point's distance exceeds the threshold (not tight: the gap is at least
// that) or no patch's bound does (tight). On a face the model's triangles cover (a box) the first
// bound is 0 for every patch inside one triangle, so only the patches along the triangles' edges
// are split, down to the threshold's size (a box of 0.6 x 0.4 x 0.5 m: about 1300 queries). Patches smaller than kGapResolution whose bound still exceeds the
// threshold count as not tight (conservative: the exact stage), as does running past
// kMaxGapProbes distance queries.
//
// Thread safety: obbSurfaceGap keeps no state and calls `nearest` on the calling thread; it is as
// safe as that callback.
#pragma once

#include "nestwalk/geometry/triangle_box.h"
#include "nestwalk/geometry/volumes.h"

#include <cstdint>
#include <functional>
#include <optional>

namespace nestwalk {

/// Metres: the largest gap between a unit's inner OBB and its triangles for which the nested test
/// alone decides contact (see above).
inline constexpr double kTightObbGap = 0.01;
/// Metres: patches of the OBB's faces are not split below this (a tenth of the threshold).
inline constexpr double kGapResolution = 0.001;
/// Distance queries per unit at most (a few milliseconds of load time for a complex model).
inline constexpr int kMaxGapProbes = 20000;

struct GapVerdict {
  bool tight = false;     // gap <= threshold: the nested test suffices
  double lowerBound = 0;  // metres: the largest distance found (the gap is at least this)
  int probes = 0;         // distance queries made
};

/// The distance from a point to the triangles and the nearest triangle (+infinity and none when
/// there are no triangles).
using NearestTriangleQuery = std::function<double(const Vec3<double>& point, std::optional<Triangle>& nearest)>;

/// Decides whether the gap between `box`'s surface and the triangles `nearest` measures is at most
/// `threshold`.
GapVerdict obbSurfaceGap(const Obb<double>& box, const NearestTriangleQuery& nearest, double threshold = kTightObbGap);

/// Auto's second criterion: a unit whose OBB is not tight gets the exact stage only when it is
/// affordable, measured at load on sample sweeps of the body into the unit (walker/exact_stage_cost.h:
/// sampleExactStageCost): at most kMaxExactStageTests bounding-volume and triangle tests a sweep.
/// A densely tessellated flat face used to exceed it (a body pressed against it reached every
/// triangle under its face at once: 10,206 tests a step on a wall of 1 cm squares); since the
/// tree's nodes carry a slab along their normals and contacts within a tie are one (mesh_tree.h,
/// 2026-11-28), that wall costs 90 tests (hard_cases_auto_cost_test), the heavy real models at most
/// about 500 (480 on the drill rig's mast), and the limit is a safety net for meshes that defeat
/// the tree. Counted, not timed: the same verdict on every machine; a test costs 25-80 ns here, so
/// the bound is about 100-300 us a step.
inline constexpr std::uint64_t kMaxExactStageTests = 4000;

struct ExactStageCost {
  std::uint64_t maxTests = 0;  // the most tests one sample sweep made
  int sweeps = 0;              // sample sweeps counted
  bool affordable() const { return maxTests <= kMaxExactStageTests; }
};

}  // namespace nestwalk
