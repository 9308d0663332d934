// Batched overlap tests in float SIMD: many pairs at once, and one viewer against many stored
// equipment boxes. Measured by `bench volumes` against FCL; the product does not run them yet (the
// walker tests its few broad-phase candidates one at a time, `query overlap` its pairs with
// testBoxPair, which also names the deciding stage and axis).
//
// Layout: blocks of kBatchLanes boxes with all fields of a block stored together
// ("array of structures of arrays"), so that one block is a few cache lines and the lanes map to
// SIMD registers (2 x SSE on the portable x86-64-v2 build, 1 x AVX2 where chosen at run time).
// Separate large arrays per field were measured 2x slower (L1 set conflicts).
//
// Exactness: the float kernel is a conservative filter. Each stored float box is inflated so that
// it contains its double original despite rounding (see toFloatConservative), and every lane gets
// one of three answers: surely separated, surely overlapping, or uncertain (within the float
// rounding band of touching). Uncertain lanes are re-decided by the scalar double test (sat.h),
// so the verdicts returned are exactly those of satObbObb<double> on the double originals.
// (The slacks and their justification are at the top of obb_batch.cpp.)
//
// The AVX2 + FMA kernels are chosen at run time where the processor has them; setting the
// environment variable NESTWALK_SIMD=portable forces the SSE ones (the verdicts are the same).
//
// Thread safety: an ObbPairBatch or NestedBoxSet is immutable once built; test() and
// queryOverlaps() may run from several threads at once (queryOverlaps keeps its scratch in a
// thread_local buffer). `out`, `hits` and `counters` are the caller's: one per thread. The kernel
// choice reads NESTWALK_SIMD with getenv on every call: do not change it (setenv) while other
// threads test.
#pragma once

#include "nestwalk/geometry/nested.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace nestwalk {

inline constexpr int kBatchLanes = 8;

/// kBatchLanes oriented boxes, field by field. axes[3*r + c][lane] is axes(r, c) (row r, column c).
struct alignas(32) ObbBlock {
  float center[3][kBatchLanes];
  float axes[9][kBatchLanes];
  float halfExtents[3][kBatchLanes];
};

/// kBatchLanes axis-aligned boxes.
struct alignas(32) AabbBlock {
  float min[3][kBatchLanes];
  float max[3][kBatchLanes];
};

/// A float box that contains the double box `b` (given in a local frame): the center and axes are
/// rounded to float and the half extents are enlarged by the largest displacement that rounding
/// can cause, rounded upward.
Obb<float> toFloatConservative(const Obb<double>& b);
Aabb<float> toFloatConservative(const Aabb<double>& b);

/// Many independent OBB pairs tested at once (the benchmark's and the cross-checks' form).
class ObbPairBatch {
 public:
  ObbPairBatch() = default;
  /// The pairs, each moved to a local frame centred on its box A.
  explicit ObbPairBatch(const std::vector<std::pair<Obb<double>, Obb<double>>>& pairs);

  std::size_t size() const { return pairs_.size(); }
  /// out[k] = 1 when pair k overlaps, else 0; identical to satObbObb<double>(A_k, B_k).overlap.
  /// Returns the number of lanes the float kernel left uncertain (re-decided in double).
  std::size_t test(std::uint8_t* out) const;

 private:
  std::vector<std::pair<Obb<double>, Obb<double>>> pairs_;  // local-frame double originals
  std::vector<ObbBlock> a_, b_;                             // conservative float pairs (A centred)
  std::vector<std::uint8_t> forced_;  // per block: lanes always re-decided in double (odd data)
  std::vector<std::uint8_t> perm_;    // per block: lanes whose two boxes have signed-permutation axes
};

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

/// The equipment's nested volumes, stored for one-vs-many queries against the viewer.
/// Coordinates are in the local frame of the scene (double originals, float blocks).
class NestedBoxSet {
 public:
  NestedBoxSet() = default;
  explicit NestedBoxSet(std::vector<NestedVolume<double>> boxes);

  std::size_t size() const { return boxes_.size(); }
  const NestedVolume<double>& box(std::size_t i) const { return boxes_[i]; }

  /// Appends to `hits` the index of every stored box whose nested test against `viewer` reports
  /// overlap (the verdict of testNested<double>), in increasing index order. Stage 1 (AABB-AABB)
  /// runs over all boxes in SIMD blocks; the survivors go through AABB-OBB and OBB-OBB.
  /// `counters`, when given, is incremented as StageCounters::add would be by testNested's result
  /// for every stored box (so its stage-1 test count grows by size()).
  void queryOverlaps(const NestedVolume<double>& viewer, std::vector<std::uint32_t>& hits,
                     StageCounters* counters = nullptr) const;

 private:
  /// A conservative float inner box, one cache line, gathered for the survivors of stage 1.
  struct alignas(64) InnerBox {
    float center[3];
    float axes[9];  // row-major, as in ObbBlock
    float halfExtents[3];
    std::uint32_t flags;  // float analysis applies (else decided in double); signed-permutation axes
  };

  std::vector<NestedVolume<double>> boxes_;
  std::vector<AabbBlock> outer_;  // conservative float outer boxes; padding lanes are empty boxes
  std::vector<InnerBox> inner_;   // conservative float inner boxes
};

}  // namespace nestwalk
