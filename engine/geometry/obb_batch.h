// Box pairs tested in float SIMD lanes: testBoxPairs, the batch form of testBoxPair (nested.h).
// Who runs it: `nestwalk query overlap` (its pairs, 1,024 at a time as they are read); `bench
// volumes` times it first among the pair tests, beside the scalar testBoxPair it replaced and the
// peers (FCL, libccd, Bullet), and `bench walker` at the walker's candidate counts. The walker does
// not: its few candidates per query are cheaper one at a time (collision_world.h gives the
// measurement). The former yes/no OBB-OBB batch and the one-vs-many nested set were run by the
// benchmark and the tests only, and were removed.
//
// Layout: blocks of kBatchLanes pairs with all fields of a block stored together ("array of
// structures of arrays"), so that the lanes map to SIMD registers (4 x SSE on the portable
// x86-64-v2 build, 2 x AVX2 or 1 x AVX-512 where chosen at run time). The answers are also formed
// in the lanes, so the only per-pair branch left is the rare one to testBoxPair.
//
// Exactness: the float kernel is a conservative filter. The boxes are rounded to float outward (a
// float box contains its double original despite rounding), and every axis of every stage gets one
// of three answers per lane: surely separating, surely clear, or open (within the float rounding
// band of touching). A lane is answered in float only when its stage's first open axis surely
// separates, or no axis is open; the others, and data outside the float analysis, are answered by
// testBoxPair itself, so the answers returned are exactly testBoxPair's, field for field. (The
// slacks and their justification are in obb_batch.cpp.)
//
// The widest kernel the processor has (AVX-512, then AVX2 + FMA) is chosen at run time; the
// environment variable NESTWALK_SIMD=avx2 or =portable caps it (the answers are the same).
//
// Thread safety: testBoxPairs is a pure function of its arguments (its scratch is on the stack);
// `out` is the caller's. The kernel choice reads NESTWALK_SIMD with getenv on every call: do not
// change it (setenv) while other threads test.
#pragma once

#include "nestwalk/geometry/nested.h"

#include <cstddef>
#include <cstdint>

namespace nestwalk {

inline constexpr int kBatchLanes = 16;

/// A float box that contains the double box `b` (given in a local frame): the center and axes are
/// rounded to float and the half extents are enlarged by the largest displacement that rounding
/// can cause, rounded upward. (The reference of the kernel's cheaper rounding, obb_batch.cpp.)
Obb<float> toFloatConservative(const Obb<double>& b);
Aabb<float> toFloatConservative(const Aabb<double>& b);

/// The instruction sets testBoxPairs can run: SSE (x86-64-v2, 4 lanes at a time), AVX2 + FMA (8)
/// and AVX-512 F/VL/BW/DQ (16).
enum class BatchKernel { Portable, Avx2, Avx512 };

/// The form testBoxPairs runs now: the widest the processor has, unless the environment variable
/// NESTWALK_SIMD is "portable" (SSE) or "avx2" (at most AVX2), read on every call so that tests and
/// the benchmark can run every path.
BatchKernel obbBatchKernel();
const char* batchKernelName(BatchKernel kernel);  // e.g. "avx2+fma (8 lanes)"

/// Pairs of boxes read where they lie: pair k is (a[k], b[k]) with a[k] the Obb at byte offset
/// k * stride from `a` (likewise b), so that the boxes can be members of the caller's own records
/// (stride = sizeof the record) or two plain arrays (stride = sizeof(Obb<double>)).
struct BoxPairsView {
  const Obb<double>* a = nullptr;
  const Obb<double>* b = nullptr;
  std::size_t count = 0;
  std::size_t stride = sizeof(Obb<double>);
  /// True: the caller vouches that every box keeps Obb's contract on its axes (orthonormal to
  /// kAxesTolerance<double> = 1e-13, volumes.h), as BoxPairsReader's boxes do, and the kernel skips
  /// its own check of the float axes (about a tenth of its work). The float analysis needs the
  /// axes orthonormal to about 1e-6. False (the default): the kernel checks the float axes to 5e-7
  /// and sends a box further off to testBoxPair, like any lane the analysis does not cover. With
  /// true, a box off by more than about 1e-6 may be answered wrongly.
  bool orthonormalAxes = false;

  const Obb<double>& first(std::size_t k) const { return at(a, k); }
  const Obb<double>& second(std::size_t k) const { return at(b, k); }

 private:
  const Obb<double>& at(const Obb<double>* base, std::size_t k) const {
    return *reinterpret_cast<const Obb<double>*>(reinterpret_cast<const char*>(base) + k * stride);
  }
};

/// testBoxPair on many pairs at once (`nestwalk query overlap`): out[k] = testBoxPair(a[k], b[k]),
/// the verdict, the deciding stage and the first separating axis in that stage's own order,
/// identical field for field. The pairs are read kBatchLanes at a time, moved to A's local frame,
/// rounded outward to float and run through all three stages in SIMD lanes (the ordering of the
/// axes kept per lane); a lane whose answer the float analysis cannot vouch for (some axis before
/// the first surely separating one is not surely clear, or the data are outside the analysis) is
/// answered by testBoxPair itself. Returns the number of pairs so re-decided in double.
/// No allocation; `out` has room for pairs.count results.
std::size_t testBoxPairs(const BoxPairsView& pairs, NestedResult* out);

}  // namespace nestwalk
