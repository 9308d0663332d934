// Test-side references for the separating-axis tests of engine/geometry/sat.h, written
// independently of the engine code (no engine function is called here; only the engine's value
// types Obb/Aabb are used to hand data in and out).
//
// 1. An EXACT reference on rational boxes (ExactBox): integer centres and half extents over a common
//    denominator, and rational rotations R = M / s built from integer quaternions (w, x, y, z),
//    s = w^2 + x^2 + y^2 + z^2, M = s * (the usual unit-quaternion rotation matrix), an integer
//    matrix. All 15 candidate axes are evaluated in __int128 integer arithmetic: for an integer
//    axis L the test |T.L| > rA + rB becomes, after multiplying by the denominators,
//        num = |T'.L| sA sB - sB sum_k EA_k |MA_k.L| - sA sum_k EB_k |MB_k.L|  > 0
//    (T', EA, EB scaled to the common denominator D = denA denB; MA_k = column k of MA). Face axes of
//    A use L = MA_i, of B L = MB_j, edge axes L = MA_i x MB_j (integer cross product). Exactly
//    parallel edges give L = 0, whose num is 0 - 0 - 0 = 0: never separating, as it must be.
//    Boxes are closed, so the pair is separated iff some num > 0 (strictly).
//    From the exact integers we also give, in long double:
//      - gap[k]  = the unnormalised gap |T.L| - rA - rB along L_real (L_real = L / k_L, |L_real| <= 1:
//                  the very quantity the engine compares, A_i x B_j being the engine's edge axis),
//      - len[k]  = |L_real| (sin of the angle between the edges for edge axes, 1 for face axes),
//      - infl[k] = the sum of half extents that the engine multiplies by kParallelEpsilon on that axis
//                  (face of A: sum b; face of B: sum a; A_i x B_j: a_i1 + a_i2 + b_j1 + b_j2),
//      - margin  = max over axes with L != 0 of gap / len (the signed separation distance certified by
//                  the 15 axes: > 0 separated, 0 touching, < 0 overlapping).
//    Magnitude limits are checked on every call (checkExactPairLimits): every intermediate stays below
//    2^124; the reference aborts rather than overflow. Pairs whose bound is below 2^60 run the same
//    formulas in int64 (a speed path, exact for the same reason).
//
// 2. A LONG DOUBLE reference for arbitrary double boxes (ldSat): the same 15 axes evaluated in long
//    double (64-bit significand) in the world frame, with no epsilon; T = cB - cA is computed in long
//    double, exact for the differences of nearby doubles (UTM coordinates included). The normalised
//    gap along each computed axis is accurate to ~1e-19 * (|T| + sizes), which is what the hard cases
//    need (their gaps are >= 1e-6 m). ldSatBothWays also evaluates (B, A) and checks that the two
//    orders agree (closure: the verdict and margin must not depend on the order, and touching is
//    overlap in both orders).
//
// 3. The engine's documented semantics as a model (SatModel, expectInflated): the engine adds eps to
//    every |R_ij| and a rounding slack to every comparison, i.e. it separates on axis k iff
//    gap[k] > eps * infl[k] + slack (up to its rounding). Given a rounding window w, a pair is
//    "surely separated" if some axis has gap > threshold + w, "surely overlapping" if no axis has
//    gap > threshold - w (nor, when strictNoMiss, gap > 0), and otherwise either answer is
//    acceptable. With eps = 1e-6 and no slack the same model describes FCL's obbDisjoint (its
//    'reps' fudge is added to |B| in exactly the same places).
#pragma once

#include "nestwalk/geometry/volumes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <string>

