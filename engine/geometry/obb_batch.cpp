// Batched OBB-OBB and AABB tests in float SIMD with exact double fallback (see obb_batch.h).
//
// Error analysis of the float filter (u = 2^-24, the unit roundoff of float)
// --------------------------------------------------------------------------
// For each pair the double test (sat.h) computes, per axis, a projected distance |d| and a radius
// r, and separates iff |d| > r on some axis. The float kernel computes g = |d| - r on every axis
// from the conservative float boxes (toFloatConservative) and bounds how far its g can be from the
// double one, with these float quantities of the lane:
//   tn = |t0| + |t1| + |t2|   (t = A^T (cB - cA); tn >= the Euclidean distance of the centres)
//   Sa = a0 + a1 + a2, Sb = b0 + b1 + b2   (float half extents, inflated)
//   C  = |cA|_1 + |cB|_1      (magnitude of the coordinates; ObbPairBatch has cA = 0)
//   M  = tn + Sa + Sb + C.
// Sources of difference, for boxes whose axes are orthonormal to 1e-6 (checked, see below):
//  - R = A^T B: entries of A and B rounded (u relative each), 3-term float dot products (3u of
//    sum |A||B| <= 1): |dR| <= 5.1u.
//  - cB - cA: centres rounded (u |c|), float subtraction (u |diff|); t = A^T diff: axes rounded
//    (u) and 3-term dot products (3u): |dt_i| <= u C + 6u tn.
//  - d on face A_i (t_i): <= u C + 6u tn; on face B_j (sum_k t_k R_kj): <= sqrt3 (u C + 6u tn)
//    + (5.1 + 3)u tn <= 1.8u C + 18.5u tn; on edge axes (t R - t R): <= sqrt2 (u C + 6u tn)
//    + (5.1 + 2)u tn <= 1.5u C + 15.6u tn.
//  - radii: float uses |R| + 1e-6 (kParallelEpsilon<float>), double |R| + 1e-12. Since
//    1e-6 - 1e-12 > |dR| and the float half extents are >= the double ones, the float radius before
//    rounding is >= the double one (what makes "separated" safe). It is larger by at most: the
//    inflation of the half extents (<= 2u |c|_1 + 9.5u S per half extent, see
//    toFloatConservative; times coefficients summing to <= sqrt3 per box: <= 3.5u C + 16.5u (Sa+Sb)),
//    plus |dR| (Sa + Sb) <= 5.1u (Sa + Sb), plus the epsilon difference < 1e-6 (Sa + Sb).
//  - float rounding of a radius (sums of <= 6 positive terms): <= 6u (Sa + Sb); of g = |d| - r:
//    <= u (|d| + r) <= 2u M; on the double side, its rounding (< 1e-15 M) and the slack sat.h
//    adds to every comparison (kRoundingSlack<double> = 1e-12 times magnitudes <= 3M): < 4e-12 M.
// The kernel's slacks are
//   sep  = kSepRel * M + kAbsSlack,   kSepRel = 64u ~ 3.8e-6,   kAbsSlack = 1e-30,
//   band = sep + kParallelEpsilon<float> * (Sa + Sb):
//  - "surely separated" (max g > sep) needs sep >= (1.8u C + 18.5u tn) + 6u (Sa+Sb) + 2u M
//    + 4e-12 M, which is <= 21u M: margin 3x;
//  - "surely overlapping" (max g < -band) needs band >= (1.8u C + 18.5u tn) + (3.5u C
//    + 16.5u (Sa+Sb)) + 5.1u (Sa+Sb) + 6u (Sa+Sb) + 2u M + 1e-15 M + 1e-6 (Sa+Sb), which is
//    <= 30u M + 1e-6 (Sa+Sb): margin 2x on the rounding part (sat.h's slack only helps here).
// (Measured: the exactness tests start failing with kSepRel = 1u, and pass down to 4u.)
// Computing sep and band in float (relative error < 8u on values ~64u M) is inside the margins.
// kAbsSlack covers the absolute rounding errors of subnormal numbers (< 2^-149 per operation).
// FMA contraction (the AVX2 path) only removes roundings: the bounds hold with or without it.
// The price of the epsilon term in the band: a pair whose boxes have exactly parallel edges (the
// edge axis degenerates to |d| ~ 0, r ~ 1e-6 S) is never "surely overlapping" and goes to double,
// except when both boxes' axes are exactly signed permutations (the identity above all), whose
// edge axes can be left out (see satLanes).
// Boxes that break the assumptions (non-finite or huge numbers, negative half extents, axes not
// orthonormal to 1e-6) are never decided in float.
//
// Paths: the kernels are written once with GCC vector extensions and compiled twice, 4 lanes at a
// time for the portable x86-64-v2 build (SSE) and 8 lanes with AVX2 + FMA, chosen at run time
// (__builtin_cpu_supports); NESTWALK_SIMD=portable in the environment forces the SSE path. The
// double fallbacks are compiled for the base instruction set only (no FMA contraction), so they
// are the very functions of sat.h / nested.h.
#include "nestwalk/geometry/obb_batch.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <stdexcept>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace nestwalk {

