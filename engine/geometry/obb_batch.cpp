// testBoxPairs in float SIMD lanes with exact double fallback, and the conservative float boxes
// (see obb_batch.h).
//
// Error analysis of the float filter (u = 2^-24, the unit roundoff of float)
// --------------------------------------------------------------------------
// For each pair the double test (sat.h) computes, per axis, a projected distance |d| and a radius
// r, and separates iff |d| > r on some axis. An OBB-OBB stage in float computes g = |d| - r on
// every axis from conservative float boxes (toFloatConservative's, or the kernel's own rounding,
// below) and bounds how far its g can be from the double one, per axis, with these float
// quantities of the lane:
//   tn = |t0| + |t1| + |t2|   (t = A^T (cB - cA); tn >= the Euclidean distance of the centres)
//   Sa = a0 + a1 + a2, Sb = b0 + b1 + b2   (float half extents, inflated)
//   C  = |cA|_1 + |cB|_1      (magnitude of the coordinates; testBoxPairs has cA = 0)
//   M  = tn + Sa + Sb + C.
// Sources of difference, for boxes whose axes are orthonormal to 1e-6 (checked by the kernel, or
// vouched for by the caller: BoxPairsView::orthonormalAxes):
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
// With slacks of the form
//   sep  = s * M + kAbsSlack,   kAbsSlack = 1e-30,
//   band = sep + kParallelEpsilon<float> * (Sa + Sb):
//  - "surely separating" (g > sep on an axis) needs sep >= (1.8u C + 18.5u tn) + 6u (Sa+Sb) + 2u M
//    + 4e-12 M, which is <= 21u M;
//  - "surely clear" (g < -band on an axis) needs band >= (1.8u C + 18.5u tn) + (3.5u C
//    + 16.5u (Sa+Sb)) + 5.1u (Sa+Sb) + 6u (Sa+Sb) + 2u M + 1e-15 M + 1e-6 (Sa+Sb), which is
//    <= 30u M + 1e-6 (Sa+Sb) (sat.h's slack only helps here).
// (Measured on the former OBB-OBB batch, s = 64u: its exactness tests failed with s = 1u and passed
// down to 4u.) Computing sep and band in float (relative error < 8u) is inside the margins.
// kAbsSlack covers the absolute rounding errors of subnormal numbers (< 2^-149 per operation).
// FMA contraction (the AVX2 and AVX-512 paths) only removes roundings: the bounds hold with or
// without it.
// The price of the epsilon term in the band: an edge axis of exactly parallel edges (|d| ~ 0,
// r ~ 1e-6 S) is never "surely clear"; testBoxPairs skips the ones it can prove degenerate (below).
//
// Paths: the kernel (obb_batch_kernel.h) is written once with GCC vector extensions and compiled
// three times: 4 lanes at a time for the portable x86-64-v2 build (SSE), 8 with AVX2 + FMA and 16
// with AVX-512 (obb_batch_avx512.cpp), the widest the processor has chosen at run time
// (__builtin_cpu_supports); NESTWALK_SIMD=avx2 or =portable in the environment caps it. The
// double fallback is testBoxPair itself, compiled for the base instruction set only (no FMA
// contraction). FMA contraction and AVX-512's wider registers change no bound above.
#include "nestwalk/geometry/obb_batch.h"

#include "nestwalk/geometry/obb_batch_kernel.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>

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

namespace obb_batch_detail {
[[gnu::noinline]] NestedResult boxPairInDouble(const Obb<double>& a, const Obb<double>& b) { return testBoxPair(a, b); }
}  // namespace obb_batch_detail

BatchKernel obbBatchKernel() {
#ifdef NESTWALK_HAVE_AVX2_PATH
  static const BatchKernel best = [] {
    __builtin_cpu_init();
    if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) return BatchKernel::Portable;
#ifdef NESTWALK_OBB_BATCH_AVX512
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
        __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq"))
      return BatchKernel::Avx512;
#endif
    return BatchKernel::Avx2;
  }();
  // Other values of NESTWALK_SIMD are ignored: the widest kernel runs.
  const char* env = std::getenv("NESTWALK_SIMD");
  if (env && std::strcmp(env, "portable") == 0) return BatchKernel::Portable;
  if (env && std::strcmp(env, "avx2") == 0 && best == BatchKernel::Avx512) return BatchKernel::Avx2;
  return best;
#else
  return BatchKernel::Portable;
#endif
}

const char* batchKernelName(BatchKernel k) {
  switch (k) {
    case BatchKernel::Avx512: return "avx512 (16 lanes)";
    case BatchKernel::Avx2: return "avx2+fma (8 lanes)";
    case BatchKernel::Portable: break;
  }
  return "portable (SSE, 4 lanes)";
}

namespace {

void gatherBlockScalar(const BoxPairsView& v, std::size_t base, PairBlock& p, unsigned& aAligned, unsigned& bAligned) {
  gatherScalar(v, base, kBatchLanes, p, aAligned, bAligned);
}

std::size_t boxPairsPortable(const BoxPairsView& pairs, NestedResult* out) {
  return pairs.orthonormalAxes ? boxPairBlocks<v4f, v4i, false>(pairs, out, gatherBlockScalar)
                               : boxPairBlocks<v4f, v4i, true>(pairs, out, gatherBlockScalar);
}

#ifdef NESTWALK_HAVE_AVX2_PATH
[[gnu::target("avx2,fma")]] std::size_t boxPairsAvx2(const BoxPairsView& pairs, NestedResult* out) {
  return pairs.orthonormalAxes ? boxPairBlocks<v8f, v8i, false>(pairs, out, gatherBlockAvx2)
                               : boxPairBlocks<v8f, v8i, true>(pairs, out, gatherBlockAvx2);
}
#endif

}  // namespace

std::size_t testBoxPairs(const BoxPairsView& pairs, NestedResult* out) {
#ifdef NESTWALK_HAVE_AVX2_PATH
  switch (obbBatchKernel()) {
#ifdef NESTWALK_OBB_BATCH_AVX512
    case BatchKernel::Avx512: return obb_batch_detail::boxPairsAvx512(pairs, out);
#else
    case BatchKernel::Avx512: break;  // not built: obbBatchKernel never chooses it
#endif
    case BatchKernel::Avx2: return boxPairsAvx2(pairs, out);
    case BatchKernel::Portable: break;
  }
#endif
  return boxPairsPortable(pairs, out);
}

}  // namespace nestwalk