namespace nestwalk::testref {

using i64 = std::int64_t;
using i128 = __int128;
using ld = long double;

inline i128 abs128(i128 v) { return v < 0 ? -v : v; }
/// i128 -> long double without the libgcc call when the value fits 64 bits (rounding as ld(i128)
/// otherwise up to one extra rounding of the low half, irrelevant at 2^-63 relative).
inline ld toLd(i128 v) {
  if (v == i128(i64(v))) return ld(i64(v));
  const i64 hi = i64(v >> 64);
  const std::uint64_t lo = std::uint64_t(v);
  return std::ldexp(ld(hi), 64) + ld(lo);
}
inline int sign128(i128 v) { return (v > 0) - (v < 0); }

[[noreturn]] inline void referenceLimitViolated(const char* what) {
  std::fprintf(stderr, "sat_reference: input outside the exact range: %s\n", what);
  std::abort();
}

// ------------------------------------------------------------------------------------------------
// Rational rotations.

/// R = m / s, exactly orthonormal (m m^T = s^2 I) and right-handed.
struct IntRotation {
  std::array<std::array<i64, 3>, 3> m{};
  i64 s = 1;

  static IntRotation identity() {
    IntRotation r;
    r.m = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    r.s = 1;
    return r;
  }
  /// The rotation of the quaternion (w, x, y, z) (need not be unit; not all zero), scaled by
  /// s = w^2 + x^2 + y^2 + z^2 so that every entry is an integer.
  static IntRotation fromQuaternion(i64 w, i64 x, i64 y, i64 z) {
    IntRotation r;
    r.s = w * w + x * x + y * y + z * z;
    if (r.s == 0) referenceLimitViolated("zero quaternion");
    r.m = {{{w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)},
            {2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)},
            {2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z}}};
    return r;
  }
  /// Rotation about coordinate axis k by the angle with cos = c / h, sin = s / h (a Pythagorean
  /// triple c^2 + s^2 = h^2).
  static IntRotation aboutAxis(int k, i64 c, i64 sn, i64 h) {
    if (c * c + sn * sn != h * h) referenceLimitViolated("not a Pythagorean triple");
    IntRotation r;
    const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
    r.s = h;
    r.m[k][k] = h;
    r.m[k1][k1] = c;
    r.m[k2][k2] = c;
    r.m[k1][k2] = -sn;
    r.m[k2][k1] = sn;
    return r;
  }
  IntRotation operator*(const IntRotation& o) const {
    IntRotation r;
    r.s = s * o.s;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        i64 v = 0;
        for (int k = 0; k < 3; ++k) v += m[i][k] * o.m[k][j];
        r.m[i][j] = v;
      }
    return r;
  }
  bool isIdentity() const {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (m[i][j] != (i == j ? s : 0)) return false;
    return true;
  }
  /// True when m / s is exactly representable in binary floating point: s is a power of two, which
  /// for a rational rotation means a signed permutation matrix.
  bool isDyadic() const { return s > 0 && (s & (s - 1)) == 0; }
  /// Checks m m^T = s^2 I and det m = s^3 exactly.
  bool isExactRotation() const {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        i128 d = 0;
        for (int k = 0; k < 3; ++k) d += i128(m[i][k]) * m[j][k];
        if (d != (i == j ? i128(s) * s : 0)) return false;
      }
    const i128 det = i128(m[0][0]) * (i128(m[1][1]) * m[2][2] - i128(m[1][2]) * m[2][1]) -
                     i128(m[0][1]) * (i128(m[1][0]) * m[2][2] - i128(m[1][2]) * m[2][0]) +
                     i128(m[0][2]) * (i128(m[1][0]) * m[2][1] - i128(m[1][1]) * m[2][0]);
    return det == i128(s) * s * s;
  }
  /// Correctly rounded double entries (m and s are exact in double; one division).
  Mat3<double> toDouble() const {
    Mat3<double> r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r(i, j) = double(m[i][j]) / double(s);
    return r;
  }
  Mat3<float> toFloat() const {
    Mat3<float> r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r(i, j) = float(m[i][j]) / float(s);
    return r;
  }
};

// ------------------------------------------------------------------------------------------------
// Exact boxes.

