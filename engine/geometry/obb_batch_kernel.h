// The float kernel of testBoxPairs (obb_batch.h), private to the geometry module: included by
// obb_batch.cpp (the SSE and AVX2 forms) and obb_batch_avx512.cpp (the AVX-512 form, a file of its
// own because GCC 12 scalarises 64-byte vector compares in a function given AVX-512 by a target
// attribute; that file is compiled with the AVX-512 flags instead). Everything defined here has
// internal linkage (an unnamed namespace), and the kernel calls no inline function from another
// header (the pairs' fields are read by pointer arithmetic; no std::min, no Eigen accessor), so
// even an unoptimised build compiles nothing for AVX-512 that the linker could pick for the
// portable build's code; the test ObbBatch.Avx512FileDefinesOnlyItsEntryPoint checks the object.
// The error analysis behind the slacks is at the top of obb_batch.cpp.
#pragma once

#include "nestwalk/geometry/obb_batch.h"

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>

// The AVX2 form is built on x86-64 with GCC or Clang (a target attribute); the AVX-512 form where
// CMake compiles obb_batch_avx512.cpp with the AVX-512 flags and says so with
// NESTWALK_OBB_BATCH_AVX512 (engine/CMakeLists.txt). Both are chosen at run time.
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define NESTWALK_HAVE_AVX2_PATH 1
#endif

