// Tests of testBoxPairs (engine/geometry/obb_batch.h), the batch form of testBoxPair that
// `nestwalk query overlap` runs: every field of every answer (overlap, deciding stage, first
// separating axis) must be the scalar double testBoxPair's, on every SIMD path, for random pairs,
// near-touching ones, parallel, identity, vertical and one-aligned axes, flat boxes and huge
// aspect ratios, near the origin and at UTM-like magnitudes, and for data outside the float
// analysis, with the axes checked by the kernel and vouched for by the caller. Each check prints
// the kernel that ran and how many lanes it left to double.
#include "nestwalk/geometry/obb_batch.h"
#include "tests/geometry/box_pair_generators.h"
#include "tests/geometry/scoped_simd.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace nestwalk {
namespace {

using namespace boxgen;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool same(const NestedResult& x, const NestedResult& y) {
  return x.overlap == y.overlap && x.stage == y.stage && x.axis == y.axis;
}

std::string text(const NestedResult& r) {
  return std::string(r.overlap ? "overlap " : "separated ") + stageName(r.stage) + " axis " + std::to_string(r.axis);
}

struct Checked {
  std::size_t uncertain = 0;  // lanes re-decided in double (first SIMD path)
  std::size_t stage[kStageCount] = {};  // answers per deciding stage
  std::size_t overlaps = 0;
  std::size_t vouched = 0;  // pairs also run with the caller vouching for the axes
};

/// testBoxPairs on `pairs`, read in place (or from two separate arrays), with the axes checked by
/// the kernel or vouched for by the caller; expects `expected` field for field and writes nothing
/// past the last answer. Returns the lanes re-decided in double.
std::size_t runBatch(const std::vector<Pair>& pairs, const std::vector<NestedResult>& expected, bool separateArrays,
                     bool vouched, const std::string& what) {
  std::vector<Obb<double>> as, bs;
  for (const auto& [a, b] : pairs) {
    as.push_back(a);
    bs.push_back(b);
  }
  BoxPairsView view;
  view.count = pairs.size();
  view.orthonormalAxes = vouched;
  if (separateArrays) {
    view.a = as.data();
    view.b = bs.data();
  } else if (!pairs.empty()) {
    view.a = &pairs[0].first;
    view.b = &pairs[0].second;
    view.stride = sizeof(Pair);
  }
  const NestedResult marker{true, OverlapStage::ObbObb, 99};
  std::vector<NestedResult> out(pairs.size() + 1, marker);
  const std::size_t uncertain = testBoxPairs(view, out.data());
  const std::string where = what + " [" + batchKernelName(obbBatchKernel()) + (separateArrays ? ", two arrays" : "") +
                            (vouched ? ", axes vouched" : "") + "]";
  EXPECT_TRUE(same(out.back(), marker)) << where << ": wrote past the end";
  std::size_t mismatches = 0;
  for (std::size_t k = 0; k < pairs.size(); ++k)
    if (!same(out[k], expected[k]) && mismatches++ < 3)
      ADD_FAILURE() << where << " pair " << k << ": " << text(out[k]) << ", testBoxPair: " << text(expected[k]);
  EXPECT_EQ(mismatches, 0u) << where;
  EXPECT_LE(uncertain, pairs.size());
  return uncertain;
}

/// Runs testBoxPairs on `pairs` on every SIMD path, read in place and from two separate arrays,
/// and the pairs whose boxes keep Obb's axes contract again with the caller vouching for the axes;
/// expects testBoxPair's answers field for field.
Checked checkPairs(const std::vector<Pair>& pairs, const std::string& what) {
  Checked c;
  std::vector<NestedResult> expected, keptExpected;
  std::vector<Pair> kept;  // both boxes' axes orthonormal to kAxesTolerance
  for (const auto& [a, b] : pairs) {
    expected.push_back(testBoxPair(a, b));
    ++c.stage[int(expected.back().stage)];
    c.overlaps += expected.back().overlap;
    if (axesError(a.axes) <= kAxesTolerance<double> && axesError(b.axes) <= kAxesTolerance<double>) {
      kept.push_back({a, b});
      keptExpected.push_back(expected.back());
    }
  }
  for (const char* path : kSimdPaths) {
    ScopedSimd simd(path);
    const std::size_t uncertain = runBatch(pairs, expected, false, false, what);
    runBatch(pairs, expected, true, false, what);
    runBatch(kept, keptExpected, false, true, what);
    if (path == kSimdPaths[0]) c.uncertain = uncertain;
    c.vouched = kept.size();
    std::printf("  %-26s %-20s %7zu pairs (%zu vouched), %5.1f%% overlap, stages %6zu/%6zu/%6zu, %5zu re-decided (%.2e)\n",
                what.c_str(), batchKernelName(obbBatchKernel()), pairs.size(), kept.size(),
                100.0 * double(c.overlaps) / double(std::max<std::size_t>(1, pairs.size())), c.stage[0], c.stage[1],
                c.stage[2], uncertain, double(uncertain) / double(std::max<std::size_t>(1, pairs.size())));
  }
  return c;
}

#ifdef NDEBUG
constexpr int kPairScale = 4;
#else
constexpr int kPairScale = 1;
#endif

struct Category {
  const char* name;
  Pair (*make)(Gen&, const Vec3<double>&);
  int count;
  double maxUncertain;  // fraction of re-decided lanes expected at most (near-touching data: more)
};

Pair vertical(Gen& g, const Vec3<double>& o) { return verticalPair(g, o, false); }
Pair verticalTouching(Gen& g, const Vec3<double>& o) { return verticalPair(g, o, true); }
Pair oneAligned(Gen& g, const Vec3<double>& o) { return oneAlignedPair(g, o, false); }
Pair oneAlignedTouching(Gen& g, const Vec3<double>& o) { return oneAlignedPair(g, o, true); }

// Pairs spread at random are nearly all decided in float (the 256u band: ~1e-3 of them is left to
// double); near-touching ones (gaps from 1e-7 m) are left to double by design.
const Category kCategories[] = {
    {"random", randomPair, 60000 * kPairScale, 2e-3},
    {"vertical-axes", vertical, 25000 * kPairScale, 2e-3},
    {"one-aligned", oneAligned, 25000 * kPairScale, 2e-3},
    {"vertical-touching", verticalTouching, 15000 * kPairScale, 1.0},
    {"one-aligned-touching", oneAlignedTouching, 15000 * kPairScale, 1.0},
    {"near-touching", nearTouchingPair, 25000 * kPairScale, 1.0},
    {"parallel-axes", parallelPair, 10000 * kPairScale, 1.0},
    {"identity-axes", identityPair, 10000 * kPairScale, 1.0},
    {"flat-and-elongated", degeneratePair, 25000 * kPairScale, 1.0},
};

TEST(TestBoxPairs, EqualsTestBoxPairFieldForField) {
  std::printf("testBoxPairs vs testBoxPair:\n");
  const Vec3<double> origins[] = {Vec3<double>::Zero(), Vec3<double>(5.0e5, 7.0e6, 300.0),
                                  Vec3<double>(-4.9e5, 6.9e6, -50.0)};
  std::size_t total = 0, uncertain = 0;
  for (int o = 0; o < 3; ++o) {
    for (const Category& c : kCategories) {
      Gen g(5000 + 31 * std::uint64_t(&c - kCategories) + std::uint64_t(o));
      const int count = o == 0 ? c.count : c.count / 3;  // near the origin, then two map offsets
      std::vector<Pair> pairs;
      for (int k = 0; k < count; ++k) pairs.push_back(c.make(g, origins[o]));
      const Checked r = checkPairs(pairs, std::string(c.name) + (o == 0 ? "" : o == 1 ? " @5e5,7e6" : " @-4.9e5,6.9e6"));
      EXPECT_LE(double(r.uncertain), c.maxUncertain * double(pairs.size())) << c.name;
      EXPECT_EQ(r.vouched, pairs.size()) << c.name << ": generated boxes keep Obb's axes contract";
      total += pairs.size();
      uncertain += r.uncertain;
      if (std::string(c.name) == "random") {
        for (int s = 0; s < kStageCount; ++s) EXPECT_GT(r.stage[s], pairs.size() / 20) << "stage " << s;
      }
    }
  }
  std::printf("  total %zu pairs, %zu re-decided in double\n", total, uncertain);
}

TEST(TestBoxPairs, SizesAndPaddingLanes) {
  Gen g(71);
  for (const int n : {0, 1, 3, 7, 8, 9, 15, 16, 17, 127, 128, 129, 255, 257, 1000}) {
    std::vector<Pair> pairs;
    for (int k = 0; k < n; ++k)
      pairs.push_back(k % 3 == 0   ? randomPair(g, Vec3<double>::Zero())
                      : k % 3 == 1 ? verticalPair(g, Vec3<double>::Zero(), k % 2 == 0)
                                   : oneAlignedPair(g, Vec3<double>::Zero(), k % 2 == 0));
    checkPairs(pairs, "n=" + std::to_string(n));
  }
}

// NESTWALK_SIMD caps the kernel; unset, the widest the processor has runs (AVX-512 where it is
// built and the processor has F, VL, BW and DQ; AVX2 where it has AVX2 and FMA).
TEST(TestBoxPairs, SimdSettingChoosesTheKernel) {
  BatchKernel widest = BatchKernel::Portable;
#if defined(__x86_64__) && defined(__GNUC__)
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
    widest = BatchKernel::Avx2;
#ifdef NESTWALK_OBB_BATCH_AVX512
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
        __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq"))
      widest = BatchKernel::Avx512;
#endif
  }
#endif
  std::printf("  widest kernel here: %s\n", batchKernelName(widest));
  {
    ScopedSimd simd(nullptr);
    EXPECT_EQ(obbBatchKernel(), widest);
  }
  {
    ScopedSimd simd("avx2");
    EXPECT_EQ(obbBatchKernel(), widest == BatchKernel::Avx512 ? BatchKernel::Avx2 : widest);
  }
  {
    ScopedSimd simd("portable");
    EXPECT_EQ(obbBatchKernel(), BatchKernel::Portable);
  }
}

