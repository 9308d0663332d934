// Tests of the float SIMD batches (engine/geometry/obb_batch.h): the conservative float boxes, and
// the verdicts of ObbPairBatch and NestedBoxSet, which must be exactly those of the scalar double
// tests of sat.h / nested.h, on both SIMD paths (AVX2 where the machine has it, and the portable one).
#include "nestwalk/geometry/obb_batch.h"
#include "tests/geometry/box_pair_generators.h"
#include "tests/geometry/scoped_simd.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace nestwalk {
namespace {

using namespace boxgen;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kFloatU = 0x1p-24;


// Optimized builds check over a million pairs (about 1.5 s); unoptimized ones a quarter of that.
#ifdef NDEBUG
constexpr int kPairScale = 4;
#else
constexpr int kPairScale = 1;
#endif

struct Category {
  const char* name;
  Pair (*make)(Gen&, const Vec3<double>&);
  int count;
};

const Category kCategories[] = {
    {"random", randomPair, 150000 * kPairScale},
    {"near-touching", nearTouchingPair, 62500 * kPairScale},
    {"parallel-axes", parallelPair, 25000 * kPairScale},
    {"identity-axes", identityPair, 12500 * kPairScale},
};

/// Runs the batch on `pairs` on every SIMD path, asserts the verdicts equal the scalar double test
/// on the original pairs and on the pairs moved to A's local frame, and returns the number of
/// uncertain lanes of the first path (and the overlap count).
std::pair<std::size_t, std::size_t> checkBatch(const std::vector<Pair>& pairs, const std::string& what) {
  std::vector<std::uint8_t> expected(pairs.size());
  std::size_t overlaps = 0, shiftChanges = 0;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto& [a, b] = pairs[k];
    expected[k] = satObbObb<double>(a, b).overlap ? 1 : 0;
    Obb<double> la = a, lb = b;
    la.center.setZero();
    lb.center = b.center - a.center;
    shiftChanges += (satObbObb<double>(la, lb).overlap ? 1 : 0) != expected[k];
    overlaps += expected[k];
  }
  EXPECT_EQ(shiftChanges, 0u) << what << ": moving the pair to A's frame changed the double verdict";

  const ObbPairBatch batch(pairs);
  EXPECT_EQ(batch.size(), pairs.size());
  std::size_t firstUncertain = 0;
  for (const char* path : kSimdPaths) {
    ScopedSimd simd(path);
    std::vector<std::uint8_t> out(pairs.size() + 1, 0xAB);
    const std::size_t uncertain = batch.test(out.data());
    if (path == kSimdPaths[0]) firstUncertain = uncertain;
    EXPECT_EQ(out.back(), 0xAB) << what << ": wrote past the end";
    std::size_t mismatches = 0, firstBad = pairs.size();
    for (std::size_t k = 0; k < pairs.size(); ++k)
      if (out[k] != expected[k]) {
        if (mismatches++ == 0) firstBad = k;
      }
    EXPECT_EQ(mismatches, 0u) << what << " [" << simdPathName(path) << "]: first mismatch at pair " << firstBad;
    EXPECT_LE(uncertain, pairs.size());
    std::printf("  %-28s %-9s %8zu pairs, %5.1f%% overlap, %6zu uncertain lanes (%.2e)\n", what.c_str(),
                simdPathName(path), pairs.size(), 100.0 * double(overlaps) / double(std::max<std::size_t>(1, pairs.size())),
                uncertain, double(uncertain) / double(std::max<std::size_t>(1, pairs.size())));
  }
  return {firstUncertain, overlaps};
}

// ----------------------------------------------------------------------------------------------
// toFloatConservative

