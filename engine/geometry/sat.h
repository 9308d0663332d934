// Separating-axis overlap tests for closed boxes: AABB-AABB, AABB-OBB and OBB-OBB, with early
// exit, reporting which axis separated the boxes.
//
// Follows Gottschalk, Lin & Manocha, "OBBTree" (SIGGRAPH 1996), section 4 and Ericson,
// Real-Time Collision Detection (2005) 4.4.1: the 15 candidate axes are tried in Gottschalk's
// order, A's three face normals, B's three face normals, then the nine edge-edge cross products
// A_i x B_j, with the box B expressed in A's frame (R = A^T B, t = A^T (cB - cA)).
//
// Conventions:
//  - Boxes are closed: touching (|t.L| == rA + rB) is overlap. Separation needs a strict '>'.
//  - Axis index: 0..2 = A's face axes, 3..5 = B's face axes, 6 + 3 i + j = A_i x B_j,
//    kNoAxis (-1) when no axis separates (overlap). For AABB-AABB: 0..2 = x, y, z.
//  - NaN anywhere makes every comparison false, hence "overlap": the conservative answer.
//  - Conservative near-parallel edges: |R| is inflated by kParallelEpsilon<T> (see below), so an
//    edge axis whose cross product has degenerated to rounding noise cannot report a separation
//    that is not there. The price is a false-overlap band: a pair whose only separating axis is an
//    edge axis at angle theta between the edges, separated by less than eps * S / sin(theta)
//    (S = sum of the four half extents involved), is reported as overlapping. Face axes are
//    inflated by eps * (sum of half extents), i.e. 1e-12 relative in double.
#pragma once

#include "engine/geometry/volumes.h"

#include <cstdint>

namespace nestwalk {

/// Added to every |R_ij| = |A_i . B_j| (Gottschalk 1996, RAPID's "fudge"). It must exceed the
/// error of a computed R_ij: with axes orthonormal to kAxesTolerance<T> and each R_ij a 3-term dot
/// product, that error is below kAxesTolerance + 3u (u = unit roundoff). Analysis: when A_i and B_j
/// are parallel, every term of the edge test is O(error of R) times box sizes, and |t| on the other
/// two axes is bounded by the face tests already passed; the test then cannot separate as long as
/// eps >= that error.
///  - double: u = 1.1e-16, axes to 1e-13  -> error <= 1.004e-13; eps = 1e-12 keeps a 10x margin and
///    a worst false-overlap band of sqrt(eps) * S = 1e-6 * S (1 um for 1 m boxes) at
///    theta ~ 1e-6 rad, and eps * S elsewhere.
///  - float:  u = 6e-8, axes to 2e-7 -> error <= 3.8e-7; eps = 1e-6 (RAPID's value) keeps a 2.6x
///    margin; worst band 1e-3 * S at theta ~ 1e-3 rad. Float is meant for filters whose
///    uncertain answers are re-decided in double (see obb_batch.h).
template <class T> inline constexpr T kParallelEpsilon = T(1e-12);
template <> inline constexpr float kParallelEpsilon<float> = 1e-6f;

inline constexpr int kNoAxis = -1;

struct SatResult {
  bool overlap;
  std::int8_t axis;  // separating axis index, kNoAxis when overlapping
};

/// The SAT given B in A's frame: t = A^T (cB - cA), R = A^T B, half extents a and b.
template <class T>
inline SatResult satInFrameOfA(const Vec3<T>& t, const Mat3<T>& R, const Vec3<T>& a, const Vec3<T>& b) {
  Mat3<T> absR;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) absR(i, j) = std::abs(R(i, j)) + kParallelEpsilon<T>;

  // A's face axes.
  for (int i = 0; i < 3; ++i) {
    const T rb = b[0] * absR(i, 0) + b[1] * absR(i, 1) + b[2] * absR(i, 2);
    if (std::abs(t[i]) > a[i] + rb) return {false, std::int8_t(i)};
  }
  // B's face axes.
  for (int j = 0; j < 3; ++j) {
    const T ra = a[0] * absR(0, j) + a[1] * absR(1, j) + a[2] * absR(2, j);
    const T d = t[0] * R(0, j) + t[1] * R(1, j) + t[2] * R(2, j);
    if (std::abs(d) > ra + b[j]) return {false, std::int8_t(3 + j)};
  }
  // Edge axes L = A_i x B_j (Ericson 4.4.1, written for general i, j).
  for (int i = 0; i < 3; ++i) {
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const T ra = a[i1] * absR(i2, j) + a[i2] * absR(i1, j);
      const T rb = b[j1] * absR(i, j2) + b[j2] * absR(i, j1);
      const T d = t[i2] * R(i1, j) - t[i1] * R(i2, j);
      if (std::abs(d) > ra + rb) return {false, std::int8_t(6 + 3 * i + j)};
    }
  }
  return {true, std::int8_t(kNoAxis)};
}

/// AABB-AABB on the closed boxes; exact (comparisons only, no arithmetic).
template <class T>
inline SatResult satAabbAabb(const Aabb<T>& a, const Aabb<T>& b) {
  for (int k = 0; k < 3; ++k)
    if (a.max[k] < b.min[k] || b.max[k] < a.min[k]) return {false, std::int8_t(k)};
  return {true, std::int8_t(kNoAxis)};
}

/// AABB (as box A, axes = identity) against OBB B; axis indices as for OBB-OBB.
template <class T>
inline SatResult satAabbObb(const Aabb<T>& a, const Obb<T>& b) {
  return satInFrameOfA<T>(b.center - a.center(), b.axes, a.halfExtents(), b.halfExtents);
}

/// OBB-OBB, the full 15-axis test.
template <class T>
inline SatResult satObbObb(const Obb<T>& a, const Obb<T>& b) {
  const Mat3<T> at = a.axes.transpose();
  return satInFrameOfA<T>(at * (b.center - a.center), at * b.axes, a.halfExtents, b.halfExtents);
}

/// Name of an axis index for reports: "A0".."A2", "B0".."B2", "A0xB0".."A2xB2", "" for kNoAxis.
const char* satAxisName(int axis);
/// Name of an AABB-AABB axis: "x", "y", "z", "" for kNoAxis.
const char* aabbAxisName(int axis);

}  // namespace nestwalk