TEST(TestBoxPairs, OddInputsFollowTestBoxPair) {
  // Data outside the float analysis must still get testBoxPair's answer: non-finite numbers, huge
  // ones, negative or subnormal half extents, axes that are not orthonormal, exact touching.
  Gen g(72);
  std::vector<Pair> pairs;
  const Obb<double> unit{{0, 0, 0}, Mat3<double>::Identity(), {1, 1, 1}};
  const Obb<double> turned{{0, 0, 0}, g.rotation(), {1, 0.5, 2}};
  for (const Obb<double>& base : {unit, turned}) {
    auto add = [&](const Obb<double>& b) {
      pairs.emplace_back(base, b);
      pairs.emplace_back(b, base);
    };
    Obb<double> b = turned;
    for (const Vec3<double>& c : {Vec3<double>(2.0, 0, 0), Vec3<double>(kNaN, 0, 0), Vec3<double>(kInf, 0, 0),
                                  Vec3<double>(1e30, 0, 0), Vec3<double>(1e300, -1e300, 0), Vec3<double>(3, 1, 0)}) {
      b.center = c;
      add(b);
    }
    b = unit;
    b.center = {2, 0, 0};  // exactly touching when base is the unit box
    add(b);
    b.halfExtents = {kInf, 1, 1};
    add(b);
    b.halfExtents = {-1, 1, 1};
    add(b);
    b.halfExtents = {-1e-50, 1, 1};
    add(b);
    b.halfExtents = {1e25, 1, 1};
    b.center = {3e25, 0, 0};
    add(b);
    b = turned;
    b.axes *= 1.5;  // not orthonormal
    b.center = {2.2, 0, 0};
    add(b);
    b.axes = Mat3<double>::Constant(kNaN);
    add(b);
    b = unit;
    b.axes(0, 1) = 1e-45;  // nearly the identity, with an entry below float's range
    add(b);
    b.halfExtents = {1e-40, 1e-320, 0};  // subnormal in float, and in double
    b.center = {1 + 2e-40, 0, 0};
    add(b);
    const Obb<double> tiny{{0, 0, 0}, g.rotation(), {1e-42, 3e-41, 0}};
    pairs.emplace_back(tiny, Obb<double>{{1e-41, -2e-41, 0}, g.rotation(), {1e-41, 1e-41, 1e-41}});
    pairs.emplace_back(tiny, tiny);
  }
  for (int k = 0; k < 40; ++k) pairs.emplace_back(unit, randomPair(g, Vec3<double>::Zero()).second);  // fill blocks
  checkPairs(pairs, "odd inputs");
}

}  // namespace
}  // namespace nestwalk