TEST(ToFloatConservative, ObbContainsTheDoubleBox) {
  Gen g(11);
  for (int n = 0; n < 20000; ++n) {
    Obb<double> b{g.inCube(g.chance(0.5) ? 3000.0 : 1.0), g.rotation(), g.halfExtents(0.2)};
    if (n % 5 == 0) b.axes = Mat3<double>::Identity();
    if (n % 7 == 0) b.center = b.center.cast<float>().cast<double>();  // exact in float
    if (n % 11 == 0) b.halfExtents.setZero();                          // a point
    const Obb<float> f = toFloatConservative(b);
    const Obb<double> fd = f.cast<double>();
    const Mat3<double> inv = fd.axes.inverse();
    // The enlargement stays within the bound the kernel's error analysis relies on.
    const double bound = 2 * kFloatU * b.center.lpNorm<1>() + 9.5 * kFloatU * b.halfExtents.sum() + 1e-30;
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(fd.halfExtents[k], b.halfExtents[k]);
      EXPECT_LE(fd.halfExtents[k] - b.halfExtents[k], bound) << "box " << n;
      EXPECT_EQ(f.center[k], float(b.center[k]));  // rounded to nearest
    }
    for (int i = 0; i < 8; ++i) {
      const Vec3<double> p = b.corner(i);
      // Obb::contains (fl(A)^T (p - fl(c))), and the parallelepiped fl(c) + fl(A) y.
      ASSERT_TRUE(fd.contains(p)) << "box " << n << " corner " << i;
      const Vec3<double> y = inv * (p - fd.center);
      ASSERT_TRUE((y.cwiseAbs().array() <= fd.halfExtents.array()).all()) << "box " << n << " corner " << i;
    }
  }
}

TEST(ToFloatConservative, ExactBoxesStayExact) {
  const Obb<double> b{{1.5, -2.25, 1000.0}, Mat3<double>::Identity(), {0, 0, 0}};
  const Obb<float> f = toFloatConservative(b);
  EXPECT_EQ(f.center, Vec3<float>(1.5f, -2.25f, 1000.0f));
  EXPECT_EQ(f.halfExtents, Vec3<float>::Zero());
  EXPECT_TRUE(f.isAxisAligned());
}

TEST(ToFloatConservative, AabbRoundsOutward) {
  Gen g(12);
  for (int n = 0; n < 20000; ++n) {
    const Vec3<double> c = g.inCube(3000.0), h = g.halfExtents(0.2);
    const Aabb<double> b{c - h, c + h};
    const Aabb<float> f = toFloatConservative(b);
    for (int k = 0; k < 3; ++k) {
      ASSERT_LE(double(f.min[k]), b.min[k]);
      ASSERT_GE(double(f.max[k]), b.max[k]);
      // The tightest float bounds.
      ASSERT_GT(double(std::nextafter(f.min[k], std::numeric_limits<float>::infinity())), b.min[k]);
      ASSERT_LT(double(std::nextafter(f.max[k], -std::numeric_limits<float>::infinity())), b.max[k]);
    }
  }
  const Aabb<float> empty = toFloatConservative(Aabb<double>{});
  EXPECT_TRUE(empty.isEmpty());
  const Aabb<float> huge = toFloatConservative(Aabb<double>{Vec3<double>::Constant(-1e300), Vec3<double>::Constant(1e300)});
  EXPECT_TRUE((huge.min.array() <= -std::numeric_limits<float>::max()).all());
  EXPECT_TRUE((huge.max.array() >= std::numeric_limits<float>::max()).all());
}

// ----------------------------------------------------------------------------------------------
// ObbPairBatch

TEST(ObbPairBatch, EqualsScalarDoubleOnOverAMillionPairs) {
  std::printf("ObbPairBatch vs satObbObb<double>:\n");
  const Vec3<double> utm(5.5e5, 4.65e6, 300.0);
  std::size_t total = 0;
  for (const bool atUtm : {false, true}) {
    for (const Category& c : kCategories) {
      Gen g(1000 + 17 * std::uint64_t(&c - kCategories) + (atUtm ? 1 : 0));
      // Near the origin: A's centre within 1 km of it (a local frame); at UTM: 1/3 of the count.
      const int count = atUtm ? c.count / 3 : c.count;
      std::vector<Pair> pairs;
      pairs.reserve(std::size_t(count));
      for (int k = 0; k < count; ++k) pairs.push_back(c.make(g, atUtm ? utm : Vec3<double>::Zero()));
      const auto [uncertain, overlaps] = checkBatch(pairs, std::string(c.name) + (atUtm ? " @UTM" : ""));
      total += pairs.size();
      if (std::string(c.name) == "random") {
        // The mixture is meant to be about half overlapping, and the float filter to decide nearly all.
        EXPECT_GT(overlaps, pairs.size() * 35 / 100);
        EXPECT_LT(overlaps, pairs.size() * 65 / 100);
        EXPECT_LT(uncertain, pairs.size() / 1000);
      }
    }
  }
  EXPECT_GE(total, 250000u * kPairScale);
}