/// Closed box with centre c / den, half extents e / den (in some length unit), axes rot.
struct ExactBox {
  std::array<i64, 3> c{};
  std::array<i64, 3> e{};
  i64 den = 1;
  IntRotation rot = IntRotation::identity();

  /// The axis-aligned box [mn, mx] (integers), as centre (mn + mx) / 2 and half extents (mx - mn) / 2.
  static ExactBox fromMinMax(const std::array<i64, 3>& mn, const std::array<i64, 3>& mx) {
    ExactBox b;
    for (int k = 0; k < 3; ++k) {
      b.c[k] = mn[k] + mx[k];
      b.e[k] = mx[k] - mn[k];
    }
    b.den = 2;
    return b;
  }
  /// The exact AABB: half extents sum_j |M_ij| e_j / (den s), centre c s / (den s).
  ExactBox aabb() const {
    ExactBox b;
    for (int i = 0; i < 3; ++i) {
      b.c[i] = c[i] * rot.s;
      i64 h = 0;
      for (int j = 0; j < 3; ++j) h += std::llabs(rot.m[i][j]) * e[j];
      b.e[i] = h;
    }
    b.den = den * rot.s;
    return b;
  }
  ExactBox translated(const std::array<i64, 3>& d) const {  // by d / den
    ExactBox b = *this;
    for (int k = 0; k < 3; ++k) b.c[k] += d[k];
    return b;
  }
  /// True when the double box toObb(unit) (unit a power of two) is exactly this box: dyadic axes,
  /// dyadic denominator and values within 53 bits.
  bool exactInDouble() const {
    if (!rot.isDyadic() || (den & (den - 1)) != 0) return false;
    for (int k = 0; k < 3; ++k)
      if (std::llabs(c[k]) > (i64(1) << 53) || std::llabs(e[k]) > (i64(1) << 53)) return false;
    return true;
  }
  Obb<double> toObb(double unit) const {
    Obb<double> b;
    for (int k = 0; k < 3; ++k) {
      b.center[k] = double(ld(c[k]) / ld(den)) * unit;
      b.halfExtents[k] = double(ld(e[k]) / ld(den)) * unit;
    }
    b.axes = rot.toDouble();
    return b;
  }
  /// For axis-aligned boxes: [c - e, c + e] / den as a double Aabb (exact for dyadic den and <= 53 bits).
  Aabb<double> toAabb(double unit) const {
    Aabb<double> b;
    for (int k = 0; k < 3; ++k) {
      b.min[k] = double(ld(c[k] - e[k]) / ld(den)) * unit;
      b.max[k] = double(ld(c[k] + e[k]) / ld(den)) * unit;
    }
    return b;
  }
  Obb<float> toObbFloat(double unit) const {
    Obb<float> b;
    for (int k = 0; k < 3; ++k) {
      b.center[k] = float(double(ld(c[k]) / ld(den)) * unit);
      b.halfExtents[k] = float(double(ld(e[k]) / ld(den)) * unit);
    }
    b.axes = rot.toFloat();
    return b;
  }
  /// Long double copy (for the ld reference and windows).
  ld maxAbsCoord() const {
    ld r = 0;
    for (int k = 0; k < 3; ++k) r = std::max(r, std::fabs(ld(c[k]) / ld(den)));
    return r;
  }
  ld sumHalf() const { return (ld(e[0]) + ld(e[1]) + ld(e[2])) / ld(den); }
};

// ------------------------------------------------------------------------------------------------
// Results shared by the exact and the long double reference.

inline constexpr int kAxes = 15;