namespace {

constexpr double kFloatRoundoff = 0x1p-24;  // u: |fl(x) - x| <= u |x| for normal floats
// Growth per metre of half extent (unitless) added to the float box's bound for the rounding of
// the bound's own double arithmetic (a few 2^-53, ~1e-16): 1e-12 covers it with room and adds
// 1 pm to a 1 m box.
constexpr double kBoundArithmeticMargin = 1e-12;

/// The smallest float >= x (x itself when representable).
float roundUp(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}
/// The largest float <= x.
float roundDown(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

}  // namespace

// The float box: centre and axes rounded to nearest; each half extent enlarged by
//   2 * disp + (4u + 1e-12) * (e0 + e1 + e2),   disp = |c - fl(c)|_1 + sum_j e_j |A_j - fl(A_j)|_1,
// then rounded upward. disp bounds (in the Euclidean norm, as the L1 norm does) how far any point
// c + A x (|x_k| <= e_k) of the double box moves when c and A are replaced by their float
// roundings; the factor 2 and the (4u + 1e-12) sum term cover the non-orthonormality of the float
// axes (their columns have norms within 1 + u and pairwise dot products within u + 1e-13), so
// the double box lies inside the float one both as the parallelepiped fl(c) + fl(A) y,
// |y_k| <= ef_k, and in the sense of Obb::contains (fl(A)^T (p - fl(c)), within ef_k).
// Since |c - fl(c)|_1 <= u |c|_1 and |A_j - fl(A_j)|_1 <= sqrt3 u, the enlargement is at most
// 2u |c|_1 + 9.5u (e0 + e1 + e2) (the figure the kernel's error analysis uses).
Obb<float> toFloatConservative(const Obb<double>& b) {
  Obb<float> f;
  f.center = b.center.cast<float>();
  f.axes = b.axes.cast<float>();
  double disp = 0, esum = 0;
  for (int k = 0; k < 3; ++k) disp += std::abs(b.center[k] - double(f.center[k]));
  for (int j = 0; j < 3; ++j) {
    double colErr = 0;
    for (int k = 0; k < 3; ++k) colErr += std::abs(b.axes(k, j) - double(f.axes(k, j)));
    disp += std::abs(b.halfExtents[j]) * colErr;
    esum += std::abs(b.halfExtents[j]);
  }
  const double grow = 2 * disp + (4 * kFloatRoundoff + kBoundArithmeticMargin) * esum;
  for (int k = 0; k < 3; ++k) f.halfExtents[k] = roundUp(b.halfExtents[k] + grow);
  return f;
}

Aabb<float> toFloatConservative(const Aabb<double>& b) {
  Aabb<float> f;
  for (int k = 0; k < 3; ++k) {
    f.min[k] = roundDown(b.min[k]);
    f.max[k] = roundUp(b.max[k]);
  }
  return f;
}

namespace {

// ---------------------------------------------------------------------------------------------
// The 15-axis SAT kernel on W lanes (W = 4: SSE, the portable path; W = 8: AVX2 + FMA), written
// with GCC vector extensions; the template is always inlined, so each instantiation is compiled
// for the instruction set of the function that calls it.

// The helpers below return 32-byte vectors by value; they are always inlined, so the ABI note
// GCC gives for them (AVX vectors in a function compiled without AVX) does not apply.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

typedef float v4f __attribute__((vector_size(16)));
typedef std::int32_t v4i __attribute__((vector_size(16)));
typedef float v8f __attribute__((vector_size(32)));
typedef std::int32_t v8i __attribute__((vector_size(32)));

constexpr float kSepRel = 64.0f * 0x1p-24f;  // 64u, see the analysis at the top of the file
// What the analysis assumes of sat.h: the float epsilon exceeds the error of a float R entry
// (5.1u = 3.1e-7) plus the double epsilon, and the double test's slack is far below 1u.
static_assert(kParallelEpsilon<float> - kParallelEpsilon<double> > 4e-7f);
static_assert(kParallelEpsilon<float> <= 1e-5f);
static_assert(kRoundingSlack<double> <= 1e-10);
constexpr float kAbsSlack = 1e-30f;
constexpr float kEpsF = kParallelEpsilon<float>;
// Lanes with numbers beyond this are left to double (keeps every float product finite).
constexpr double kMaxCoordinate = 1e18;
constexpr double kMaxAxesError = 1e-6;

template <class V>
[[gnu::always_inline]] inline V load(const float* p) {
  V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

template <class V, class VI>
[[gnu::always_inline]] inline V vabs(const V& x) {
  return reinterpret_cast<V>(reinterpret_cast<VI>(x) & 0x7fffffff);
}

template <class V>
[[gnu::always_inline]] inline V vmax(const V& a, const V& b) {
  return a > b ? a : b;
}

/// Lanes l0 .. l0 + W - 1 of the blocks: box A against box B (kACentred: A's centres are taken to
/// be the origin, the pair's local frame). Writes, per lane, -1/0 to sepOut (surely separated) and
/// ovOut (surely overlapping); neither set means uncertain. Bit l of `permLanes` says that both
/// boxes of lane l have axes that are exactly signed permutations (e.g. the identity): then R is
/// exactly a signed permutation in double as in float, and each edge axis either degenerates
/// (d exactly 0 in double: it never separates) or is one of A's face axes, tested with |d| = |t_m|
/// exactly and a radius within 1e-12 (Sa + Sb) of that face's; so the edge axes are left out of g
/// (a "surely overlapping" face, band >> 1e-12 (Sa + Sb), implies the edge does not separate either).
/// Without this the degenerate edges (g = -1e-6 S) would leave every overlapping axis-aligned pair
/// uncertain.
template <class V, class VI, bool kACentred>
[[gnu::always_inline]] inline void satLanes(const ObbBlock& A, const ObbBlock& B, int l0, unsigned permLanes,
                                            std::int32_t* sepOut, std::int32_t* ovOut) {
  // A(r, c) = axes[3 r + c].
  const V a00 = load<V>(A.axes[0] + l0), a01 = load<V>(A.axes[1] + l0), a02 = load<V>(A.axes[2] + l0);
  const V a10 = load<V>(A.axes[3] + l0), a11 = load<V>(A.axes[4] + l0), a12 = load<V>(A.axes[5] + l0);
  const V a20 = load<V>(A.axes[6] + l0), a21 = load<V>(A.axes[7] + l0), a22 = load<V>(A.axes[8] + l0);
  const V b00 = load<V>(B.axes[0] + l0), b01 = load<V>(B.axes[1] + l0), b02 = load<V>(B.axes[2] + l0);
  const V b10 = load<V>(B.axes[3] + l0), b11 = load<V>(B.axes[4] + l0), b12 = load<V>(B.axes[5] + l0);
  const V b20 = load<V>(B.axes[6] + l0), b21 = load<V>(B.axes[7] + l0), b22 = load<V>(B.axes[8] + l0);
  const V ea0 = load<V>(A.halfExtents[0] + l0), ea1 = load<V>(A.halfExtents[1] + l0),
          ea2 = load<V>(A.halfExtents[2] + l0);
  const V eb0 = load<V>(B.halfExtents[0] + l0), eb1 = load<V>(B.halfExtents[1] + l0),
          eb2 = load<V>(B.halfExtents[2] + l0);
  V c0 = load<V>(B.center[0] + l0), c1 = load<V>(B.center[1] + l0), c2 = load<V>(B.center[2] + l0);
  V cmag = vabs<V, VI>(c0) + vabs<V, VI>(c1) + vabs<V, VI>(c2);  // C of the analysis
  if constexpr (!kACentred) {
    const V ca0 = load<V>(A.center[0] + l0), ca1 = load<V>(A.center[1] + l0), ca2 = load<V>(A.center[2] + l0);
    cmag += vabs<V, VI>(ca0) + vabs<V, VI>(ca1) + vabs<V, VI>(ca2);
    c0 -= ca0;
    c1 -= ca1;
    c2 -= ca2;
  }

  // t = A^T (cB - cA), R = A^T B.
  const V t0 = a00 * c0 + a10 * c1 + a20 * c2;
  const V t1 = a01 * c0 + a11 * c1 + a21 * c2;
  const V t2 = a02 * c0 + a12 * c1 + a22 * c2;
  const V r00 = a00 * b00 + a10 * b10 + a20 * b20;
  const V r01 = a00 * b01 + a10 * b11 + a20 * b21;
  const V r02 = a00 * b02 + a10 * b12 + a20 * b22;
  const V r10 = a01 * b00 + a11 * b10 + a21 * b20;
  const V r11 = a01 * b01 + a11 * b11 + a21 * b21;
  const V r12 = a01 * b02 + a11 * b12 + a21 * b22;
  const V r20 = a02 * b00 + a12 * b10 + a22 * b20;
  const V r21 = a02 * b01 + a12 * b11 + a22 * b21;
  const V r22 = a02 * b02 + a12 * b12 + a22 * b22;
  const V q00 = vabs<V, VI>(r00) + kEpsF, q01 = vabs<V, VI>(r01) + kEpsF, q02 = vabs<V, VI>(r02) + kEpsF;
  const V q10 = vabs<V, VI>(r10) + kEpsF, q11 = vabs<V, VI>(r11) + kEpsF, q12 = vabs<V, VI>(r12) + kEpsF;
  const V q20 = vabs<V, VI>(r20) + kEpsF, q21 = vabs<V, VI>(r21) + kEpsF, q22 = vabs<V, VI>(r22) + kEpsF;
  const V at0 = vabs<V, VI>(t0), at1 = vabs<V, VI>(t1), at2 = vabs<V, VI>(t2);

  // g = max over the 15 axes of |d| - (rA + rB).
  // A's face axes.
  V g = at0 - (ea0 + (eb0 * q00 + eb1 * q01 + eb2 * q02));
  g = vmax(g, at1 - (ea1 + (eb0 * q10 + eb1 * q11 + eb2 * q12)));
  g = vmax(g, at2 - (ea2 + (eb0 * q20 + eb1 * q21 + eb2 * q22)));
  // B's face axes.
  g = vmax(g, vabs<V, VI>(t0 * r00 + t1 * r10 + t2 * r20) - ((ea0 * q00 + ea1 * q10 + ea2 * q20) + eb0));
  g = vmax(g, vabs<V, VI>(t0 * r01 + t1 * r11 + t2 * r21) - ((ea0 * q01 + ea1 * q11 + ea2 * q21) + eb1));
  g = vmax(g, vabs<V, VI>(t0 * r02 + t1 * r12 + t2 * r22) - ((ea0 * q02 + ea1 * q12 + ea2 * q22) + eb2));
  V ge = V{} - std::numeric_limits<float>::infinity();  // over the edge axes
  // Edge axes A_i x B_j: ra = a[i1] |R(i2,j)| + a[i2] |R(i1,j)|, rb = b[j1] |R(i,j2)| + b[j2] |R(i,j1)|,
  // d = t[i2] R(i1,j) - t[i1] R(i2,j), with i1 = i+1, i2 = i+2, j1 = j+1, j2 = j+2 (mod 3).
  ge = vmax(ge, vabs<V, VI>(t2 * r10 - t1 * r20) - ((ea1 * q20 + ea2 * q10) + (eb1 * q02 + eb2 * q01)));
  ge = vmax(ge, vabs<V, VI>(t2 * r11 - t1 * r21) - ((ea1 * q21 + ea2 * q11) + (eb2 * q00 + eb0 * q02)));
  ge = vmax(ge, vabs<V, VI>(t2 * r12 - t1 * r22) - ((ea1 * q22 + ea2 * q12) + (eb0 * q01 + eb1 * q00)));
  ge = vmax(ge, vabs<V, VI>(t0 * r20 - t2 * r00) - ((ea2 * q00 + ea0 * q20) + (eb1 * q12 + eb2 * q11)));
  ge = vmax(ge, vabs<V, VI>(t0 * r21 - t2 * r01) - ((ea2 * q01 + ea0 * q21) + (eb2 * q10 + eb0 * q12)));
  ge = vmax(ge, vabs<V, VI>(t0 * r22 - t2 * r02) - ((ea2 * q02 + ea0 * q22) + (eb0 * q11 + eb1 * q10)));
  ge = vmax(ge, vabs<V, VI>(t1 * r00 - t0 * r10) - ((ea0 * q10 + ea1 * q00) + (eb1 * q22 + eb2 * q21)));
  ge = vmax(ge, vabs<V, VI>(t1 * r01 - t0 * r11) - ((ea0 * q11 + ea1 * q01) + (eb2 * q20 + eb0 * q22)));
  ge = vmax(ge, vabs<V, VI>(t1 * r02 - t0 * r12) - ((ea0 * q12 + ea1 * q02) + (eb0 * q21 + eb1 * q20)));

  {
    VI lanes;
    for (int l = 0; l < int(sizeof(V) / sizeof(float)); ++l) lanes[l] = std::int32_t(1u << (l0 + l));
    const VI perm = (lanes & std::int32_t(permLanes)) != 0;
    g = vmax(g, perm ? V{} - std::numeric_limits<float>::infinity() : ge);
  }

  // Slacks (see the top of the file).
  const V sab = (ea0 + ea1 + ea2) + (eb0 + eb1 + eb2);
  const V m = ((at0 + at1 + at2) + sab) + cmag;
  const V sep = kSepRel * m + kAbsSlack;
  const V negBand = -(sep + kEpsF * sab);
  const VI sepMask = g > sep;
  const VI ovMask = g < negBand;
  std::memcpy(sepOut + l0, &sepMask, sizeof sepMask);
  std::memcpy(ovOut + l0, &ovMask, sizeof ovMask);
}

/// The float pass over all blocks: writes out[k] for the lanes it decides (and a placeholder
/// for the others), and appends the uncertain ones to `uncertain`.
template <class V, class VI>
[[gnu::always_inline]] inline void satBlocks(const ObbBlock* a, const ObbBlock* b, const std::uint8_t* forced,
                                             const std::uint8_t* perm, std::size_t n, std::uint8_t* out,
                                             std::vector<std::uint32_t>& uncertain) {
  constexpr int kW = int(sizeof(V) / sizeof(float));
  const std::size_t blocks = (n + kBatchLanes - 1) / kBatchLanes;
  for (std::size_t blk = 0; blk < blocks; ++blk) {
    alignas(32) std::int32_t sep[kBatchLanes], ov[kBatchLanes];
    for (int l0 = 0; l0 < kBatchLanes; l0 += kW) satLanes<V, VI, true>(a[blk], b[blk], l0, perm[blk], sep, ov);
    const std::size_t base = blk * kBatchLanes;
    unsigned unsure = forced[blk];
    if (n - base >= std::size_t(kBatchLanes)) {
      for (int l = 0; l < kBatchLanes; ++l) {
        out[base + l] = std::uint8_t(ov[l] & 1);
        unsure |= unsigned((ov[l] | sep[l]) == 0) << l;
      }
    } else {
      const int lanes = int(n - base);
      for (int l = 0; l < lanes; ++l) {
        out[base + l] = std::uint8_t(ov[l] & 1);
        unsure |= unsigned((ov[l] | sep[l]) == 0) << l;
      }
      unsure &= (1u << lanes) - 1u;
    }
    while (unsure) {
      uncertain.push_back(std::uint32_t(base + unsigned(__builtin_ctz(unsure))));
      unsure &= unsure - 1u;
    }
  }
}

using SatBlocksFn = void (*)(const ObbBlock*, const ObbBlock*, const std::uint8_t*, const std::uint8_t*, std::size_t,
                             std::uint8_t*, std::vector<std::uint32_t>&);

void satBlocksPortable(const ObbBlock* a, const ObbBlock* b, const std::uint8_t* forced, const std::uint8_t* perm,
                       std::size_t n, std::uint8_t* out, std::vector<std::uint32_t>& uncertain) {
  satBlocks<v4f, v4i>(a, b, forced, perm, n, out, uncertain);
}

#if defined(__x86_64__) && defined(__GNUC__)
#define NESTWALK_HAVE_AVX2_PATH 1
[[gnu::target("avx2,fma")]] void satBlocksAvx2(const ObbBlock* a, const ObbBlock* b, const std::uint8_t* forced,
                                               const std::uint8_t* perm, std::size_t n, std::uint8_t* out,
                                               std::vector<std::uint32_t>& uncertain) {
  satBlocks<v8f, v8i>(a, b, forced, perm, n, out, uncertain);
}
#endif

/// Stages 2 and 3 of the nested test in float for kBatchLanes gathered boxes `b`: res[0] / res[1]
/// are the surely separated / surely overlapping masks of (viewer's outer AABB as an OBB, box's
/// inner OBB), res[2] / res[3] those of (viewer's inner OBB, box's inner OBB). perm2 / perm3: the
/// lanes whose two boxes have signed-permutation axes, for each stage (see satLanes).
template <class V, class VI>
[[gnu::always_inline]] inline void stages23(const ObbBlock& viewerOuter, const ObbBlock& viewerInner,
                                            const ObbBlock& b, unsigned perm2, unsigned perm3,
                                            std::int32_t (*res)[kBatchLanes]) {
  constexpr int kW = int(sizeof(V) / sizeof(float));
  for (int l0 = 0; l0 < kBatchLanes; l0 += kW) {
    satLanes<V, VI, false>(viewerOuter, b, l0, perm2, res[0], res[1]);
    satLanes<V, VI, false>(viewerInner, b, l0, perm3, res[2], res[3]);
  }
}

using Stages23Fn = void (*)(const ObbBlock&, const ObbBlock&, const ObbBlock&, unsigned, unsigned,
                            std::int32_t (*)[kBatchLanes]);

void stages23Portable(const ObbBlock& viewerOuter, const ObbBlock& viewerInner, const ObbBlock& b, unsigned perm2,
                      unsigned perm3, std::int32_t (*res)[kBatchLanes]) {
  stages23<v4f, v4i>(viewerOuter, viewerInner, b, perm2, perm3, res);
}

#ifdef NESTWALK_HAVE_AVX2_PATH
[[gnu::target("avx2,fma")]] void stages23Avx2(const ObbBlock& viewerOuter, const ObbBlock& viewerInner,
                                              const ObbBlock& b, unsigned perm2, unsigned perm3,
                                              std::int32_t (*res)[kBatchLanes]) {
  stages23<v8f, v8i>(viewerOuter, viewerInner, b, perm2, perm3, res);
}
#endif

/// Whether to run the AVX2 + FMA kernels: when the processor has them, unless the environment
/// variable NESTWALK_SIMD is "portable" (read on every call, so that tests can run both paths).
bool useAvx2() {
#ifdef NESTWALK_HAVE_AVX2_PATH
  static const bool avx2 = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  }();
  if (!avx2) return false;
  const char* env = std::getenv("NESTWALK_SIMD");
  return !(env && std::strcmp(env, "portable") == 0);
#else
  return false;
#endif
}

SatBlocksFn pickSatBlocks() {
#ifdef NESTWALK_HAVE_AVX2_PATH
  if (useAvx2()) return satBlocksAvx2;
#endif
  return satBlocksPortable;
}

Stages23Fn pickStages23() {
#ifdef NESTWALK_HAVE_AVX2_PATH
  if (useAvx2()) return stages23Avx2;
#endif
  return stages23Portable;
}

/// Double decision of one pair, kept out of line so that it is compiled for the base instruction
/// set (no FMA contraction) whatever the caller.
[[gnu::noinline]] bool decideInDouble(const Obb<double>& a, const Obb<double>& b) {
  return satObbObb<double>(a, b).overlap;
}

/// Whether the float analysis applies to the box (see the top of the file).
bool floatFriendly(const Obb<double>& d, const Obb<float>& f) {
  for (int k = 0; k < 3; ++k) {
    if (!(std::abs(d.center[k]) <= kMaxCoordinate) || !(d.halfExtents[k] >= 0) ||
        !(d.halfExtents[k] <= kMaxCoordinate) || !std::isfinite(f.halfExtents[k]))
      return false;
  }
  if (!d.axes.allFinite() || !(axesError(d.axes) <= kMaxAxesError)) return false;
  return f.axes.cwiseAbs().maxCoeff() <= 2.0f;
}

/// Whether the axes are exactly a signed permutation matrix (the identity, or axes swapped and
/// flipped): such axes are exact in float, and products of them are exact in both precisions.
bool isSignedPermutation(const Mat3<double>& m) {
  for (int r = 0; r < 3; ++r) {
    int rowOnes = 0, colOnes = 0;
    for (int c = 0; c < 3; ++c) {
      if (std::abs(m(r, c)) == 1.0) ++rowOnes;
      else if (m(r, c) != 0.0) return false;
      if (std::abs(m(c, r)) == 1.0) ++colOnes;
    }
    if (rowOnes != 1 || colOnes != 1) return false;
  }
  return true;
}

void storeLane(ObbBlock& blk, int lane, const Obb<float>& f) {
  for (int k = 0; k < 3; ++k) {
    blk.center[k][lane] = f.center[k];
    blk.halfExtents[k][lane] = f.halfExtents[k];
  }
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) blk.axes[3 * r + c][lane] = f.axes(r, c);
}

ObbBlock paddingObbBlock() {
  // Unit boxes at the origin: harmless finite numbers; the lanes are never read.
  ObbBlock blk{};
  const Obb<float> unit{Vec3<float>::Zero(), Mat3<float>::Identity(), Vec3<float>::Ones()};
  for (int l = 0; l < kBatchLanes; ++l) storeLane(blk, l, unit);
  return blk;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// ObbPairBatch

ObbPairBatch::ObbPairBatch(const std::vector<std::pair<Obb<double>, Obb<double>>>& pairs) {
  const std::size_t n = pairs.size();
  const std::size_t blocks = (n + kBatchLanes - 1) / kBatchLanes;
  pairs_.reserve(n);
  a_.assign(blocks, paddingObbBlock());
  b_.assign(blocks, paddingObbBlock());
  forced_.assign(blocks, 0);
  perm_.assign(blocks, 0);
  for (std::size_t k = 0; k < n; ++k) {
    // The local frame of A: satObbObb computes b.center - a.center first, so the double verdict on
    // the shifted pair is bit for bit the verdict on the original one.
    Obb<double> la = pairs[k].first, lb = pairs[k].second;
    lb.center = pairs[k].second.center - pairs[k].first.center;
    la.center.setZero();
    const Obb<float> fa = toFloatConservative(la), fb = toFloatConservative(lb);
    const std::size_t blk = k / kBatchLanes;
    const int lane = int(k % kBatchLanes);
    storeLane(a_[blk], lane, fa);
    storeLane(b_[blk], lane, fb);
    if (!floatFriendly(la, fa) || !floatFriendly(lb, fb)) forced_[blk] |= std::uint8_t(1u << lane);
    if (isSignedPermutation(la.axes) && isSignedPermutation(lb.axes)) perm_[blk] |= std::uint8_t(1u << lane);
    pairs_.emplace_back(la, lb);
  }
}

std::size_t ObbPairBatch::test(std::uint8_t* out) const {
  std::vector<std::uint32_t> uncertain;
  pickSatBlocks()(a_.data(), b_.data(), forced_.data(), perm_.data(), pairs_.size(), out, uncertain);
  for (const std::uint32_t k : uncertain) out[k] = decideInDouble(pairs_[k].first, pairs_[k].second) ? 1 : 0;
  return uncertain.size();
}

// ---------------------------------------------------------------------------------------------
// testBoxPairs: testBoxPair's three stages per lane, with the first separating axis.
//
// Each stage runs its axes in testBoxPair's order and classifies each axis per lane with the
// float error bound: g > sep, surely separating in double; g < -band, surely not; else open.
// The lane's answer for a stage is sure when every axis before the first one that is not surely
// clear is surely clear and that one surely separates (or every axis is surely clear: no
// separating axis). The boxes are rounded to float here, cheaply: A's centre is the origin
// (the pair's local frame, as testBoxPair), B's centre is fl(cB - cA), the axes are rounded to
// nearest and every half extent becomes fl(e) + kGrowCentre |fl(c)|_1 + kGrowSize (sum fl(e)) +
// kGrowAbs, computed in float. That exceeds toFloatConservative's enlargement 2 disp +
// (4u + 1e-12) sum e (<= 2u |c|_1 + 7.5u sum e, see above) after the roundings of fl(e) (u e),
// of the growth's own float arithmetic (< 6u of it) and of the sum (u), so the float box contains
// the double one; and it is at most 2.6u C + 14u S (against 2u C + 9.5u S in the analysis above).
// Error bounds per axis, g_float against g_double (M = 2C + SX + S, C = |fl(cB - cA)|_1, S the
// four boxes' half extents: the two OBBs' and the two AABBs'):
//  - stage 3 (OBB-OBB): the analysis above with the larger enlargement: < 40u M + 1e-6 S;
//  - stage 2 (AABB-OBB): the AABB's half extents sum_j |fl(A)_kj| fe_j differ from the double
//    ones (|A| e + aabbOf's padding, ~1e-15 relative) by <= sqrt3 (2.6u C + 14u S) + u S + 5.2u S
//    < 4.5u C + 30.5u S each, i.e. < 7.8u C + 53u S on a radius (coefficients summing to
//    <= sqrt3), on top of the stage-3 terms (R = Y exactly rounded, t = fl(c) with no rotation):
//    < 100u M + 1e-6 S;
//  - stage 1 (AABB-AABB, |c_k| against hA_k + hB_k): u C + 2 (4.5u C + 30.5u S) + 2u M < 70u M.
// kPairSepRel = 256u keeps a margin of 2.5x on the worst (stage 2), and band = sep + 1e-6 S
// covers the epsilon difference. The stage-2 AABB is A's (or B's, when only B is axis aligned:
// testBoxPair then swaps the roles; the sign of t does not matter to |d|).
// Exactly parallel edges: an edge axis A_i x B_j whose R(i1, j) and R(i2, j) are both exact zeros
// in double has d = 0 and never separates there; the kernel skips it where the float data show it:
// stage 2, R = the OBB's axes, is exact in float (fl(x) = 0 means |x| <= 2^-150, and then |d| in
// double is < 1e-40 |t|, far below sat.h's slack 1e-12 |t|_1); stage 3 when every product of
// R(i1, j) and R(i2, j) has a float factor that is zero (structural zeros: boxes turned about a
// common axis, e.g. both about z). Without this, every overlapping pair of boxes turned about
// the vertical would be left uncertain.

namespace {

constexpr float kPairSepRel = 256.0f * 0x1p-24f;  // 256u, see above (unitless, relative to M)
constexpr float kGrowCentre = 2.5f * 0x1p-24f;    // growth of a half extent per |c|_1 (see above)
constexpr float kGrowSize = 12.0f * 0x1p-24f;     // growth per metre of summed half extents
constexpr float kGrowAbs = 1e-36f;                // m: covers float underflow of tiny half extents
// Lanes outside these are answered in double: products stay finite, and the axes are orthonormal
// to 1e-6 in double (the float check, accurate to ~5u = 3e-7, is kept at 5e-7).
constexpr float kMaxCoordinateF = 1e18f;
constexpr float kMaxFloatAxesError = 5e-7f;
constexpr std::int32_t kUnsure = -2;  // a stage's lane code: no sure answer (else axis or kNoAxis)

/// kBatchLanes pairs in A's local frame, rounded to float: row r holds field r of every lane, the
/// fields in the memory order of Obb<double> (centre, axes column by column, half extents): rows
/// 0..14 box A (its centre rows are not used: A's centre is the origin), rows 16..30 box B, with
/// B's centre replaced by cB - cA (computed in double).
struct alignas(32) PairBlock {
  float row[32][kBatchLanes];
};
constexpr int kRowAxes = 3, kRowExtents = 12, kRowB = 16;  // (axes(r, c) at kRowAxes + 3 c + r)
static_assert(sizeof(Obb<double>) == 15 * sizeof(double), "Obb<double>: centre, axes, half extents, unpadded");

/// A stage's answer per lane from its axes' g = |d| - r in testing order: the first axis that is not
/// surely clear (g >= -band) if it surely separates (g > sep), kNoAxis when every axis is surely
/// clear, else kUnsure. Scanned backwards, two compares and two selects per axis. NaN: kUnsure.
template <class V, class VI, int N>
[[gnu::always_inline]] inline VI stageCode(const V (&g)[N], const V& sep, const V& negBand) {
  VI code = VI{} + std::int32_t(kNoAxis);
#pragma GCC unroll 15
  for (int i = N - 1; i >= 0; --i) {
    const VI candidate = g[i] > sep ? VI{} + i : VI{} + kUnsure;
    code = g[i] < negBand ? code : candidate;
  }
  return code;
}

template <class VI>
[[gnu::always_inline]] inline bool anyLane(const VI& m) {
  for (int l = 0; l < int(sizeof(VI) / sizeof(std::int32_t)); ++l)
    if (m[l]) return true;
  return false;
}

/// g = |d| - (rA + rB) on the 15 axes of sat.h in its order (A's faces, B's faces, A_i x B_j), B
/// given in A's frame by t and R; zero[i][j]: lanes where R(i, j) is an exact zero in double (see
/// above), whose degenerate edge axes get g = -inf.
template <class V, class VI>
[[gnu::always_inline]] inline void sat15(V (&g)[15], const V (&t)[3], const V (&R)[3][3], const V (&a)[3],
                                         const V (&b)[3], const VI (&zero)[3][3]) {
  V q[3][3];
#pragma GCC unroll 3
  for (int i = 0; i < 3; ++i)
#pragma GCC unroll 3
    for (int j = 0; j < 3; ++j) q[i][j] = vabs<V, VI>(R[i][j]) + kEpsF;
#pragma GCC unroll 3
  for (int i = 0; i < 3; ++i) g[i] = vabs<V, VI>(t[i]) - (a[i] + (b[0] * q[i][0] + b[1] * q[i][1] + b[2] * q[i][2]));
#pragma GCC unroll 3
  for (int j = 0; j < 3; ++j)
    g[3 + j] = vabs<V, VI>(t[0] * R[0][j] + t[1] * R[1][j] + t[2] * R[2][j]) -
               ((a[0] * q[0][j] + a[1] * q[1][j] + a[2] * q[2][j]) + b[j]);
#pragma GCC unroll 3
  for (int i = 0; i < 3; ++i) {
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
#pragma GCC unroll 3
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const V ra = a[i1] * q[i2][j] + a[i2] * q[i1][j];
      const V rb = b[j1] * q[i][j2] + b[j2] * q[i][j1];
      const V gij = vabs<V, VI>(t[i2] * R[i1][j] - t[i1] * R[i2][j]) - (ra + rb);
      const VI degenerate = zero[i1][j] & zero[i2][j];
      g[6 + 3 * i + j] = degenerate ? V{} - std::numeric_limits<float>::infinity() : gij;
    }
  }
}

/// Lanes whose float axes X are orthonormal to kMaxFloatAxesError.
template <class V, class VI>
[[gnu::always_inline]] inline VI orthonormal(const V (&x)[3][3]) {
  VI ok = VI{} - 1;
#pragma GCC unroll 3
  for (int i = 0; i < 3; ++i)
#pragma GCC unroll 3
    for (int j = i; j < 3; ++j) {
      const V dot = x[0][i] * x[0][j] + x[1][i] * x[1][j] + x[2][i] * x[2][j] - (i == j ? 1.0f : 0.0f);
      ok &= vabs<V, VI>(dot) <= kMaxFloatAxesError;
    }
  return ok;
}

/// Lanes l0 .. l0 + W - 1 of a block: the codes of the three stages (codes[s][lane]) and whether the
/// float analysis applies (ok[lane]). aAligned / bAligned: bit per lane, axes exactly the identity.
template <class V, class VI>
[[gnu::always_inline]] inline void pairLanes(const PairBlock& p, int l0, unsigned aAligned, unsigned bAligned,
                                             std::int32_t (*codes)[kBatchLanes], std::int32_t* ok) {
  constexpr int kW = int(sizeof(V) / sizeof(float));
  V a[3][3], b[3][3], ea[3], eb[3], c[3];
#pragma GCC unroll 3
  for (int r = 0; r < 3; ++r)
#pragma GCC unroll 3
    for (int col = 0; col < 3; ++col) {
      a[r][col] = load<V>(p.row[kRowAxes + 3 * col + r] + l0);
      b[r][col] = load<V>(p.row[kRowB + kRowAxes + 3 * col + r] + l0);
    }
#pragma GCC unroll 3
  for (int k = 0; k < 3; ++k) {
    ea[k] = load<V>(p.row[kRowExtents + k] + l0);
    eb[k] = load<V>(p.row[kRowB + kRowExtents + k] + l0);
    c[k] = load<V>(p.row[kRowB + k] + l0);
  }
  VI lanes, one = VI{} + 1;
  for (int l = 0; l < kW; ++l) lanes[l] = std::int32_t(l0 + l);
  const VI aAl = ((VI{} + std::int32_t(aAligned)) >> lanes & one) != 0;
  const VI bAl = ((VI{} + std::int32_t(bAligned)) >> lanes & one) != 0;

  // The float analysis applies: finite, bounded numbers, half extents >= 0, orthonormal axes.
  VI good = orthonormal<V, VI>(a) & orthonormal<V, VI>(b);
#pragma GCC unroll 3
  for (int k = 0; k < 3; ++k) {
    good &= vabs<V, VI>(c[k]) <= kMaxCoordinateF;
    good &= (ea[k] >= 0.0f) & (ea[k] <= kMaxCoordinateF) & (eb[k] >= 0.0f) & (eb[k] <= kMaxCoordinateF);
  }
  std::memcpy(ok + l0, &good, sizeof good);

  // The outward rounding of the half extents, and the AABBs' half extents |A| e.
  const V cmag = vabs<V, VI>(c[0]) + vabs<V, VI>(c[1]) + vabs<V, VI>(c[2]);
  const V growA = kGrowSize * (ea[0] + ea[1] + ea[2]) + kGrowAbs;
  const V growB = kGrowCentre * cmag + kGrowSize * (eb[0] + eb[1] + eb[2]) + kGrowAbs;
  V ha[3], hb[3];
#pragma GCC unroll 3
  for (int k = 0; k < 3; ++k) {
    ea[k] += growA;
    eb[k] += growB;
  }
#pragma GCC unroll 3
  for (int k = 0; k < 3; ++k) {
    ha[k] = vabs<V, VI>(a[k][0]) * ea[0] + vabs<V, VI>(a[k][1]) * ea[1] + vabs<V, VI>(a[k][2]) * ea[2];
    hb[k] = vabs<V, VI>(b[k][0]) * eb[0] + vabs<V, VI>(b[k][1]) * eb[1] + vabs<V, VI>(b[k][2]) * eb[2];
  }
  const V sizes = ((ea[0] + ea[1] + ea[2]) + (eb[0] + eb[1] + eb[2])) + ((ha[0] + ha[1] + ha[2]) + (hb[0] + hb[1] + hb[2]));
  const V sep = kPairSepRel * ((cmag + cmag) + sizes) + kAbsSlack;
  const V negBand = -(sep + kEpsF * sizes);

  // Stage 1: the AABBs (A's centred on the origin, B's on c).
  V g1[3];
#pragma GCC unroll 3
  for (int k = 0; k < 3; ++k) g1[k] = vabs<V, VI>(c[k]) - (ha[k] + hb[k]);
  const VI code1 = stageCode<V, VI>(g1, sep, negBand);
  std::memcpy(codes[0] + l0, &code1, sizeof code1);

  // Stage 2, where some lane gets there: AABB of A against B, or of B against A when only B is
  // axis aligned (testBoxPair's swap; the axis is renamed by the caller).
  const VI reach2 = (code1 == std::int32_t(kNoAxis)) & ~(aAl & bAl);
  VI code2 = VI{} + kUnsure;
  if (anyLane(reach2)) {
    const VI swap = bAl & ~aAl;
    V y[3][3], ey[3], hx[3];
    VI zero[3][3];
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i) {
      ey[i] = swap ? ea[i] : eb[i];
      hx[i] = swap ? hb[i] : ha[i];
#pragma GCC unroll 3
      for (int j = 0; j < 3; ++j) {
        y[i][j] = swap ? a[i][j] : b[i][j];
        zero[i][j] = y[i][j] == 0.0f;
      }
    }
    V g[15];
    sat15<V, VI>(g, c, y, hx, ey, zero);
    code2 = stageCode<V, VI>(g, sep, negBand);
  }
  std::memcpy(codes[1] + l0, &code2, sizeof code2);

  // Stage 3, where some lane gets there: the OBBs, t = A^T c, R = A^T B.
  const VI reach3 = reach2 & (code2 == std::int32_t(kNoAxis)) & ~aAl & ~bAl;
  VI code3 = VI{} + kUnsure;
  if (anyLane(reach3)) {
    V t[3], R[3][3];
    VI zero[3][3];
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i) {
      t[i] = a[0][i] * c[0] + a[1][i] * c[1] + a[2][i] * c[2];
#pragma GCC unroll 3
      for (int j = 0; j < 3; ++j) {
        R[i][j] = a[0][i] * b[0][j] + a[1][i] * b[1][j] + a[2][i] * b[2][j];
        zero[i][j] = ((a[0][i] == 0.0f) | (b[0][j] == 0.0f)) & ((a[1][i] == 0.0f) | (b[1][j] == 0.0f)) &
                     ((a[2][i] == 0.0f) | (b[2][j] == 0.0f));
      }
    }
    V g[15];
    sat15<V, VI>(g, t, R, ea, eb, zero);
    code3 = stageCode<V, VI>(g, sep, negBand);
  }
  std::memcpy(codes[2] + l0, &code3, sizeof code3);
}