TEST(ObbPairBatch, AxisAlignedPairsAreDecidedInFloat) {
  // Boxes whose axes are exactly signed permutations (the identity above all) have exactly
  // parallel edges: the float kernel must still decide them unless they nearly touch.
  Gen g(22);
  std::vector<Pair> pairs;
  for (int k = 0; k < 40000; ++k) {
    Pair p = randomPair(g, Vec3<double>::Zero());
    p.first.axes = k % 2 ? Mat3<double>(Mat3<double>::Identity()) : g.signedPermutation();
    p.second.axes = k % 3 ? Mat3<double>(Mat3<double>::Identity()) : g.signedPermutation();
    pairs.push_back(p);
  }
  const auto [uncertain, overlaps] = checkBatch(pairs, "axis-aligned random");
  EXPECT_GT(overlaps, pairs.size() / 4);
  EXPECT_LT(uncertain, pairs.size() / 1000);
}

TEST(ObbPairBatch, SizesAndPaddingLanes) {
  Gen g(21);
  for (const int n : {0, 1, 7, 8, 9, 15, 16, 17, 100}) {
    std::vector<Pair> pairs;
    for (int k = 0; k < n; ++k) pairs.push_back(k % 2 ? randomPair(g, Vec3<double>::Zero()) : nearTouchingPair(g, Vec3<double>::Zero()));
    checkBatch(pairs, "n=" + std::to_string(n));
  }
  const ObbPairBatch empty;
  EXPECT_EQ(empty.size(), 0u);
  EXPECT_EQ(empty.test(nullptr), 0u);
}

TEST(ObbPairBatch, OddInputsFollowTheDoubleTest) {
  // Data outside the float analysis (non-finite, huge, negative half extents, axes that are not
  // orthonormal, boxes far apart at float-overflowing distances) must still get the double verdict.
  Gen g(31);
  std::vector<Pair> pairs;
  const Obb<double> unit{{0, 0, 0}, Mat3<double>::Identity(), {1, 1, 1}};
  auto add = [&](Obb<double> a, Obb<double> b) { pairs.emplace_back(a, b); };
  Obb<double> b = unit;
  b.center = {1.5, 0, 0};
  add(unit, b);
  b.center = {kNaN, 0, 0};
  add(unit, b);
  b.center = {kInf, 0, 0};
  add(unit, b);
  b.center = {1e30, 0, 0};
  add(unit, b);
  b.center = {1e300, -1e300, 0};
  add(unit, b);
  b = unit;
  b.halfExtents = {kInf, 1, 1};
  b.center = {5, 0, 0};
  add(unit, b);
  b.halfExtents = {-1, 1, 1};
  add(unit, b);
  b.halfExtents = {1e25, 1, 1};
  b.center = {3e25, 0, 0};
  add(unit, b);
  b = unit;
  b.axes *= 1.5;  // not orthonormal
  b.center = {2.2, 0, 0};
  add(unit, b);
  b.axes = Mat3<double>::Constant(kNaN);
  add(unit, b);
  b = unit;
  b.halfExtents = {1e-40, 1e-40, 1e-40};  // subnormal in float
  b.center = {1 + 2e-40, 0, 0};
  add(unit, b);
  Obb<double> tiny{{0, 0, 0}, g.rotation(), {1e-42, 3e-41, 0}};
  Obb<double> tiny2{{1e-41, -2e-41, 0}, g.rotation(), {1e-41, 1e-41, 1e-41}};
  add(tiny, tiny2);
  add(tiny, tiny);
  for (int k = 0; k < 40; ++k) add(unit, randomPair(g, Vec3<double>::Zero()).second);  // fill blocks
  checkBatch(pairs, "odd inputs");
}

// ----------------------------------------------------------------------------------------------
// NestedBoxSet

NestedVolume<double> randomVolume(Gen& g, double spread, double size) {
  Obb<double> inner{g.inCube(spread), g.chance(0.2) ? Mat3<double>(Mat3<double>::Identity()) : g.rotation(),
                    g.halfExtents(0.1) * (size / 10.0)};
  NestedVolume<double> v = NestedVolume<double>::fromObb(inner);
  if (g.chance(0.3)) {  // a looser outer box (e.g. around the object rather than the inner box)
    v.outer.min -= Vec3<double>(g.uniform(0, size), g.uniform(0, size), g.uniform(0, size)) * 0.3;
    v.outer.max += Vec3<double>(g.uniform(0, size), g.uniform(0, size), g.uniform(0, size)) * 0.3;
  }
  if (g.chance(0.1)) {  // an outer box that does not contain the inner one
    v.outer = Aabb<double>::fromCenterHalfExtents(inner.center + g.inCube(size * 0.2), inner.halfExtents);
  }
  return v;
}