namespace nestwalk {

namespace obb_batch_detail {
/// testBoxPair, kept out of line in obb_batch.cpp (compiled for the base instruction set): the
/// exact answer of the lanes the float analysis cannot vouch for.
NestedResult boxPairInDouble(const Obb<double>& a, const Obb<double>& b);
/// testBoxPairs' AVX-512 form (obb_batch_avx512.cpp).
std::size_t boxPairsAvx512(const BoxPairsView& pairs, NestedResult* out);
}  // namespace obb_batch_detail

namespace {

using obb_batch_detail::boxPairInDouble;

// ---------------------------------------------------------------------------------------------
// GCC vector extensions: the kernel's templates are always inlined, so each instantiation is
// compiled for the instruction set of the function that calls it.

// The helpers below return 32- and 64-byte vectors by value; they are always inlined, so the ABI
// note GCC gives for them (AVX vectors in a function compiled without AVX) does not apply.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

typedef float v4f __attribute__((vector_size(16)));
typedef std::int32_t v4i __attribute__((vector_size(16)));
typedef float v8f __attribute__((vector_size(32)));
typedef std::int32_t v8i __attribute__((vector_size(32)));
typedef float v16f __attribute__((vector_size(64)));
typedef std::int32_t v16i __attribute__((vector_size(64)));

// What the analysis assumes of sat.h: the float epsilon exceeds the error of a float R entry
// (5.1u = 3.1e-7) plus the double epsilon, and the double test's slack is far below 1u.
static_assert(kParallelEpsilon<float> - kParallelEpsilon<double> > 4e-7f);
static_assert(kParallelEpsilon<float> <= 1e-5f);
static_assert(kRoundingSlack<double> <= 1e-10);
constexpr float kAbsSlack = 1e-30f;  // covers absolute rounding errors of subnormal numbers
constexpr float kEpsF = kParallelEpsilon<float>;

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
// (4u + 1e-12) sum e (<= 2u |c|_1 + 7.5u sum e, obb_batch.cpp) after the roundings of fl(e) (u e),
// of the growth's own float arithmetic (< 6u of it) and of the sum (u), so the float box contains
// the double one; and it is at most 2.6u C + 14u S (against 2u C + 9.5u S in obb_batch.cpp's
// analysis).
// Error bounds per axis, g_float against g_double (M = 2C + SX + S, C = |fl(cB - cA)|_1, S the
// four boxes' half extents: the two OBBs' and the two AABBs'):
//  - stage 3 (OBB-OBB): obb_batch.cpp's analysis with the larger enlargement: < 40u M + 1e-6 S;
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

constexpr float kPairSepRel = 256.0f * 0x1p-24f;  // 256u, as above (unitless, relative to M)
constexpr float kGrowCentre = 2.5f * 0x1p-24f;    // growth of a half extent per |c|_1 (as above)
constexpr float kGrowSize = 12.0f * 0x1p-24f;     // growth per metre of summed half extents
constexpr float kGrowAbs = 1e-36f;                // m: covers float underflow of tiny half extents
// Lanes outside these are answered in double: products stay finite, and the axes are orthonormal
// to 1e-6 in double (the float check, accurate to ~5u = 3e-7, is kept at 5e-7), or the caller
// vouches for Obb's contract (BoxPairsView::orthonormalAxes), which is far inside that.
constexpr float kMaxCoordinateF = 1e18f;
constexpr float kMaxFloatAxesError = 5e-7f;
constexpr std::int32_t kUnsure = -2;  // a stage's lane code: no sure answer (else axis or kNoAxis)
static_assert(kAxesTolerance<double> < 1e-6, "BoxPairsView::orthonormalAxes: Obb's contract within the analysis");
// The pairs' fields are read as doubles in Obb's memory order: no padding, no over-alignment
// (Eigen's vectorisation, on in the AVX-512 file, must not change the layout).
static_assert(alignof(Obb<double>) == alignof(double), "Obb<double>: a plain array of 15 doubles");

/// kBatchLanes pairs in A's local frame, rounded to float: row r holds field r of every lane, the
/// fields in the memory order of Obb<double> (centre, axes column by column, half extents): rows
/// 0..14 box A (its centre rows are not used: A's centre is the origin), rows 16..30 box B, with
/// B's centre replaced by cB - cA (computed in double).
struct alignas(64) PairBlock {
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
      g[6 + 3 * i + j] = degenerate ? V{} - __builtin_inff() : gij;
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

/// An axis of the test (B, A) renamed for (A, B), as testBoxPair does after its swap, per lane:
/// faces 0-2 and 3-5 trade places, edge 6 + 3i + j becomes 6 + 3j + i.
template <class VI>
[[gnu::always_inline]] inline VI swappedAxis(const VI& c) {
  const VI e = c - 6;
  const VI i = (e * 11) >> 5;  // e / 3 for 0 <= e <= 8
  const VI edge = 6 + 3 * (e - 3 * i) + i;
  return c < 3 ? c + 3 : (c < 6 ? c - 3 : edge);
}

/// One lane's answer packed as the bytes of a NestedResult (overlap, stage, axis; little endian),
/// from the three stages' codes in testBoxPair's order of stages, and the lanes that the float
/// analysis leaves to testBoxPair (unsure). (tests/geometry/obb_batch_answer_test.cpp checks it
/// against the scalar reading of the codes on every combination.)
template <class VI>
[[gnu::always_inline]] inline VI packedAnswer(const VI& c1, const VI& c2, const VI& c3, const VI& good, const VI& aAl,
                                              const VI& bAl, VI& unsure) {
  const VI unsureCode = VI{} + kUnsure;
  const VI use1 = (c1 >= 0) | (aAl & bAl);  // stage 1 separates, or both boxes are axis aligned
  const VI use2 = (c2 >= 0) | aAl | bAl;    // (where not use1) stage 2 separates, or is the last
  unsure = ~good | (c1 == unsureCode) | (~use1 & (c2 == unsureCode)) | (~use1 & ~use2 & (c3 == unsureCode));
  const VI c2Named = (bAl & ~aAl & (c2 >= 0)) ? swappedAxis(c2) : c2;
  const VI code = use1 ? c1 : (use2 ? c2Named : c3);
  const VI stage = use1 ? VI{} + int(OverlapStage::AabbAabb)
                        : (use2 ? VI{} + int(OverlapStage::AabbObb) : VI{} + int(OverlapStage::ObbObb));
  return (code < 0 ? VI{} + 1 : VI{}) | (stage << (8 * offsetof(NestedResult, stage))) |
         ((code & 0xff) << (8 * offsetof(NestedResult, axis)));
}

/// W lanes of boxes read from rows of floats (row r of field r, `stride` floats apart, from lane
/// l0), with what every stage uses: the half extents rounded outward, the AABBs' half extents
/// |A| e, the slacks, and whether the float analysis applies to the lane.
template <class V, class VI>
struct LaneBoxes {
  V a[3][3], b[3][3], ea[3], eb[3], c[3];  // A's and B's axes (row, column), half extents; cB - cA
  V ha[3], hb[3];                          // the AABBs' half extents
  V sep, negBand;                          // a sure separation exceeds sep; a sure clearance is below negBand
  VI good;                                 // the float analysis applies: finite, bounded, orthonormal
};

/// kCheckAxes: test the float axes' orthonormality (false where the caller vouches for it,
/// BoxPairsView::orthonormalAxes).
template <class V, class VI, bool kCheckAxes>
[[gnu::always_inline]] inline LaneBoxes<V, VI> laneBoxes(const float* rows, int stride, int l0) {
  LaneBoxes<V, VI> L;
  auto field = [&](int r) { return load<V>(rows + r * stride + l0); };
#pragma GCC unroll 3
  for (int r = 0; r < 3; ++r)
#pragma GCC unroll 3
    for (int col = 0; col < 3; ++col) {
      L.a[r][col] = field(kRowAxes + 3 * col + r);
      L.b[r][col] = field(kRowB + kRowAxes + 3 * col + r);
    }
#pragma GCC unroll 3
  for (int k = 0; k < 3; ++k) {
    L.ea[k] = field(kRowExtents + k);
    L.eb[k] = field(kRowB + kRowExtents + k);
    L.c[k] = field(kRowB + k);
  }

  // The float analysis applies: finite, bounded numbers, half extents >= 0, orthonormal axes.
  L.good = VI{} - 1;
  if constexpr (kCheckAxes) L.good = orthonormal<V, VI>(L.a) & orthonormal<V, VI>(L.b);
#pragma GCC unroll 3
  for (int k = 0; k < 3; ++k) {
    L.good &= vabs<V, VI>(L.c[k]) <= kMaxCoordinateF;
    L.good &= (L.ea[k] >= 0.0f) & (L.ea[k] <= kMaxCoordinateF) & (L.eb[k] >= 0.0f) & (L.eb[k] <= kMaxCoordinateF);
  }

  // The outward rounding of the half extents, and the AABBs' half extents |A| e.
  const V cmag = vabs<V, VI>(L.c[0]) + vabs<V, VI>(L.c[1]) + vabs<V, VI>(L.c[2]);
  const V growA = kGrowSize * (L.ea[0] + L.ea[1] + L.ea[2]) + kGrowAbs;
  const V growB = kGrowCentre * cmag + kGrowSize * (L.eb[0] + L.eb[1] + L.eb[2]) + kGrowAbs;
#pragma GCC unroll 3
  for (int k = 0; k < 3; ++k) {
    L.ea[k] += growA;
    L.eb[k] += growB;
  }
#pragma GCC unroll 3
  for (int k = 0; k < 3; ++k) {
    L.ha[k] = vabs<V, VI>(L.a[k][0]) * L.ea[0] + vabs<V, VI>(L.a[k][1]) * L.ea[1] + vabs<V, VI>(L.a[k][2]) * L.ea[2];
    L.hb[k] = vabs<V, VI>(L.b[k][0]) * L.eb[0] + vabs<V, VI>(L.b[k][1]) * L.eb[1] + vabs<V, VI>(L.b[k][2]) * L.eb[2];
  }
  const V sizes = ((L.ea[0] + L.ea[1] + L.ea[2]) + (L.eb[0] + L.eb[1] + L.eb[2])) +
                  ((L.ha[0] + L.ha[1] + L.ha[2]) + (L.hb[0] + L.hb[1] + L.hb[2]));
  L.sep = kPairSepRel * ((cmag + cmag) + sizes) + kAbsSlack;
  L.negBand = -(L.sep + kEpsF * sizes);
  return L;
}

/// Stage 1's code per lane: the AABBs (A's centred on the origin, B's on c).
template <class V, class VI>
[[gnu::always_inline]] inline VI stage1Code(const LaneBoxes<V, VI>& L) {
  V g1[3];
#pragma GCC unroll 3
  for (int k = 0; k < 3; ++k) g1[k] = vabs<V, VI>(L.c[k]) - (L.ha[k] + L.hb[k]);
  return stageCode<V, VI>(g1, L.sep, L.negBand);
}

/// Stages 2 and 3's codes per lane, for the lanes in reach2 (stage 1 found no separation and the
/// boxes are not both axis aligned); kUnsure elsewhere. Each stage runs only where a lane gets there.
template <class V, class VI>
[[gnu::always_inline]] inline void laterStageCodes(const LaneBoxes<V, VI>& L, const VI& aAl, const VI& bAl,
                                                   const VI& reach2, VI& code2, VI& code3) {
  // Stage 2: AABB of A against B, or of B against A when only B is axis aligned (testBoxPair's
  // swap; the axis is renamed by packedAnswer).
  code2 = VI{} + kUnsure;
  if (anyLane(reach2)) {
    const VI swap = bAl & ~aAl;
    V y[3][3], ey[3], hx[3];
    VI zero[3][3];
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i) {
      ey[i] = swap ? L.ea[i] : L.eb[i];
      hx[i] = swap ? L.hb[i] : L.ha[i];
#pragma GCC unroll 3
      for (int j = 0; j < 3; ++j) {
        y[i][j] = swap ? L.a[i][j] : L.b[i][j];
        zero[i][j] = y[i][j] == 0.0f;
      }
    }
    V g[15];
    sat15<V, VI>(g, L.c, y, hx, ey, zero);
    code2 = stageCode<V, VI>(g, L.sep, L.negBand);
  }