/// An axis of the test (B, A) renamed for (A, B), as testBoxPair does after its swap.
constexpr std::int8_t kSwappedAxis[15] = {3, 4, 5, 0, 1, 2, 6, 9, 12, 7, 10, 13, 8, 11, 14};

/// Double decision of one pair, kept out of line (testBoxPair is compiled for the base instruction set).
[[gnu::noinline]] NestedResult boxPairInDouble(const Obb<double>& a, const Obb<double>& b) { return testBoxPair(a, b); }

PairBlock paddingPairBlock() {
  PairBlock p{};
  for (int l = 0; l < kBatchLanes; ++l)
    for (int k = 0; k < 3; ++k)
      for (const int box : {0, kRowB}) {
        p.row[box + kRowAxes + 4 * k][l] = 1.0f;
        p.row[box + kRowExtents + k][l] = 1.0f;
      }
  return p;
}

/// Axes exactly the identity (Obb::isAxisAligned), without branches.
[[gnu::always_inline]] inline bool identityAxes(const Mat3<double>& m) {
  const double* x = m.data();
  return ((x[0] == 1.0) & (x[4] == 1.0) & (x[8] == 1.0) & (x[1] == 0.0) & (x[2] == 0.0) & (x[3] == 0.0) &
          (x[5] == 0.0) & (x[6] == 0.0) & (x[7] == 0.0)) != 0;
}