/// A viewer touching or nearly touching a stored volume, on its inner box or its outer box.
NestedVolume<double> nearViewer(Gen& g, const NestedVolume<double>& box) {
  Obb<double> inner{box.inner.center + g.inCube(5.0), g.rotation(), g.halfExtents(0.1)};
  if (g.chance(0.5)) {
    placeAlong(box.inner, inner, satAxis(g, box.inner, inner), signedGap(g));
    NestedVolume<double> v = NestedVolume<double>::fromObb(inner);
    if (g.chance(0.3)) v.outer.max += g.inCube(0.5).cwiseAbs();
    return v;
  }
  // Outer box touching the stored outer box on one axis (exact or within a small gap).
  NestedVolume<double> v = NestedVolume<double>::fromObb(inner);
  const int k = g.index(3);
  const double shift = box.outer.max[k] - v.outer.min[k] + (g.chance(0.3) ? 0.0 : signedGap(g));
  v.outer.min[k] += shift;
  v.outer.max[k] += shift;
  v.inner.center[k] += shift;
  return v;
}

/// Checks every viewer's query against brute-force testNested on every SIMD path; returns the
/// summed counters of one path (to show which stages the checks reached).
StageCounters checkQueries(const NestedBoxSet& set, const std::vector<NestedVolume<double>>& viewers,
                           const std::string& what) {
  StageCounters total;
  for (const char* path : kSimdPaths) {
    ScopedSimd simd(path);
    for (std::size_t q = 0; q < viewers.size(); ++q) {
      const NestedVolume<double>& viewer = viewers[q];
      std::vector<std::uint32_t> expected = {424242u};  // hits are appended
      StageCounters expectedCounters;
      expectedCounters.tests[2] = 5;  // counters are added to
      for (std::size_t i = 0; i < set.size(); ++i) {
        const NestedResult r = testNested(viewer, set.box(i));
        if (r.overlap) expected.push_back(std::uint32_t(i));
        expectedCounters.add(r);
      }
      std::vector<std::uint32_t> hits = {424242u};
      StageCounters counters;
      counters.tests[2] = 5;
      set.queryOverlaps(viewer, hits, &counters);
      EXPECT_EQ(hits, expected) << what << " [" << simdPathName(path) << "] viewer " << q;
      EXPECT_EQ(counters.tests, expectedCounters.tests) << what << " [" << simdPathName(path) << "] viewer " << q;
      EXPECT_EQ(counters.separated, expectedCounters.separated) << what << " [" << simdPathName(path) << "] viewer " << q;
      std::vector<std::uint32_t> hits2;
      set.queryOverlaps(viewer, hits2);  // without counters
      EXPECT_EQ(hits2, std::vector<std::uint32_t>(expected.begin() + 1, expected.end()));
      if (path == kSimdPaths[0]) {
        counters.tests[2] -= 5;
        for (int s = 0; s < kStageCount; ++s) {
          total.tests[s] += counters.tests[s];
          total.separated[s] += counters.separated[s];
        }
      }
    }
  }
  return total;
}

void printCounters(const char* what, const StageCounters& c) {
  std::printf("  %-22s stage tests %8llu / %7llu / %7llu, separated %8llu / %7llu / %7llu\n", what,
              (unsigned long long)c.tests[0], (unsigned long long)c.tests[1], (unsigned long long)c.tests[2],
              (unsigned long long)c.separated[0], (unsigned long long)c.separated[1],
              (unsigned long long)c.separated[2]);
}

TEST(NestedBoxSet, EqualsBruteForceTestNested) {
  Gen g(41);
  std::size_t queries = 0;
  StageCounters total;
  for (const int n : {1, 2, 7, 8, 9, 13, 64, 100, 1001, 4099}) {
    std::vector<NestedVolume<double>> boxes;
    for (int i = 0; i < n; ++i) boxes.push_back(randomVolume(g, 60.0, 10.0));
    // Identical copies and exact duplicates of neighbours across lanes.
    if (n > 3) boxes[2] = boxes[1];
    const NestedBoxSet set(boxes);
    ASSERT_EQ(set.size(), std::size_t(n));
    std::vector<NestedVolume<double>> viewers;
    for (int q = 0; q < 120; ++q) viewers.push_back(randomVolume(g, 60.0, g.logUniform(1.0, 300.0)));
    for (int q = 0; q < 120; ++q) viewers.push_back(nearViewer(g, boxes[std::size_t(g.index(n))]));
    viewers.push_back(boxes[0]);  // the box itself
    const StageCounters c = checkQueries(set, viewers, "n=" + std::to_string(n));
    for (int s = 0; s < kStageCount; ++s) {
      total.tests[s] += c.tests[s];
      total.separated[s] += c.separated[s];
    }
    queries += viewers.size();
  }
  EXPECT_GT(queries, 2400u);
  printCounters("random sets", total);
  // The checks reach every stage, with separations at each.
  for (int s = 0; s < kStageCount; ++s) EXPECT_GT(total.separated[s], 100u) << "stage " << s;
}