  // Stage 3: the OBBs, t = A^T c, R = A^T B.
  const VI reach3 = reach2 & (code2 == std::int32_t(kNoAxis)) & ~aAl & ~bAl;
  code3 = VI{} + kUnsure;
  if (anyLane(reach3)) {
    V t[3], R[3][3];
    VI zero[3][3];
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i) {
      t[i] = L.a[0][i] * L.c[0] + L.a[1][i] * L.c[1] + L.a[2][i] * L.c[2];
#pragma GCC unroll 3
      for (int j = 0; j < 3; ++j) {
        R[i][j] = L.a[0][i] * L.b[0][j] + L.a[1][i] * L.b[1][j] + L.a[2][i] * L.b[2][j];
        zero[i][j] = ((L.a[0][i] == 0.0f) | (L.b[0][j] == 0.0f)) & ((L.a[1][i] == 0.0f) | (L.b[1][j] == 0.0f)) &
                     ((L.a[2][i] == 0.0f) | (L.b[2][j] == 0.0f));
      }
    }
    V g[15];
    sat15<V, VI>(g, t, R, L.ea, L.eb, zero);
    code3 = stageCode<V, VI>(g, L.sep, L.negBand);
  }
}

/// Lanes whose bit is set in `bits` (lane l of the vector is bit l0 + l).
template <class VI>
[[gnu::always_inline]] inline VI laneBits(unsigned bits, int l0) {
  VI lanes;
  for (int l = 0; l < int(sizeof(VI) / sizeof(std::int32_t)); ++l) lanes[l] = std::int32_t(l0 + l);
  return ((VI{} + std::int32_t(bits)) >> lanes & 1) != 0;
}

/// Lanes l0 .. l0 + W - 1 of a block: each lane's answer packed (packedAnswer) into answer[lane],
/// and unsure[lane] non-zero where testBoxPair must decide. aAligned / bAligned: bit per lane, axes
/// exactly the identity.
template <class V, class VI, bool kCheckAxes>
[[gnu::always_inline]] inline void pairLanes(const PairBlock& p, int l0, unsigned aAligned, unsigned bAligned,
                                             std::int32_t* answer, std::int32_t* unsure) {
  const LaneBoxes<V, VI> L = laneBoxes<V, VI, kCheckAxes>(&p.row[0][0], kBatchLanes, l0);
  const VI aAl = laneBits<VI>(aAligned, l0), bAl = laneBits<VI>(bAligned, l0);
  const VI code1 = stage1Code(L);
  VI code2, code3;
  laterStageCodes(L, aAl, bAl, (code1 == std::int32_t(kNoAxis)) & ~(aAl & bAl), code2, code3);
  VI notSure;
  const VI packed = packedAnswer(code1, code2, code3, L.good, aAl, bAl, notSure);
  std::memcpy(answer + l0, &packed, sizeof packed);
  std::memcpy(unsure + l0, &notSure, sizeof notSure);
}

// packedAnswer's int32 holds a NestedResult in its first three bytes, as memory holds it.
static_assert(std::endian::native == std::endian::little, "packedAnswer: little-endian lanes");
static_assert(sizeof(NestedResult) == 3 && offsetof(NestedResult, overlap) == 0, "NestedResult: three bytes");

inline PairBlock paddingPairBlock() {
  PairBlock p{};
  for (int l = 0; l < kBatchLanes; ++l)
    for (int k = 0; k < 3; ++k)
      for (int box = 0; box <= kRowB; box += kRowB) {  // (no initializer_list: see the top)
        p.row[box + kRowAxes + 4 * k][l] = 1.0f;
        p.row[box + kRowExtents + k][l] = 1.0f;
      }
  return p;
}

/// Box k of a pair array (first box at `base`, `stride` bytes apart) as its 15 doubles: the centre,
/// the axes column by column, the half extents (Obb<double>'s memory order).
[[gnu::always_inline]] inline const double* boxFields(const Obb<double>* base, std::size_t stride, std::size_t k) {
  return reinterpret_cast<const double*>(reinterpret_cast<const char*>(base) + k * stride);
}
[[gnu::always_inline]] inline const Obb<double>& boxAt(const Obb<double>* base, std::size_t stride, std::size_t k) {
  return *reinterpret_cast<const Obb<double>*>(boxFields(base, stride, k));
}

/// Axes exactly the identity (Obb::isAxisAligned), without branches; `box`: the box's fields.
[[gnu::always_inline]] inline bool identityAxes(const double* box) {
  const double* x = box + 3;
  return ((x[0] == 1.0) & (x[4] == 1.0) & (x[8] == 1.0) & (x[1] == 0.0) & (x[2] == 0.0) & (x[3] == 0.0) &
          (x[5] == 0.0) & (x[6] == 0.0) & (x[7] == 0.0)) != 0;
}

/// The fields of a pair's boxes (15 doubles each, boxFields) into lane l of rows 0..14 and
/// 16..30; B's centre as its difference from A's.
[[gnu::always_inline]] inline void gatherLane(PairBlock& p, int l, const double* a, const double* b) {
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
    const double* a = boxFields(pairs.a, pairs.stride, base + std::size_t(l));
    const double* b = boxFields(pairs.b, pairs.stride, base + std::size_t(l));
    gatherLane(p, l, a, b);
    aAligned |= unsigned(identityAxes(a)) << l;
    bAligned |= unsigned(identityAxes(b)) << l;
  }
}

