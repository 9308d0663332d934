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
//  - Conservative rounding: every comparison also carries a slack of kRoundingSlack<T> times the
//    magnitudes in play (|cB - cA|_1 plus all half extents), so that exactly touching boxes (a point
//    on a rotated face, boxes moved to a local frame) are never separated by the rounding of t, R
//    and the sums. A verdict of "separated" is therefore exact for the boxes as given; "overlap"
//    may be a separation smaller than the bands above (1e-12 relative in double).
// Thread safety: pure inline functions.
#pragma once

#include "nestwalk/geometry/volumes.h"

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

/// Relative slack on every comparison, covering the rounding of the test itself. Each side of a
/// comparison is a sum of at most 9 products of quantities bounded by M = |cB - cA|_1 + sum of half
/// extents, each rounded (relative u) and built from axes off orthonormal by kAxesTolerance<T>
/// (moving any projection by at most sqrt(3) * kAxesTolerance * M).
///  - double: 16 u M + 1.8e-13 M < 2e-13 M; 1e-12 keeps a 5x margin (1 nm at 1 km).
///  - float:  16 u M + 3.5e-7 M < 1.4e-6 M; 2e-6 keeps a 1.4x margin (20 um for 10 m).
template <class T> inline constexpr T kRoundingSlack = T(1e-12);
template <> inline constexpr float kRoundingSlack<float> = 2e-6f;

inline constexpr int kNoAxis = -1;

struct SatResult {
  bool overlap;
  std::int8_t axis;  // separating axis index, kNoAxis when overlapping
};

namespace detail {

/// Steps 2 and 3 of the SAT, once A's face axes have not separated the boxes: B's face axes and
/// the edge axes, given t = A^T (cB - cA), R = A^T B and absR = |R| + eps.
template <class T>
[[gnu::always_inline]] inline SatResult satAfterFacesOfA(const T (&t)[3], const T (&R)[3][3], const T (&absR)[3][3],
                                                          const T* a, const T* b, T slack) {
  // B's face axes.
  for (int j = 0; j < 3; ++j) {
    const T ra = a[0] * absR[0][j] + a[1] * absR[1][j] + a[2] * absR[2][j];
    const T d = t[0] * R[0][j] + t[1] * R[1][j] + t[2] * R[2][j];
    if (std::abs(d) > ra + b[j] + slack) return {false, std::int8_t(3 + j)};
  }
  // Edge axes L = A_i x B_j (Ericson 4.4.1, written for general i, j).
  for (int i = 0; i < 3; ++i) {
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const T ra = a[i1] * absR[i2][j] + a[i2] * absR[i1][j];
      const T rb = b[j1] * absR[i][j2] + b[j2] * absR[i][j1];
      const T d = t[i2] * R[i1][j] - t[i1] * R[i2][j];
      if (std::abs(d) > ra + rb + slack) return {false, std::int8_t(6 + 3 * i + j)};
    }
  }
  return {true, std::int8_t(kNoAxis)};
}

/// The slack of a pair: kRoundingSlack times |d|_1 plus the half extents.
template <class T>
[[gnu::always_inline]] inline T pairSlack(const T* d, const T* a, const T* b) {
  return kRoundingSlack<T> * (std::abs(d[0]) + std::abs(d[1]) + std::abs(d[2]) + a[0] + a[1] + a[2] + b[0] + b[1] + b[2]);
}

}  // namespace detail

/// The SAT given B in A's frame: t = A^T (cB - cA), R = A^T B, half extents a and b.
/// `inputRounding` is an absolute bound on what rounding the inputs t and a cost (see satAabbObb).
template <class T>
[[gnu::always_inline]] inline SatResult satInFrameOfA(const Vec3<T>& tv, const Mat3<T>& Rm, const Vec3<T>& a,
                                                      const Vec3<T>& b, T inputRounding = T(0)) {
  const T slack = detail::pairSlack(tv.data(), a.data(), b.data()) + inputRounding;
  T t[3], R[3][3], absR[3][3];
  // A's face axes, row by row of R so that an early exit skips the rest.
  for (int i = 0; i < 3; ++i) {
    t[i] = tv[i];
    for (int j = 0; j < 3; ++j) {
      R[i][j] = Rm(i, j);
      absR[i][j] = std::abs(R[i][j]) + kParallelEpsilon<T>;
    }
    if (std::abs(t[i]) > a[i] + b[0] * absR[i][0] + b[1] * absR[i][1] + b[2] * absR[i][2] + slack)
      return {false, std::int8_t(i)};
  }
  return detail::satAfterFacesOfA<T>(t, R, absR, a.data(), b.data(), slack);
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
[[gnu::always_inline]] inline SatResult satAabbObb(const Aabb<T>& a, const Obb<T>& b) {
  // The AABB's centre and half extents are rounded from min and max (each by at most u times
  // |min| + |max| on its axis), and every test sums at most two such terms per axis with weights
  // <= 1 + eps: 8 epsilon = 16 u times the sum bounds it with margin, even far from the origin.
  const T inputRounding = T(8) * std::numeric_limits<T>::epsilon() * (a.min.cwiseAbs() + a.max.cwiseAbs()).sum();
  return satInFrameOfA<T>(b.center - a.center(), b.axes, a.halfExtents(), b.halfExtents, inputRounding);
}

/// OBB-OBB, the full 15-axis test. R and t are formed row by row (A_i . B_j, A_i . d) with
/// explicit dot products, so that a pair separated by A's first face axis costs 4 dot products.
template <class T>
[[gnu::always_inline]] inline SatResult satObbObb(const Obb<T>& A, const Obb<T>& B) {
  const T d[3] = {B.center[0] - A.center[0], B.center[1] - A.center[1], B.center[2] - A.center[2]};
  const T* a = A.halfExtents.data();
  const T* b = B.halfExtents.data();
  const T* Aax = A.axes.data();  // column-major: axis i is Aax[3i .. 3i+2]
  const T* Bax = B.axes.data();
  const T slack = detail::pairSlack(d, a, b);
  T t[3], R[3][3], absR[3][3];
  for (int i = 0; i < 3; ++i) {
    const T* Ai = Aax + 3 * i;
    t[i] = Ai[0] * d[0] + Ai[1] * d[1] + Ai[2] * d[2];
    for (int j = 0; j < 3; ++j) {
      const T* Bj = Bax + 3 * j;
      R[i][j] = Ai[0] * Bj[0] + Ai[1] * Bj[1] + Ai[2] * Bj[2];
      absR[i][j] = std::abs(R[i][j]) + kParallelEpsilon<T>;
    }
    if (std::abs(t[i]) > a[i] + b[0] * absR[i][0] + b[1] * absR[i][1] + b[2] * absR[i][2] + slack)
      return {false, std::int8_t(i)};
  }
  return detail::satAfterFacesOfA<T>(t, R, absR, a, b, slack);
}

/// Name of an axis index for reports: "A0".."A2", "B0".."B2", "A0xB0".."A2xB2", "" for kNoAxis.
const char* satAxisName(int axis);
/// Name of an AABB-AABB axis: "x", "y", "z", "" for kNoAxis.
const char* aabbAxisName(int axis);

}  // namespace nestwalk