/// The fields of one box (15 doubles from `d`, the Obb's memory order) into lane l of rows
/// first..first + 14; B's centre as its difference from A's.
[[gnu::always_inline]] inline void gatherLane(PairBlock& p, int l, const Obb<double>& A, const Obb<double>& B) {
  const double* a = A.center.data();
  const double* b = B.center.data();
  for (int f = 0; f < 15; ++f) {
    p.row[f][l] = float(a[f]);
    p.row[kRowB + f][l] = float(f < 3 ? b[f] - a[f] : b[f]);
  }
}

/// Gathers lanes [0, lanes) of the block from pairs base..: the portable way, field by field.
/// Returns the identity-axes bits of A and B.
[[gnu::always_inline]] inline void gatherScalar(const BoxPairsView& pairs, std::size_t base, int lanes, PairBlock& p,
                                                unsigned& aAligned, unsigned& bAligned) {
  aAligned = bAligned = 0;
  for (int l = 0; l < lanes; ++l) {
    const Obb<double>& A = pairs.first(base + std::size_t(l));
    const Obb<double>& B = pairs.second(base + std::size_t(l));
    gatherLane(p, l, A, B);
    aAligned |= unsigned(identityAxes(A.axes)) << l;
    bAligned |= unsigned(identityAxes(B.axes)) << l;
  }
}