struct SatRef {
  bool separated = false;     // some axis separates (strict >)
  int firstAxis = -1;         // first separating axis in the engine's (Gottschalk's) order
  ld margin = 0;              // max over axes with L != 0 of gap / len
  int marginAxis = -1;
  std::array<int, kAxes> sign{};   // sign of the gap (exact in the integer reference)
  std::array<ld, kAxes> gap{};     // unnormalised gap along L_real (|L_real| = len <= 1)
  std::array<ld, kAxes> len{};     // |L_real|
  std::array<ld, kAxes> infl{};    // sum of half extents multiplied by eps on this axis
  ld extent = 0;                   // |T|_1 + sum of all half extents: the pair's size
  ld absCoord = 0;                 // largest |coordinate| of the two centres: magnitude for rounding
};

/// Axis index -> (i, j) of the edge axis A_i x B_j, or the face.
inline std::string axisName(int k) {
  static const char* const names[kAxes] = {"A0",    "A1",    "A2",    "B0",    "B1",
                                           "B2",    "A0xB0", "A0xB1", "A0xB2", "A1xB0",
                                           "A1xB1", "A1xB2", "A2xB0", "A2xB1", "A2xB2"};
  return k >= 0 && k < kAxes ? names[k] : "none";
}

/// Sum of the half extents that the engine's |R| + eps inflation multiplies on axis k.
template <class V>
ld inflationSum(int k, const V& a, const V& b) {
  if (k < 3) return ld(b[0]) + ld(b[1]) + ld(b[2]);
  if (k < 6) return ld(a[0]) + ld(a[1]) + ld(a[2]);
  const int i = (k - 6) / 3, j = (k - 6) % 3;
  return ld(a[(i + 1) % 3]) + ld(a[(i + 2) % 3]) + ld(b[(j + 1) % 3]) + ld(b[(j + 2) % 3]);
}

inline void finishRef(SatRef& r) {
  r.separated = false;
  r.firstAxis = -1;
  r.marginAxis = -1;
  r.margin = -std::numeric_limits<ld>::infinity();
  for (int k = 0; k < kAxes; ++k) {
    if (r.sign[k] > 0 && !r.separated) {
      r.separated = true;
      r.firstAxis = k;
    }
    if (r.len[k] > 0) {
      const ld m = r.gap[k] / r.len[k];
      if (m > r.margin) {
        r.margin = m;
        r.marginAxis = k;
      }
    }
  }
}

// ------------------------------------------------------------------------------------------------
// 1. Exact integer reference.

inline void checkExactLimits(const ExactBox& b) {
  if (b.den <= 0 || b.den > (i64(1) << 15)) referenceLimitViolated("den");
  if (b.rot.s <= 0 || b.rot.s > (i64(1) << 15)) referenceLimitViolated("rotation denominator");
  for (int k = 0; k < 3; ++k) {
    if (b.e[k] < 0) referenceLimitViolated("negative half extent");
    if (std::llabs(b.c[k]) > (i64(1) << 60) || b.e[k] > (i64(1) << 60)) referenceLimitViolated("magnitude");
  }
}

/// Bounds every intermediate of exactNumerator for the pair (A, B); aborts above 2^124. Returns the
/// bound, so that small pairs can take the 64-bit path (same formulas, exact as long as the bound
/// is below 2^60).
inline ld checkExactPairLimits(const ExactBox& A, const ExactBox& B) {
  ld tmax = 0, emax = 0;
  for (int k = 0; k < 3; ++k) {
    tmax = std::max(tmax, std::fabs(ld(B.c[k]) * A.den) + std::fabs(ld(A.c[k]) * B.den));
    emax = std::max(emax, std::max(ld(A.e[k]) * B.den, ld(B.e[k]) * A.den));
  }
  const ld sA = A.rot.s, sB = B.rot.s, smax = std::max(sA, sB);
  const ld lmax = 2 * sA * sB;                        // |cross product entries| <= 2 sA sB, faces <= s
  const ld b1 = 3 * tmax * lmax * sA * sB;            // |T.L| sA sB
  const ld b2 = 3 * emax * (3 * smax * lmax) * smax;  // pA sB, pB sA
  const ld b = std::max(b1, b2);
  if (!(b < 0x1p124L)) referenceLimitViolated("intermediate above 2^124");
  return b;
}

