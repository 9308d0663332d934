// The answers testBoxPairs forms in its SIMD lanes (packedAnswer, engine/geometry/obb_batch_kernel.h)
// against the scalar reading of the three stages' codes it replaced, on every combination: each
// stage's code from "unsure" (-2) and "no separating axis" (-1) to axis 14, whether the float
// analysis applies, and which boxes are axis aligned (testBoxPair swaps the roles when only B is,
// and the stage-2 axis is renamed).
#include "nestwalk/geometry/obb_batch_kernel.h"

#include <gtest/gtest.h>

#include <cstring>

namespace nestwalk {
namespace {

/// An axis of the test (B, A) renamed for (A, B), as testBoxPair does after its swap.
constexpr std::int8_t kSwappedAxisTable[15] = {3, 4, 5, 0, 1, 2, 6, 9, 12, 7, 10, 13, 8, 11, 14};

/// The scalar reading: the first stage that decides, in testBoxPair's order; false when the lane
/// must be decided in double.
bool referenceAnswer(int c1, int c2, int c3, bool good, bool aAl, bool bAl, NestedResult& r) {
  r = {true, OverlapStage::AabbAabb, std::int8_t(kNoAxis)};
  if (!good || c1 == kUnsure) return false;
  if (c1 >= 0 || (aAl && bAl)) {
    r = {c1 < 0, OverlapStage::AabbAabb, std::int8_t(c1)};
    return true;
  }
  if (c2 == kUnsure) return false;
  if (bAl) {
    r = {c2 < 0, OverlapStage::AabbObb, c2 < 0 ? std::int8_t(kNoAxis) : kSwappedAxisTable[c2]};
    return true;
  }
  if (c2 >= 0 || aAl) {
    r = {c2 < 0, OverlapStage::AabbObb, std::int8_t(c2)};
    return true;
  }
  if (c3 == kUnsure) return false;
  r = {c3 < 0, OverlapStage::ObbObb, std::int8_t(c3)};
  return true;
}

TEST(ObbBatchAnswer, LanesAnswerAsTheScalarReadingOfTheStages) {
  int cases = 0, mismatches = 0;
  for (int c1 = kUnsure; c1 < 15; ++c1)
    for (int c2 = kUnsure; c2 < 15; ++c2)
      for (int c3 = kUnsure; c3 < 15; ++c3)
        for (int flags = 0; flags < 8; ++flags) {
          const bool good = flags & 1, aAl = flags & 2, bAl = flags & 4;
          v4i unsure;
          const v4i packed = packedAnswer(v4i{} + c1, v4i{} + c2, v4i{} + c3, v4i{} - int(good), v4i{} - int(aAl),
                                          v4i{} - int(bAl), unsure);
          NestedResult want;
          const bool sure = referenceAnswer(c1, c2, c3, good, aAl, bAl, want);
          ++cases;
          bool same = (unsure[0] == 0) == sure;
          if (same && sure) {
            const std::int32_t lane = packed[0];
            NestedResult got;
            std::memcpy(&got, &lane, sizeof got);
            same = got.overlap == want.overlap && got.stage == want.stage && got.axis == want.axis;
          }
          if (!same && mismatches++ < 5)
            ADD_FAILURE() << "codes " << c1 << ", " << c2 << ", " << c3 << ", good " << good << ", A aligned " << aAl
                          << ", B aligned " << bAl << ": the lanes " << (unsure[0] ? "leave it to double" : "answer")
                          << ", the scalar reading " << (sure ? "answers" : "leaves it to double");
        }
  EXPECT_EQ(cases, 17 * 17 * 17 * 8);
  EXPECT_EQ(mismatches, 0);
}

}  // namespace
}  // namespace nestwalk