/// Reads a block's codes out in testBoxPair's order of stages; lanes without a sure answer are
/// answered by testBoxPair. Returns how many.
[[gnu::always_inline]] inline std::size_t answerBlock(const BoxPairsView& pairs, std::size_t base, int lanes,
                                                      unsigned aAligned, unsigned bAligned,
                                                      const std::int32_t (*codes)[kBatchLanes], const std::int32_t* ok,
                                                      NestedResult* out) {
  std::size_t uncertain = 0;
  for (int l = 0; l < lanes; ++l) {
    const std::size_t k = base + std::size_t(l);
    const bool aAl = (aAligned >> l) & 1u, bAl = (bAligned >> l) & 1u;
    const std::int32_t c1 = codes[0][l], c2 = codes[1][l], c3 = codes[2][l];
    NestedResult r{true, OverlapStage::AabbAabb, std::int8_t(kNoAxis)};
    bool sure = ok[l] != 0 && c1 != kUnsure;
    if (sure) {
      if (c1 >= 0 || (aAl && bAl)) {
        r = {c1 < 0, OverlapStage::AabbAabb, std::int8_t(c1)};
      } else if (c2 == kUnsure) {
        sure = false;
      } else if (bAl) {
        r = {c2 < 0, OverlapStage::AabbObb, c2 < 0 ? std::int8_t(kNoAxis) : kSwappedAxis[c2]};
      } else if (c2 >= 0 || aAl) {
        r = {c2 < 0, OverlapStage::AabbObb, std::int8_t(c2)};
      } else if (c3 == kUnsure) {
        sure = false;
      } else {
        r = {c3 < 0, OverlapStage::ObbObb, std::int8_t(c3)};
      }
    }
    if (!sure) {
      r = boxPairInDouble(pairs.first(k), pairs.second(k));
      ++uncertain;
    }
    out[k] = r;
  }
  return uncertain;
}

