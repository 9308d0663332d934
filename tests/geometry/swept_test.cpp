// Swept tests (swept.h) against the static tests of sat.h / nested.h sampled along the motion: at
// every sampled t the static verdict must agree with "t lies in the swept interval", except within
// a hair of the interval's ends. Plus the cases the walker relies on: a thin pole passed at 50 m/s
// in one step, grazing motion, no motion, map coordinates at UTM magnitudes.
#include "nestwalk/geometry/swept.h"
#include "tests/geometry/test_shapes.h"

#include <gtest/gtest.h>

#include <random>

namespace nestwalk {
namespace {

using testshapes::randomRotation;

Obb<double> randomObb(std::mt19937& rng, double spread) {
  std::uniform_real_distribution<double> pos(-spread, spread), ext(0.0, 1.5);
  Obb<double> b;
  b.center = Vec3<double>(pos(rng), pos(rng), pos(rng));
  b.axes = randomRotation(rng);
  b.halfExtents = Vec3<double>(ext(rng), ext(rng), ext(rng));
  return b;
}

Obb<double> moved(const Obb<double>& b, const Vec3<double>& d) { return {b.center + d, b.axes, b.halfExtents}; }
NestedVolume<double> moved(const NestedVolume<double>& v, const Vec3<double>& d) {
  return {{v.outer.min + d, v.outer.max + d}, moved(v.inner, d)};
}

/// Samples t on [0, 1] and checks the static verdict against the interval; returns the number of
/// samples compared (all within the tolerance band are skipped).
template <class StaticTest>
int checkAgainstSamples(const SweepResult& r, StaticTest overlapAt, double band) {
  int compared = 0;
  for (int k = 0; k <= 200; ++k) {
    const double t = k / 200.0;
    if (!r.empty() && (std::abs(t - r.enter) < band || std::abs(t - r.exit) < band)) continue;
    const bool inside = !r.empty() && t >= r.enter && t <= r.exit;
    EXPECT_EQ(overlapAt(t), inside) << "t=" << t << " enter=" << r.enter << " exit=" << r.exit;
    ++compared;
  }
  return compared;
}

TEST(Swept, ObbObbIntervalMatchesStaticSatAlongTheMotion) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> dd(-4.0, 4.0);
  int contacts = 0;
  for (int i = 0; i < 4000; ++i) {
    const Obb<double> a = randomObb(rng, 2.0), b = randomObb(rng, 2.0);
    const Vec3<double> d(dd(rng), dd(rng), dd(rng));
    const SweepResult r = sweepObbObb(a, d, b);
    contacts += r.contactInStep();
    checkAgainstSamples(r, [&](double t) { return satObbObb(moved(a, d * t), b).overlap; }, 1e-9);
  }
  EXPECT_GT(contacts, 1000);
}

TEST(Swept, AabbObbAndAabbAabbIntervalsMatchStaticTests) {
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> dd(-4.0, 4.0);
  for (int i = 0; i < 4000; ++i) {
    const Obb<double> a = randomObb(rng, 2.0), b = randomObb(rng, 2.0);
    const Aabb<double> box = aabbOf(a), other = aabbOf(b);
    const Vec3<double> d(dd(rng), dd(rng), dd(rng));
    checkAgainstSamples(sweepAabbObb(box, d, b),
                        [&](double t) { return satAabbObb(Aabb<double>{box.min + d * t, box.max + d * t}, b).overlap; },
                        1e-9);
    checkAgainstSamples(sweepAabbAabb(box, d, other),
                        [&](double t) { return satAabbAabb(Aabb<double>{box.min + d * t, box.max + d * t}, other).overlap; },
                        1e-9);
  }
}

TEST(Swept, NestedContactIsTheFirstTimeAllThreeStagesOverlap) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> dd(-4.0, 4.0);
  for (int i = 0; i < 3000; ++i) {
    // The object's outer box is tighter than the AABB of its OBB (as for a model's exact AABB).
    const Obb<double> ob = randomObb(rng, 2.0);
    NestedVolume<double> object = NestedVolume<double>::fromObb(ob);
    object.outer.max -= 0.3 * (object.outer.max - object.outer.min).cwiseAbs() * 0.5;
    const NestedVolume<double> viewer = NestedVolume<double>::fromObb(randomObb(rng, 2.0));
    const Vec3<double> d(dd(rng), dd(rng), dd(rng));
    const SweptNestedResult r = sweepNested(viewer, d, object);
    // Reference: the first sampled t at which testNested says overlap, by bisection between samples.
    double first = -1;
    for (int k = 0; k <= 400 && first < 0; ++k)
      if (testNested(moved(viewer, d * (k / 400.0)), object).overlap) first = k / 400.0;
    if (first < 0) {
      // No sampled contact: the swept test may only see one between samples.
      if (r.contact) {
        const bool between = testNested(moved(viewer, d * std::min(1.0, r.t + 1e-9)), object).overlap;
        EXPECT_TRUE(between) << "swept contact at t=" << r.t << " not confirmed by the static test";
      }
      continue;
    }
    ASSERT_TRUE(r.contact) << "static contact at t=" << first << " missed";
    EXPECT_LE(r.t, first + 1e-12);
    EXPECT_GE(r.t, first - 1.0 / 400 - 1e-12);
    // The swept slabs carry the slack of the whole step, so the contact may come a hair early.
    EXPECT_TRUE(testNested(moved(viewer, d * std::min(1.0, r.t + 1e-9)), object).overlap);
  }
}