TEST(NestedBoxSet, FarFromTheOriginAndManyNearTouchingBoxes) {
  // A local frame a few km across; boxes packed around one spot so that most survive stage 1.
  Gen g(42);
  std::vector<NestedVolume<double>> boxes;
  const Vec3<double> spot(2500.0, -1800.0, 120.0);
  const NestedVolume<double> viewer = randomVolume(g, 0.0, 6.0);
  NestedVolume<double> shiftedViewer = viewer;
  shiftedViewer.inner.center += spot;
  shiftedViewer.outer.min += spot;
  shiftedViewer.outer.max += spot;
  for (int i = 0; i < 3001; ++i) {
    NestedVolume<double> b = i % 3 ? nearViewer(g, shiftedViewer) : randomVolume(g, 20.0, 8.0);
    if (i % 3 == 0) {
      b.inner.center += spot;
      b.outer.min += spot;
      b.outer.max += spot;
    }
    boxes.push_back(b);
  }
  const NestedBoxSet set(boxes);
  printCounters("near-touching set", checkQueries(set, {shiftedViewer}, "near-touching set"));
  std::vector<NestedVolume<double>> viewers;
  for (int q = 0; q < 20; ++q) viewers.push_back(nearViewer(g, boxes[std::size_t(g.index(3001))]));
  printCounters("far set", checkQueries(set, viewers, "far set"));
}

TEST(NestedBoxSet, EmptySetAndOddViewers) {
  Gen g(43);
  const NestedBoxSet empty;
  std::vector<std::uint32_t> hits = {7u};
  StageCounters counters;
  empty.queryOverlaps(randomVolume(g, 10, 10), hits, &counters);
  EXPECT_EQ(hits, std::vector<std::uint32_t>{7u});
  EXPECT_EQ(counters.tests, (std::array<std::uint64_t, kStageCount>{}));
  EXPECT_EQ(NestedBoxSet(std::vector<NestedVolume<double>>{}).size(), 0u);

  // Sets of 1..17 boxes (padding lanes in every position) against viewers that cover everything,
  // nothing, or are not numbers at all: padding lanes must never hit.
  std::vector<NestedVolume<double>> viewers;
  NestedVolume<double> all;
  all.outer = {Vec3<double>::Constant(-kInf), Vec3<double>::Constant(kInf)};
  all.inner = {{0, 0, 0}, Mat3<double>::Identity(), Vec3<double>::Constant(1e6)};
  viewers.push_back(all);
  NestedVolume<double> big;
  big.outer = {Vec3<double>::Constant(-1e6), Vec3<double>::Constant(1e6)};
  big.inner = all.inner;
  viewers.push_back(big);
  viewers.push_back(NestedVolume<double>{});  // empty outer box, zero inner box at the origin
  NestedVolume<double> nan = big;
  nan.outer.min[1] = kNaN;
  nan.inner.center[0] = kNaN;
  viewers.push_back(nan);
  NestedVolume<double> flat = NestedVolume<double>::fromObb({{0, 0, 0}, Mat3<double>::Identity(), {50, 50, 0}});
  viewers.push_back(flat);
  for (int n = 1; n <= 17; ++n) {
    std::vector<NestedVolume<double>> boxes;
    for (int i = 0; i < n; ++i) boxes.push_back(randomVolume(g, 30.0, 10.0));
    boxes.back().outer = Aabb<double>{};          // an empty stored box
    if (n > 2) boxes[1].inner.center[2] = kNaN;   // a stored box with a NaN
    if (n > 4) boxes[3].inner.axes *= 2.0;        // axes that are not orthonormal
    checkQueries(NestedBoxSet(boxes), viewers, "odd n=" + std::to_string(n));
  }
}

}  // namespace
}  // namespace nestwalk