/// The whole run, W lanes at a time: per block, gather and round the pairs, run the kernel, answer.
template <class V, class VI, class FullGather>
[[gnu::always_inline]] inline std::size_t boxPairBlocks(const BoxPairsView& pairs, NestedResult* out,
                                                        const FullGather& gatherFull) {
  constexpr int kW = int(sizeof(V) / sizeof(float));
  PairBlock p = paddingPairBlock();
  alignas(32) std::int32_t codes[3][kBatchLanes], ok[kBatchLanes];
  std::size_t uncertain = 0;
  for (std::size_t base = 0; base < pairs.count; base += kBatchLanes) {
    const int lanes = int(std::min<std::size_t>(kBatchLanes, pairs.count - base));
    unsigned aAligned = 0, bAligned = 0;
    if (lanes == kBatchLanes)
      gatherFull(pairs, base, p, aAligned, bAligned);
    else
      gatherScalar(pairs, base, lanes, p, aAligned, bAligned);
    for (int l0 = 0; l0 < kBatchLanes; l0 += kW) pairLanes<V, VI>(p, l0, aAligned, bAligned, codes, ok);
    uncertain += answerBlock(pairs, base, lanes, aAligned, bAligned, codes, ok, out);
  }
  return uncertain;
}

std::size_t boxPairsPortable(const BoxPairsView& pairs, NestedResult* out) {
  return boxPairBlocks<v4f, v4i>(pairs, out,
                                 [](const BoxPairsView& v, std::size_t base, PairBlock& p, unsigned& aAl, unsigned& bAl) {
                                   gatherScalar(v, base, kBatchLanes, p, aAl, bAl);
                                 });
}

