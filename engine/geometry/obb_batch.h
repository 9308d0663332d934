// Box pairs tested in float SIMD lanes: testBoxPairs, the batch form of testBoxPair (nested.h).
// Who runs it: `nestwalk query overlap` (all its pairs, read whole, answered in one call); `bench
// volumes` times it first among the pair tests, beside the scalar testBoxPair it replaced and the
// peers (FCL, libccd, Bullet), and `bench walker` at the walker's candidate counts. The walker does
// not: its few candidates per query are cheaper one at a time (collision_world.h gives the
// measurement). The former yes/no OBB-OBB batch and the one-vs-many nested set were run by the
// benchmark and the tests only, and were removed.
//
// Layout: blocks of kBatchLanes pairs with all fields of a block stored together ("array of
// structures of arrays"), so that one block is a few cache lines and the lanes map to SIMD
// registers (2 x SSE on the portable x86-64-v2 build, 1 x AVX2 where chosen at run time).
//
// Exactness: the float kernel is a conservative filter. The boxes are rounded to float outward (a
// float box contains its double original despite rounding), and every axis of every stage gets one
// of three answers per lane: surely separating, surely clear, or open (within the float rounding
// band of touching). A lane is answered in float only when its stage's first open axis surely
// separates, or no axis is open; the others, and data outside the float analysis, are answered by
// testBoxPair itself, so the answers returned are exactly testBoxPair's, field for field. (The
// slacks and their justification are in obb_batch.cpp.)
//
// The AVX2 + FMA kernel is chosen at run time where the processor has it; setting the environment
// variable NESTWALK_SIMD=portable forces the SSE one (the answers are the same).
//
// Thread safety: testBoxPairs is a pure function of its arguments (its scratch is on the stack);
// `out` is the caller's. The kernel choice reads NESTWALK_SIMD with getenv on every call: do not
// change it (setenv) while other threads test.
#pragma once

#include "nestwalk/geometry/nested.h"

#include <cstddef>
#include <cstdint>

namespace nestwalk {

inline constexpr int kBatchLanes = 8;

/// A float box that contains the double box `b` (given in a local frame): the center and axes are
/// rounded to float and the half extents are enlarged by the largest displacement that rounding
/// can cause, rounded upward. (The reference of the kernel's cheaper rounding, obb_batch.cpp.)
Obb<float> toFloatConservative(const Obb<double>& b);
Aabb<float> toFloatConservative(const Aabb<double>& b);

/// Whether testBoxPairs runs its AVX2 + FMA form now: where the build has it and the processor has
/// AVX2 and FMA, unless the environment variable NESTWALK_SIMD is "portable" (read on every call,
/// so that tests and the benchmark can run both paths).
bool obbBatchUsesAvx2();

/// Pairs of boxes read where they lie: pair k is (a[k], b[k]) with a[k] the Obb at byte offset
/// k * stride from `a` (likewise b), so that the boxes can be members of the caller's own records
/// (stride = sizeof the record) or two plain arrays (stride = sizeof(Obb<double>)).
struct BoxPairsView {
  const Obb<double>* a = nullptr;
  const Obb<double>* b = nullptr;
  std::size_t count = 0;
  std::size_t stride = sizeof(Obb<double>);

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
