// Tests of the conservative float boxes of engine/geometry/obb_batch.h (toFloatConservative): they
// contain their double originals, within the enlargement the float kernel's error analysis assumes.
// (testBoxPairs is tested in box_pairs_batch_test.cpp.)
#include "nestwalk/geometry/obb_batch.h"
#include "tests/geometry/box_pair_generators.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <cmath>
#include <limits>

namespace nestwalk {
namespace {

using namespace boxgen;
constexpr double kFloatU = 0x1p-24;


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

}  // namespace
}  // namespace nestwalk