#ifdef NESTWALK_HAVE_AVX2_PATH
/// A full block gathered with AVX2: each box's 15 doubles are loaded as four vectors (the last
/// masked, so that nothing past the box is read), converted to float, and the 8 lanes' rows
/// transposed in registers (the scalar gather costs about as much as the kernel). The identity
/// test of the axes is made on the doubles.
[[gnu::target("avx2,fma")]] inline void gatherAvx2(const BoxPairsView& v, std::size_t base, PairBlock& p,
                                                   unsigned& aAligned, unsigned& bAligned) {
  const __m256i first3 = _mm256_setr_epi64x(-1, -1, -1, 0);
  const __m256d keepLast = _mm256_castsi256_pd(_mm256_setr_epi64x(0, 0, 0, -1));
  const __m256d ident0 = _mm256_setr_pd(0, 0, 0, 1);  // (c, c, c, A00) and (A10, A20, A01, A11), (A21, A02, A12, A22)
  __m256 q[4][8];                                     // [A 0-7, A 8-15, B 0-7, B 8-15][lane]
  aAligned = bAligned = 0;
  for (int l = 0; l < 8; ++l) {
    const double* a = v.first(base + std::size_t(l)).center.data();
    const double* b = v.second(base + std::size_t(l)).center.data();
    const __m256d a0 = _mm256_loadu_pd(a), a1 = _mm256_loadu_pd(a + 4), a2 = _mm256_loadu_pd(a + 8),
                  a3 = _mm256_maskload_pd(a + 12, first3);
    const __m256d b0 = _mm256_loadu_pd(b), b1 = _mm256_loadu_pd(b + 4), b2 = _mm256_loadu_pd(b + 8),
                  b3 = _mm256_maskload_pd(b + 12, first3);
    const __m256d d0 = _mm256_sub_pd(b0, _mm256_andnot_pd(keepLast, a0));  // (cB - cA, B00)
    q[0][l] = _mm256_set_m128(_mm256_cvtpd_ps(a1), _mm256_cvtpd_ps(a0));
    q[1][l] = _mm256_set_m128(_mm256_cvtpd_ps(a3), _mm256_cvtpd_ps(a2));
    q[2][l] = _mm256_set_m128(_mm256_cvtpd_ps(b1), _mm256_cvtpd_ps(d0));
    q[3][l] = _mm256_set_m128(_mm256_cvtpd_ps(b3), _mm256_cvtpd_ps(b2));
    const int ia = (_mm256_movemask_pd(_mm256_cmp_pd(a0, ident0, _CMP_EQ_OQ)) & 8) &
                   (_mm256_movemask_pd(_mm256_cmp_pd(a1, ident0, _CMP_EQ_OQ)) == 15 ? 8 : 0) &
                   (_mm256_movemask_pd(_mm256_cmp_pd(a2, ident0, _CMP_EQ_OQ)) == 15 ? 8 : 0);
    const int ib = (_mm256_movemask_pd(_mm256_cmp_pd(b0, ident0, _CMP_EQ_OQ)) & 8) &
                   (_mm256_movemask_pd(_mm256_cmp_pd(b1, ident0, _CMP_EQ_OQ)) == 15 ? 8 : 0) &
                   (_mm256_movemask_pd(_mm256_cmp_pd(b2, ident0, _CMP_EQ_OQ)) == 15 ? 8 : 0);
    aAligned |= unsigned(ia != 0) << l;
    bAligned |= unsigned(ib != 0) << l;
  }
  for (int g = 0; g < 4; ++g) {  // 8 x 8 transposes: row 8 g + i gets element i of every lane
    const __m256* r = q[g];
    const __m256 t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpackhi_ps(r[0], r[1]);
    const __m256 t2 = _mm256_unpacklo_ps(r[2], r[3]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
    const __m256 t4 = _mm256_unpacklo_ps(r[4], r[5]), t5 = _mm256_unpackhi_ps(r[4], r[5]);
    const __m256 t6 = _mm256_unpacklo_ps(r[6], r[7]), t7 = _mm256_unpackhi_ps(r[6], r[7]);
    const __m256 u0 = _mm256_shuffle_ps(t0, t2, 0x44), u1 = _mm256_shuffle_ps(t0, t2, 0xEE);
    const __m256 u2 = _mm256_shuffle_ps(t1, t3, 0x44), u3 = _mm256_shuffle_ps(t1, t3, 0xEE);
    const __m256 u4 = _mm256_shuffle_ps(t4, t6, 0x44), u5 = _mm256_shuffle_ps(t4, t6, 0xEE);
    const __m256 u6 = _mm256_shuffle_ps(t5, t7, 0x44), u7 = _mm256_shuffle_ps(t5, t7, 0xEE);
    float* out = p.row[8 * g];
    _mm256_store_ps(out + 0 * kBatchLanes, _mm256_permute2f128_ps(u0, u4, 0x20));
    _mm256_store_ps(out + 1 * kBatchLanes, _mm256_permute2f128_ps(u1, u5, 0x20));
    _mm256_store_ps(out + 2 * kBatchLanes, _mm256_permute2f128_ps(u2, u6, 0x20));
    _mm256_store_ps(out + 3 * kBatchLanes, _mm256_permute2f128_ps(u3, u7, 0x20));
    _mm256_store_ps(out + 4 * kBatchLanes, _mm256_permute2f128_ps(u0, u4, 0x31));
    _mm256_store_ps(out + 5 * kBatchLanes, _mm256_permute2f128_ps(u1, u5, 0x31));
    _mm256_store_ps(out + 6 * kBatchLanes, _mm256_permute2f128_ps(u2, u6, 0x31));
    _mm256_store_ps(out + 7 * kBatchLanes, _mm256_permute2f128_ps(u3, u7, 0x31));
  }
}

[[gnu::target("avx2,fma")]] std::size_t boxPairsAvx2(const BoxPairsView& pairs, NestedResult* out) {
  static_assert(kBatchLanes == 8, "gatherAvx2 transposes 8 lanes");
  return boxPairBlocks<v8f, v8i>(pairs, out, gatherAvx2);
}
#endif

}  // namespace

std::size_t testBoxPairs(const BoxPairsView& pairs, NestedResult* out) {
#ifdef NESTWALK_HAVE_AVX2_PATH
  if (useAvx2()) return boxPairsAvx2(pairs, out);
#endif
  return boxPairsPortable(pairs, out);
}

// ---------------------------------------------------------------------------------------------
// NestedBoxSet

namespace {

// Survivors of stage 1 whose double stage 1 the float test could not vouch for carry this bit.
constexpr std::uint32_t kUnsureStage1 = 0x80000000u;
// InnerBox::flags.
constexpr std::uint32_t kFloatOk = 1;          // the float analysis covers the box
constexpr std::uint32_t kPermutationAxes = 2;  // axes exactly a signed permutation

/// Whether hi_d >= lo_d surely holds for the doubles behind hi = roundUp(hi_d), lo = roundDown(lo_d)
/// (each within one ulp <= 2^-23 |x| of its double, or 2^-149 below the normal range).
constexpr float kStage1Rel = 0x1p-21f;  // 2 ulps of each operand, plus the rounding of this test, x2
inline bool surelyAtLeast(float hi, float lo) {
  return hi - lo > kStage1Rel * (std::abs(hi) + std::abs(lo)) + kAbsSlack;
}

}  // namespace

NestedBoxSet::NestedBoxSet(std::vector<NestedVolume<double>> boxes) : boxes_(std::move(boxes)) {
  const std::size_t n = boxes_.size();
  if (n >= std::size_t(kUnsureStage1)) throw std::length_error("NestedBoxSet: more than 2^31 - 1 boxes");
  AabbBlock padding;
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < kBatchLanes; ++l) {
      padding.min[k][l] = std::numeric_limits<float>::infinity();
      padding.max[k][l] = -std::numeric_limits<float>::infinity();
    }
  outer_.assign((n + kBatchLanes - 1) / kBatchLanes, padding);
  inner_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Aabb<float> f = toFloatConservative(boxes_[i].outer);
    AabbBlock& blk = outer_[i / kBatchLanes];
    const int lane = int(i % kBatchLanes);
    for (int k = 0; k < 3; ++k) {
      blk.min[k][lane] = f.min[k];
      blk.max[k][lane] = f.max[k];
    }
    const Obb<float> g = toFloatConservative(boxes_[i].inner);
    InnerBox& in = inner_[i];
    for (int k = 0; k < 3; ++k) {
      in.center[k] = g.center[k];
      in.halfExtents[k] = g.halfExtents[k];
    }
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) in.axes[3 * r + c] = g.axes(r, c);
    in.flags = (floatFriendly(boxes_[i].inner, g) ? kFloatOk : 0u) |
               (isSignedPermutation(boxes_[i].inner.axes) ? kPermutationAxes : 0u);
  }
}