TEST(Swept, ThinPoleIsHitAt50MetresPerSecondInOneStep) {
  // A 5 cm pole, 3 m tall; a 0.5 x 0.5 x 1.8 m body 0.1 m before it moves 50 m/s / 60 Hz.
  for (double offset : {0.0, 5.5e5}) {
    Obb<double> pole;
    pole.center = Vec3<double>(offset + 10.0, offset + 20.0, 1.5);
    pole.halfExtents = Vec3<double>(0.025, 0.025, 1.5);
    Obb<double> body;
    body.center = Vec3<double>(offset + 10.0 - 0.25 - 0.025 - 0.1, offset + 20.0, 0.9);
    body.halfExtents = Vec3<double>(0.25, 0.25, 0.9);
    const Vec3<double> d(50.0 / 60.0, 0, 0);
    EXPECT_FALSE(satObbObb(body, pole).overlap);
    EXPECT_FALSE(satObbObb(moved(body, d), pole).overlap);  // sampling at the step's ends misses it
    const SweptNestedResult r =
        sweepNested(NestedVolume<double>::fromObb(body), d, NestedVolume<double>::fromObb(pole));
    ASSERT_TRUE(r.contact);
    EXPECT_NEAR(r.t * d.norm(), 0.1, 1e-9);
    EXPECT_NEAR(r.normal.x(), -1.0, 1e-12);  // from the pole toward the body
  }
}

TEST(Swept, MotionAlongATouchingFaceTouchesFromTheStartWithANormalAcrossTheMotion) {
  Obb<double> wall;
  wall.center = Vec3<double>(0, 1.0, 1.0);
  wall.halfExtents = Vec3<double>(5.0, 0.5, 1.0);
  Obb<double> body;
  body.center = Vec3<double>(0, 0.25, 0.9);  // touching the wall's face y = 0.5
  body.halfExtents = Vec3<double>(0.25, 0.25, 0.9);
  const Vec3<double> d(1.0, 0, 0);
  const SweepResult r = sweepObbObb(body, d, wall);
  EXPECT_TRUE(r.contactInStep());
  EXPECT_LE(r.enter, 0.0);
  // Moving away from the face: the interval ends at t = 0.
  const SweepResult away = sweepObbObb(body, Vec3<double>(0, -1.0, 0), wall);
  EXPECT_NEAR(away.exit, 0.0, 1e-10);
}

TEST(Swept, NoMotionIsTheStaticTest) {
  std::mt19937 rng(10);
  for (int i = 0; i < 2000; ++i) {
    const Obb<double> a = randomObb(rng, 1.5), b = randomObb(rng, 1.5);
    const SweepResult r = sweepObbObb(a, Vec3<double>::Zero(), b);
    EXPECT_EQ(r.contactInStep(), satObbObb(a, b).overlap);
  }
}

TEST(Swept, UtmMagnitudesGiveTheSameContactTimes) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> dd(-3.0, 3.0);
  const Vec3<double> far(5.5e5, 4.65e6, 120.0);
  for (int i = 0; i < 2000; ++i) {
    const Obb<double> a = randomObb(rng, 2.0), b = randomObb(rng, 2.0);
    const Vec3<double> d(dd(rng), dd(rng), dd(rng));
    const SweepResult r0 = sweepObbObb(a, d, b);
    const SweepResult r1 = sweepObbObb(moved(a, far), d, moved(b, far));
    ASSERT_EQ(r0.contactInStep(), r1.contactInStep()) << i;
    if (r0.contactInStep() && r0.enter > 0) {
      EXPECT_NEAR(r0.enter * d.norm(), r1.enter * d.norm(), 1e-6);
    }
  }
}

}  // namespace
}  // namespace nestwalk