/// Shared, scaled inputs of the numerators: T' = cB denA - cA denB, EA' = eA denB, EB' = eB denA.
template <class I>
struct ExactPairData {
  std::array<I, 3> T, EA, EB;
  std::array<std::array<I, 3>, 3> MA, MB;
  I sA, sB;
  ExactPairData(const ExactBox& A, const ExactBox& B) {
    for (int r = 0; r < 3; ++r) {
      T[r] = I(B.c[r]) * A.den - I(A.c[r]) * B.den;
      EA[r] = I(A.e[r]) * B.den;
      EB[r] = I(B.e[r]) * A.den;
      for (int q = 0; q < 3; ++q) {
        MA[r][q] = A.rot.m[r][q];
        MB[r][q] = B.rot.m[r][q];
      }
    }
    sA = A.rot.s;
    sB = B.rot.s;
  }
};

template <class I>
struct ExactAxisT {
  std::array<I, 3> L{};
  I kL = 1;  // L_real = L / kL
};

template <class I>
ExactAxisT<I> exactAxisT(const ExactPairData<I>& pd, int k) {
  ExactAxisT<I> d;
  if (k < 3) {
    for (int r = 0; r < 3; ++r) d.L[r] = pd.MA[r][k];
    d.kL = pd.sA;
  } else if (k < 6) {
    for (int r = 0; r < 3; ++r) d.L[r] = pd.MB[r][k - 3];
    d.kL = pd.sB;
  } else {
    const int i = (k - 6) / 3, j = (k - 6) % 3;
    const I u0 = pd.MA[0][i], u1 = pd.MA[1][i], u2 = pd.MA[2][i];
    const I v0 = pd.MB[0][j], v1 = pd.MB[1][j], v2 = pd.MB[2][j];
    d.L = {u1 * v2 - u2 * v1, u2 * v0 - u0 * v2, u0 * v1 - u1 * v0};
    d.kL = pd.sA * pd.sB;
  }
  return d;
}

template <class I>
I absI(I v) {
  return v < 0 ? -v : v;
}

/// num = |T'.L| sA sB - sB sum_q EA'_q |MA_q.L| - sA sum_q EB'_q |MB_q.L| (the generic support
/// function of a box along L; no use of orthonormality).
template <class I>
I exactNumeratorFor(const ExactPairData<I>& pd, const ExactAxisT<I>& ax) {
  const auto& L = ax.L;
  const I tl = pd.T[0] * L[0] + pd.T[1] * L[1] + pd.T[2] * L[2];
  I pA = 0, pB = 0;
  for (int q = 0; q < 3; ++q) {
    if (pd.EA[q] != 0) pA += pd.EA[q] * absI<I>(pd.MA[0][q] * L[0] + pd.MA[1][q] * L[1] + pd.MA[2][q] * L[2]);
    if (pd.EB[q] != 0) pB += pd.EB[q] * absI<I>(pd.MB[0][q] * L[0] + pd.MB[1][q] * L[1] + pd.MB[2][q] * L[2]);
  }
  return absI<I>(tl) * pd.sA * pd.sB - pA * pd.sB - pB * pd.sA;
}

/// The numerator of axis k (see the file comment): gap * D * kL * sA * sB, exact (__int128).
inline i128 exactNumerator(const ExactBox& A, const ExactBox& B, int k) {
  checkExactPairLimits(A, B);
  const ExactPairData<i128> pd(A, B);
  return exactNumeratorFor(pd, exactAxisT(pd, k));
}

