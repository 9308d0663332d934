// The running intersection of slab intervals in time: the core of every swept test (swept.h,
// triangle_sweep.h). A body translating by d over t in [0, 1] overlaps a body at rest along an
// axis L while |p0 - t v| <= r (p0: the projection of the centres' offset on L, v = L . d, r: the
// two radii along L plus the test's slack); each slab is an interval of t, and the bodies overlap
// at t when every slab holds. Clipping stops once the running interval misses [0, 1].
// Thread safety: SlabClip is a plain value that clip() updates: one per sweep, owned by the caller.
#pragma once

#include "nestwalk/geometry/sat.h"

#include <cmath>
#include <cstdint>
#include <limits>

namespace nestwalk {

/// Running intersection of slab intervals. Each slab: |p0 - t v| <= r (p0, v, r in the same units
/// along one axis L; r includes the slack). The caller keeps L per `slot` and builds the contact
/// normal from the slot of the slab that entered last: enterSign * L / |L|.
struct SlabClip {
  double enter = -std::numeric_limits<double>::infinity(), exit = std::numeric_limits<double>::infinity();
  double windowStart = 0.0, windowEnd = 1.0;  // the times of interest: clipping stops once the
                                               // running interval misses them
  std::int8_t enterAxis = kNoAxis, decidingAxis = kNoAxis;
  double enterSign = 0;  // -sign(v) of the entering slab: normal = enterSign * L / |L|
  int enterSlot = -1;

  /// Returns false once the running interval misses [windowStart, windowEnd] (then decidingAxis
  /// says which slab).
  bool clip(double p0, double v, double r, std::int8_t axis, int slot) {
    double lo, hi;
    if (v > 0) {
      lo = (p0 - r) / v;
      hi = (p0 + r) / v;
    } else if (v < 0) {
      lo = (p0 + r) / v;
      hi = (p0 - r) / v;
    } else {
      // No motion along L: the slab holds for all t or for none. NaN compares false: "holds".
      if (std::abs(p0) > r) {
        enter = std::numeric_limits<double>::infinity();
        exit = -std::numeric_limits<double>::infinity();
        decidingAxis = axis;
        return false;
      }
      return true;
    }
    if (lo > enter) {
      enter = lo;
      enterAxis = axis;
      enterSign = v > 0 ? -1.0 : 1.0;
      enterSlot = slot;
    }
    if (hi < exit) exit = hi;
    if (!(enter <= exit && enter <= windowEnd && exit >= windowStart)) {
      decidingAxis = axis;
      return false;
    }
    return true;
  }
};

}  // namespace nestwalk