/// Writes a block's answers; lanes without a sure answer are answered by testBoxPair. Returns how
/// many.
[[gnu::always_inline]] inline std::size_t answerBlock(const BoxPairsView& pairs, std::size_t base, int lanes,
                                                      const std::int32_t* answer, const std::int32_t* unsure,
                                                      NestedResult* out) {
  std::size_t uncertain = 0;
  for (int l = 0; l < lanes; ++l) std::memcpy(&out[base + std::size_t(l)], &answer[l], sizeof(NestedResult));
  for (int l = 0; l < lanes; ++l)
    if (unsure[l]) {
      const std::size_t k = base + std::size_t(l);
      out[k] = boxPairInDouble(boxAt(pairs.a, pairs.stride, k), boxAt(pairs.b, pairs.stride, k));
      ++uncertain;
    }
  return uncertain;
}

/// The whole run, W lanes at a time: per block, gather and round the pairs, run the kernel, answer.
/// kCheckAxes: false where the caller vouches for the axes (BoxPairsView::orthonormalAxes).
template <class V, class VI, bool kCheckAxes, class FullGather>
[[gnu::always_inline]] inline std::size_t boxPairBlocks(const BoxPairsView& pairs, NestedResult* out,
                                                        const FullGather& gatherFull) {
  constexpr int kW = int(sizeof(V) / sizeof(float));
  PairBlock p = paddingPairBlock();
  alignas(64) std::int32_t answer[kBatchLanes], unsure[kBatchLanes];
  std::size_t uncertain = 0;
  for (std::size_t base = 0; base < pairs.count; base += kBatchLanes) {
    const int lanes = pairs.count - base < std::size_t(kBatchLanes) ? int(pairs.count - base) : kBatchLanes;
    unsigned aAligned = 0, bAligned = 0;
    if (lanes == kBatchLanes)
      gatherFull(pairs, base, p, aAligned, bAligned);
    else
      gatherScalar(pairs, base, lanes, p, aAligned, bAligned);
    for (int l0 = 0; l0 < kBatchLanes; l0 += kW)
      pairLanes<V, VI, kCheckAxes>(p, l0, aAligned, bAligned, answer, unsure);
    uncertain += answerBlock(pairs, base, lanes, answer, unsure, out);
  }
  return uncertain;
}