template <class I>
void exactAxesInto(const ExactBox& A, const ExactBox& B, int nAxes, std::array<i128, kAxes>& num,
                   std::array<std::array<i128, 3>, kAxes>& L) {
  const ExactPairData<I> pd(A, B);
  for (int k = 0; k < nAxes; ++k) {
    const ExactAxisT<I> ax = exactAxisT(pd, k);
    num[k] = exactNumeratorFor(pd, ax);
    for (int r = 0; r < 3; ++r) L[k][r] = ax.L[r];
  }
}

/// The exact 15-axis separation test of two closed rational boxes. faceAxesOfAOnly: evaluate only
/// A's three face axes (complete for two axis-aligned boxes; the others get len 0, i.e. absent).
inline SatRef exactSat(const ExactBox& A, const ExactBox& B, bool faceAxesOfAOnly = false) {
  checkExactLimits(A);
  checkExactLimits(B);
  const ld bound = checkExactPairLimits(A, B);
  const int nAxes = faceAxesOfAOnly ? 3 : kAxes;
  std::array<i128, kAxes> num{};
  std::array<std::array<i128, 3>, kAxes> L{};
  if (bound < 0x1p60L) exactAxesInto<i64>(A, B, nAxes, num, L);  // same formulas, cannot overflow
  else exactAxesInto<i128>(A, B, nAxes, num, L);
  SatRef r;
  const ld D = ld(A.den) * ld(B.den);
  const ld sA = A.rot.s, sB = B.rot.s, sAsB = sA * sB;
  std::array<ld, 3> ea, eb;
  for (int q = 0; q < 3; ++q) {
    ea[q] = ld(A.e[q]) / ld(A.den);
    eb[q] = ld(B.e[q]) / ld(B.den);
  }
  // 1 / (D kL sA sB) for the three kinds of axis (kL = sA, sB, sA sB).
  const ld inv[3] = {1 / (D * sA * sAsB), 1 / (D * sB * sAsB), 1 / (D * sAsB * sAsB)};
  for (int k = 0; k < kAxes; ++k) {
    if (k >= nAxes) {
      r.sign[k] = 0;
      r.gap[k] = 0;
      r.len[k] = 0;
      r.infl[k] = 0;
      continue;
    }
    r.sign[k] = sign128(num[k]);
    r.gap[k] = toLd(num[k]) * inv[k < 3 ? 0 : k < 6 ? 1 : 2];
    const auto& l = L[k];
    if (l[0] == 0 && l[1] == 0 && l[2] == 0) {
      r.len[k] = 0;
    } else if (k < 6) {
      r.len[k] = 1;  // a column of M has length s exactly
    } else {
      const ld l0 = toLd(l[0]), l1 = toLd(l[1]), l2 = toLd(l[2]);
      r.len[k] = std::sqrt(l0 * l0 + l1 * l1 + l2 * l2) / sAsB;
    }
    r.infl[k] = inflationSum(k, ea, eb);
  }
  ld t1 = 0;
  for (int q = 0; q < 3; ++q) t1 += std::fabs(ld(B.c[q]) / ld(B.den) - ld(A.c[q]) / ld(A.den));
  r.extent = t1 + A.sumHalf() + B.sumHalf();
  r.absCoord = std::max(A.maxAbsCoord(), B.maxAbsCoord());
  finishRef(r);
  return r;
}

/// Axis k of SAT(A, B) named for SAT(B, A): faces change owner; A_i x B_j = -(B_j x A_i).
inline int swapAxisRoles(int k) {
  if (k < 0) return k;
  if (k < 6) return (k + 3) % 6;
  return 6 + 3 * ((k - 6) % 3) + (k - 6) / 3;
}

/// The reference of (B, A) from that of (A, B): every gap is symmetric in the two boxes (|T.L| and
/// rA + rB do not change), only the names of the axes and hence the order change.
inline SatRef swapRoles(const SatRef& r) {
  SatRef s = r;
  for (int k = 0; k < kAxes; ++k) {
    const int m = swapAxisRoles(k);
    s.sign[m] = r.sign[k];
    s.gap[m] = r.gap[k];
    s.len[m] = r.len[k];
    s.infl[m] = r.infl[k];
  }
  finishRef(s);
  return s;
}