namespace {

/// Stage 1 on one block: bit l set when lane l is NOT surely separated from the viewer's float
/// box (the float boxes contain the double ones, so a float separation is a double one; NaN
/// compares false and survives).
#if defined(__SSE2__)
struct ViewerAabb {
  Aabb<float> box;
  __m128 min[3], max[3];
  explicit ViewerAabb(const Aabb<float>& v) : box(v) {
    for (int k = 0; k < 3; ++k) {
      min[k] = _mm_set1_ps(v.min[k]);
      max[k] = _mm_set1_ps(v.max[k]);
    }
  }
};

inline unsigned stage1Survivors(const AabbBlock& b, const ViewerAabb& v) {
  unsigned mask = 0;
  for (int h = 0; h < kBatchLanes; h += 4) {
    __m128 sep = _mm_or_ps(_mm_cmplt_ps(v.max[0], _mm_load_ps(b.min[0] + h)),
                           _mm_cmplt_ps(_mm_load_ps(b.max[0] + h), v.min[0]));
    sep = _mm_or_ps(sep, _mm_or_ps(_mm_cmplt_ps(v.max[1], _mm_load_ps(b.min[1] + h)),
                                   _mm_cmplt_ps(_mm_load_ps(b.max[1] + h), v.min[1])));
    sep = _mm_or_ps(sep, _mm_or_ps(_mm_cmplt_ps(v.max[2], _mm_load_ps(b.min[2] + h)),
                                   _mm_cmplt_ps(_mm_load_ps(b.max[2] + h), v.min[2])));
    mask |= unsigned(~_mm_movemask_ps(sep) & 0xF) << h;
  }
  return mask;
}
#else
struct ViewerAabb {
  Aabb<float> box;
  explicit ViewerAabb(const Aabb<float>& v) : box(v) {}
};

inline unsigned stage1Survivors(const AabbBlock& b, const ViewerAabb& v) {
  unsigned mask = 0;
  for (int l = 0; l < kBatchLanes; ++l) {
    bool sep = false;
    for (int k = 0; k < 3; ++k) sep |= (v.box.max[k] < b.min[k][l]) | (b.max[k][l] < v.box.min[k]);
    mask |= unsigned(!sep) << l;
  }
  return mask;
}
#endif

/// Bit l set when the double stage 1 surely finds lane l overlapping the viewer.
#if defined(__SSE2__)
inline __m128 surelyAtLeast4(__m128 hi, __m128 lo) {
  const __m128 absMask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
  const __m128 slack = _mm_add_ps(
      _mm_mul_ps(_mm_set1_ps(kStage1Rel), _mm_add_ps(_mm_and_ps(hi, absMask), _mm_and_ps(lo, absMask))),
      _mm_set1_ps(kAbsSlack));
  return _mm_cmpgt_ps(_mm_sub_ps(hi, lo), slack);
}

inline unsigned stage1SurelyOverlap(const AabbBlock& b, const ViewerAabb& v) {
  unsigned mask = 0;
  for (int h = 0; h < kBatchLanes; h += 4) {
    __m128 sure = _mm_castsi128_ps(_mm_set1_epi32(-1));
    for (int k = 0; k < 3; ++k) {
      sure = _mm_and_ps(sure, surelyAtLeast4(v.max[k], _mm_load_ps(b.min[k] + h)));
      sure = _mm_and_ps(sure, surelyAtLeast4(_mm_load_ps(b.max[k] + h), v.min[k]));
    }
    mask |= unsigned(_mm_movemask_ps(sure)) << h;
  }
  return mask;
}
#else
inline unsigned stage1SurelyOverlap(const AabbBlock& b, const ViewerAabb& v) {
  unsigned mask = 0;
  for (int l = 0; l < kBatchLanes; ++l) {
    bool sure = true;
    for (int k = 0; k < 3; ++k)
      sure = sure && surelyAtLeast(v.box.max[k], b.min[k][l]) && surelyAtLeast(b.max[k][l], v.box.min[k]);
    mask |= unsigned(sure) << l;
  }
  return mask;
}
#endif

}  // namespace

void NestedBoxSet::queryOverlaps(const NestedVolume<double>& viewer, std::vector<std::uint32_t>& hits,
                                 StageCounters* counters) const {
  const std::size_t n = boxes_.size();
  if (n == 0) return;

  // Stage 1 in float over every block. The survivors, in increasing order, are flagged with
  // kUnsureStage1 when the float test cannot vouch that the double stage 1 lets them through.
  // (One buffer per thread, so that queries stop allocating once it has grown.)
  thread_local std::vector<std::uint32_t> survivors;
  survivors.clear();
  const ViewerAabb v(toFloatConservative(viewer.outer));
  const std::size_t blocks = outer_.size();
  for (std::size_t blk = 0; blk < blocks; ++blk) {
    unsigned mask = stage1Survivors(outer_[blk], v);
    if (mask == 0) continue;
    const std::size_t base = blk * kBatchLanes;
    if (n - base < std::size_t(kBatchLanes)) mask &= (1u << (n - base)) - 1u;  // padding lanes
    const unsigned unsure = ~stage1SurelyOverlap(outer_[blk], v);
    while (mask) {
      const unsigned l = unsigned(__builtin_ctz(mask));
      mask &= mask - 1u;
      survivors.push_back(std::uint32_t(base + l) | ((unsure >> l) & 1u ? kUnsureStage1 : 0u));
    }
  }

  // Stages 2 and 3 in float, kBatchLanes survivors at a time (gathered from inner_), the viewer's
  // volumes broadcast to all lanes; whatever the float kernel leaves uncertain, and any box or
  // viewer outside the float analysis, is decided by testNested in double.
  const Obb<double> viewerOuterObb{viewer.outer.center(), Mat3<double>::Identity(), viewer.outer.halfExtents()};
  const Obb<float> vo = toFloatConservative(viewerOuterObb), vi = toFloatConservative(viewer.inner);
  const bool viewerOk = floatFriendly(viewerOuterObb, vo) && floatFriendly(viewer.inner, vi);
  const bool viewerPerm = isSignedPermutation(viewer.inner.axes);  // (the outer box: identity axes)
  ObbBlock viewerOuter, viewerInner, gathered = paddingObbBlock();
  for (int l = 0; l < kBatchLanes; ++l) {
    storeLane(viewerOuter, l, vo);
    storeLane(viewerInner, l, vi);
  }
  const Stages23Fn stages = pickStages23();
  alignas(32) std::int32_t res[4][kBatchLanes] = {};
  StageCounters local;

  auto processGroup = [&](const std::uint32_t* entries, int count) {
    if (viewerOk) {
      unsigned perm = 0;
      for (int l = 0; l < count; ++l) {
        const InnerBox& in = inner_[entries[l] & ~kUnsureStage1];
        if (in.flags & kPermutationAxes) perm |= 1u << l;
        for (int k = 0; k < 3; ++k) {
          gathered.center[k][l] = in.center[k];
          gathered.halfExtents[k][l] = in.halfExtents[k];
        }
        for (int e = 0; e < 9; ++e) gathered.axes[e][l] = in.axes[e];
      }
      stages(viewerOuter, viewerInner, gathered, perm, viewerPerm ? perm : 0u, res);
    }
    for (int l = 0; l < count; ++l) {
      const std::uint32_t i = entries[l] & ~kUnsureStage1;
      NestedResult r{true, OverlapStage::ObbObb, std::int8_t(kNoAxis)};
      bool decided = false;
      if (viewerOk && !(entries[l] & kUnsureStage1) && (inner_[i].flags & kFloatOk)) {
        // (The separating axis is not reported, and StageCounters does not need it.)
        if (res[0][l]) {
          r = {false, OverlapStage::AabbObb, std::int8_t(kNoAxis)};
          decided = true;
        } else if (res[1][l] && (res[2][l] || res[3][l])) {
          r = {res[3][l] != 0, OverlapStage::ObbObb, std::int8_t(kNoAxis)};
          decided = true;
        }
      }
      if (!decided) r = testNested(viewer, boxes_[i]);
      if (r.overlap) hits.push_back(i);
      local.add(r);
    }
  };

  // The survivors' inner boxes are scattered (each a cache and TLB miss): they are requested
  // kPrefetch entries ahead of their group.
  constexpr std::size_t kPrefetch = 2 * kBatchLanes;
  const std::size_t count = survivors.size();
  for (std::size_t s = 0; s < std::min(kPrefetch, count); ++s)
    __builtin_prefetch(&inner_[survivors[s] & ~kUnsureStage1]);
  for (std::size_t s0 = 0; s0 < count; s0 += kBatchLanes) {
    const std::size_t end = std::min(count, s0 + kBatchLanes + kPrefetch);
    for (std::size_t s = s0 + kPrefetch; s < end; ++s) __builtin_prefetch(&inner_[survivors[s] & ~kUnsureStage1]);
    processGroup(survivors.data() + s0, int(std::min<std::size_t>(kBatchLanes, count - s0)));
  }

  if (counters) {
    // A box separated by the float stage 1 is one that testNested separates at stage 1.
    const std::uint64_t floatSeparated = std::uint64_t(n) - count;
    for (int s = 0; s < kStageCount; ++s) {
      counters->tests[s] += local.tests[s];
      counters->separated[s] += local.separated[s];
    }
    counters->tests[0] += floatSeparated;
    counters->separated[0] += floatSeparated;
  }
}

}  // namespace nestwalk