#ifdef NESTWALK_HAVE_AVX2_PATH
/// Eight lanes of a block (lanes firstLane .. firstLane + 7) gathered with AVX2: each box's 15 doubles are loaded as four vectors (the last
/// masked, so that nothing past the box is read), converted to float, and the 8 lanes' rows
/// transposed in registers (the scalar gather costs about as much as the kernel). The identity
/// test of the axes is made on the doubles.
[[gnu::target("avx2,fma")]] inline void gatherAvx2(const BoxPairsView& v, std::size_t base, int firstLane, PairBlock& p,
                                                   unsigned& aAligned, unsigned& bAligned) {
  const __m256i first3 = _mm256_setr_epi64x(-1, -1, -1, 0);
  const __m256d keepLast = _mm256_castsi256_pd(_mm256_setr_epi64x(0, 0, 0, -1));
  const __m256d ident0 = _mm256_setr_pd(0, 0, 0, 1);  // (c, c, c, A00) and (A10, A20, A01, A11), (A21, A02, A12, A22)
  __m256 q[4][8];                                     // [A 0-7, A 8-15, B 0-7, B 8-15][lane]
  for (int l = 0; l < 8; ++l) {
    const double* a = boxFields(v.a, v.stride, base + std::size_t(firstLane + l));
    const double* b = boxFields(v.b, v.stride, base + std::size_t(firstLane + l));
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
    aAligned |= unsigned(ia != 0) << (firstLane + l);
    bAligned |= unsigned(ib != 0) << (firstLane + l);
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
    float* out = p.row[8 * g] + firstLane;
    _mm256_storeu_ps(out + 0 * kBatchLanes, _mm256_permute2f128_ps(u0, u4, 0x20));
    _mm256_storeu_ps(out + 1 * kBatchLanes, _mm256_permute2f128_ps(u1, u5, 0x20));
    _mm256_storeu_ps(out + 2 * kBatchLanes, _mm256_permute2f128_ps(u2, u6, 0x20));
    _mm256_storeu_ps(out + 3 * kBatchLanes, _mm256_permute2f128_ps(u3, u7, 0x20));
    _mm256_storeu_ps(out + 4 * kBatchLanes, _mm256_permute2f128_ps(u0, u4, 0x31));
    _mm256_storeu_ps(out + 5 * kBatchLanes, _mm256_permute2f128_ps(u1, u5, 0x31));
    _mm256_storeu_ps(out + 6 * kBatchLanes, _mm256_permute2f128_ps(u2, u6, 0x31));
    _mm256_storeu_ps(out + 7 * kBatchLanes, _mm256_permute2f128_ps(u3, u7, 0x31));
  }
}

/// A full block, eight lanes at a time.
[[gnu::target("avx2,fma")]] inline void gatherBlockAvx2(const BoxPairsView& v, std::size_t base, PairBlock& p,
                                                        unsigned& aAligned, unsigned& bAligned) {
  static_assert(kBatchLanes % 8 == 0, "gatherAvx2 transposes 8 lanes");
  aAligned = bAligned = 0;
  for (int firstLane = 0; firstLane < kBatchLanes; firstLane += 8) gatherAvx2(v, base, firstLane, p, aAligned, bAligned);
}
#endif  // NESTWALK_HAVE_AVX2_PATH

}  // namespace

}  // namespace nestwalk