/// Self-check of the integer reference by brute force: the gap numerator of axis k recomputed from
/// the projections of the 8 + 8 corners (no |.| formula for the radii). Must equal exactNumerator.
inline i128 exactNumeratorByCorners(const ExactBox& A, const ExactBox& B, int k) {
  const ExactPairData<i128> pd(A, B);
  const ExactAxisT<i128> ax = exactAxisT(pd, k);
  const i128 sA = A.rot.s, sB = B.rot.s;
  // Common scale D sA sB: corner_A = (cA denB) sA sB + sum_q +-EA_q MA_q sB, and likewise for B.
  auto range = [&](const ExactBox& X, i64 otherDen, i128 sOwn, i128 sOther, i128& lo, i128& hi) {
    lo = 0;
    hi = 0;
    for (int n = 0; n < 8; ++n) {
      i128 p = 0;
      for (int r = 0; r < 3; ++r) {
        i128 coord = i128(X.c[r]) * otherDen * sOwn * sOther;
        for (int q = 0; q < 3; ++q) {
          const i128 sg = (n >> q) & 1 ? 1 : -1;
          coord += sg * i128(X.e[q]) * otherDen * X.rot.m[r][q] * sOther;
        }
        p += coord * ax.L[r];
      }
      if (n == 0 || p < lo) lo = p;
      if (n == 0 || p > hi) hi = p;
    }
  };
  i128 loA, hiA, loB, hiB;
  range(A, B.den, sA, sB, loA, hiA);
  range(B, A.den, sB, sA, loB, hiB);
  return std::max(loB - hiA, loA - hiB);
}

// ------------------------------------------------------------------------------------------------
// 2. Long double reference for double boxes.

inline SatRef ldSatRaw(const Vec3<ld>& cA, const Mat3<ld>& A, const Vec3<ld>& a, const Vec3<ld>& cB, const Mat3<ld>& B,
                const Vec3<ld>& b) {
  SatRef r;
  const Vec3<ld> t = cB - cA;
  for (int k = 0; k < kAxes; ++k) {
    Vec3<ld> L;
    if (k < 3)
      L = A.col(k);
    else if (k < 6)
      L = B.col(k - 3);
    else
      L = A.col((k - 6) / 3).cross(B.col((k - 6) % 3));
    const ld tl = std::fabs(t.dot(L));
    ld ra = 0, rb = 0;
    for (int q = 0; q < 3; ++q) {
      ra += a[q] * std::fabs(A.col(q).dot(L));
      rb += b[q] * std::fabs(B.col(q).dot(L));
    }
    r.gap[k] = tl - ra - rb;
    r.len[k] = L.norm();
    // Exactly parallel edges (L == 0) never separate.
    r.sign[k] = r.len[k] == 0 ? 0 : (r.gap[k] > 0) - (r.gap[k] < 0);
    r.infl[k] = inflationSum(k, a, b);
  }
  r.extent = t.cwiseAbs().sum() + a.sum() + b.sum();
  r.absCoord = std::max(cA.cwiseAbs().maxCoeff(), cB.cwiseAbs().maxCoeff());
  finishRef(r);
  return r;
}

template <class T>
SatRef ldSat(const Obb<T>& a, const Obb<T>& b) {
  return ldSatRaw(a.center.template cast<ld>(), a.axes.template cast<ld>(), a.halfExtents.template cast<ld>(),
                     b.center.template cast<ld>(), b.axes.template cast<ld>(), b.halfExtents.template cast<ld>());
}

/// The AABB [min, max] as box A (centre and half extents taken exactly in long double).
template <class T>
SatRef ldSat(const Aabb<T>& a, const Obb<T>& b) {
  const Vec3<ld> mn = a.min.template cast<ld>(), mx = a.max.template cast<ld>();
  return ldSatRaw((mn + mx) / ld(2), Mat3<ld>::Identity(), (mx - mn) / ld(2), b.center.template cast<ld>(),
                     b.axes.template cast<ld>(), b.halfExtents.template cast<ld>());
}

/// Evaluates (A, B) and (B, A); `consistent` tells whether both orders give the same margin (to `tol`,
/// relative to the pair's size) and the same verdict (except at |margin| <= that tolerance, where
/// rounding decides). Returns the (A, B) result.
template <class T>
SatRef ldSatBothWays(const Obb<T>& a, const Obb<T>& b, bool& consistent, ld tol = 1e-15L) {
  const SatRef ab = ldSat(a, b), ba = ldSat(b, a);
  const ld t = tol * (1 + ab.extent + ab.absCoord);
  // The verdicts may differ only where the margin is zero up to the long double rounding.
  consistent = std::fabs(ab.margin - ba.margin) <= t && (ab.separated == ba.separated || std::fabs(ab.margin) <= t);
  return ab;
}

// ------------------------------------------------------------------------------------------------
// 3. The inflated model: what a SAT with |R| + eps and a rounding slack answers, up to a window.

enum class Expect { Overlap, Separated, Either };

inline const char* expectName(Expect e) {
  return e == Expect::Overlap ? "overlap" : e == Expect::Separated ? "separated" : "either";
}

/// A SAT's documented tolerance as parameters: it separates on axis k iff
///   gap_k > eps * infl_k + slackRel * (|T|_1 + sum a + sum b) + slackAbs
/// (sat.h: eps = kParallelEpsilon, slackRel = kRoundingSlack, slackAbs = the input rounding of
/// satAabbObb; FCL: eps = 1e-6 and no slack; the pure exact test: all zero).
struct SatModel {
  ld eps = 0;
  ld slackRel = 0;
  ld slackAbs = 0;
};

inline ld thresholdOf(const SatRef& r, const SatModel& m, int k) {
  return m.eps * r.infl[k] + m.slackRel * r.extent + m.slackAbs;
}

/// window: absolute rounding window on the unnormalised gap; strictNoMiss: an axis with exact gap
/// <= 0 can never separate (the tolerance covers all rounding, or the inputs are exact). Face-only:
/// only axes 0..2 exist (AABB-AABB).
inline Expect expectInflated(const SatRef& r, const SatModel& m, ld window, bool strictNoMiss, bool faceOnlyAabb = false) {
  bool sure = false, possible = false;
  for (int k = 0; k < (faceOnlyAabb ? 3 : kAxes); ++k) {
    if (r.len[k] == 0) continue;
    const ld thr = thresholdOf(r, m, k);
    if (r.gap[k] > thr + window) sure = true;
    if (r.gap[k] > thr - window && (!strictNoMiss || r.sign[k] > 0)) possible = true;
  }
  return sure ? Expect::Separated : possible ? Expect::Either : Expect::Overlap;
}

/// When a SAT reports separation on `axis`: that axis must plausibly separate, and no earlier axis may
/// surely separate (early exit in the engine's order). Returns "" or a reason.
inline std::string checkReportedAxis(const SatRef& r, int axis, const SatModel& m, ld window, bool strictNoMiss) {
  if (axis < 0 || axis >= kAxes) return "axis index out of range";
  if (!(r.gap[axis] > thresholdOf(r, m, axis) - window)) return "reported axis " + axisName(axis) + " does not separate";
  if (strictNoMiss && r.sign[axis] <= 0) return "reported axis " + axisName(axis) + " has exact gap <= 0";
  for (int k = 0; k < axis; ++k)
    if (r.len[k] > 0 && r.gap[k] > thresholdOf(r, m, k) + window)
      return "earlier axis " + axisName(k) + " surely separates but " + axisName(axis) + " was reported";
  return "";
}

}  // namespace nestwalk::testref
