// Tests of engine/geometry/volumes.h: Aabb, Obb, aabbOf, Similarity, orthonormalized, axesError.
// Expected values are hand-computed or come from long double recomputations written here (corners,
// polar decomposition by Newton iteration), not from the code under test.
#include "nestwalk/geometry/volumes.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace nestwalk {
namespace {

using Vec3d = Vec3<double>;
using Mat3d = Mat3<double>;
using ld = long double;
constexpr double kU = 1.1102230246251565e-16;  // 2^-53

Mat3d randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0, 1);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  return q.toRotationMatrix();
}

Obb<double> randomObb(std::mt19937_64& rng, double centreScale) {
  std::uniform_real_distribution<double> u(-1, 1), h(0, 3);
  Obb<double> b;
  b.center = Vec3d(u(rng), u(rng), u(rng)) * centreScale;
  b.axes = randomRotation(rng);
  for (int k = 0; k < 3; ++k) b.halfExtents[k] = std::uniform_int_distribution<int>(0, 7)(rng) == 0 ? 0.0 : h(rng);
  return b;
}

// The 8 corners in long double from the double data (sign bits as documented: bit k -> axis k).
Vec3<ld> cornerLd(const Obb<double>& b, int i) {
  Vec3<ld> p = b.center.cast<ld>();
  for (int k = 0; k < 3; ++k) p += ((i >> k) & 1 ? ld(1) : ld(-1)) * ld(b.halfExtents[k]) * b.axes.col(k).cast<ld>();
  return p;
}

// ------------------------------------------------------------------------------------------------

TEST(Volumes, AabbDefaultIsEmpty) {
  const Aabb<double> e;
  EXPECT_TRUE(e.isEmpty());
  EXPECT_EQ(e.volume(), 0.0);
  EXPECT_FALSE(e.contains(Vec3d::Zero()));
  Aabb<double> p;
  p.extend(Vec3d(1, 2, 3));  // a point box: not empty, zero volume
  EXPECT_FALSE(p.isEmpty());
  EXPECT_EQ(p.min, Vec3d(1, 2, 3));
  EXPECT_EQ(p.max, Vec3d(1, 2, 3));
  EXPECT_EQ(p.volume(), 0.0);
  EXPECT_TRUE(p.contains(Vec3d(1, 2, 3)));
}

TEST(Volumes, AabbBasics) {
  const Aabb<double> b = Aabb<double>::fromCenterHalfExtents(Vec3d(1, 2, 3), Vec3d(0.5, 1, 2));
  EXPECT_EQ(b.min, Vec3d(0.5, 1, 1));
  EXPECT_EQ(b.max, Vec3d(1.5, 3, 5));
  EXPECT_EQ(b.center(), Vec3d(1, 2, 3));
  EXPECT_EQ(b.halfExtents(), Vec3d(0.5, 1, 2));
  EXPECT_EQ(b.size(), Vec3d(1, 2, 4));
  EXPECT_EQ(b.volume(), 8.0);
  EXPECT_FALSE(b.isEmpty());
  // Closed: the boundary is inside; the tolerance widens every side.
  EXPECT_TRUE(b.contains(Vec3d(1.5, 3, 5)));
  EXPECT_TRUE(b.contains(Vec3d(0.5, 1, 1)));
  EXPECT_FALSE(b.contains(Vec3d(1.5 + 1e-9, 2, 3)));
  EXPECT_TRUE(b.contains(Vec3d(1.5 + 1e-9, 2, 3), 2e-9));
  EXPECT_FALSE(b.contains(Vec3d(0.5 - 3e-9, 2, 3), 2e-9));
  // extend by a box and by a point
  Aabb<double> c = b;
  c.extend(Aabb<double>{Vec3d(-1, 2, 2), Vec3d(0, 7, 3)});
  EXPECT_EQ(c.min, Vec3d(-1, 1, 1));
  EXPECT_EQ(c.max, Vec3d(1.5, 7, 5));
  c.extend(Vec3d(10, -10, 4));
  EXPECT_EQ(c.min, Vec3d(-1, -10, 1));
  EXPECT_EQ(c.max, Vec3d(10, 7, 5));
  // Extending by the empty box changes nothing.
  Aabb<double> d = b;
  d.extend(Aabb<double>{});
  EXPECT_EQ(d.min, b.min);
  EXPECT_EQ(d.max, b.max);
  // cast
  const Aabb<float> f = b.cast<float>();
  EXPECT_EQ(f.min, Vec3<float>(0.5f, 1, 1));
  EXPECT_EQ(f.max, Vec3<float>(1.5f, 3, 5));
}

TEST(Volumes, FlatAabbsAreNotEmpty) {
  const Aabb<double> panel{Vec3d(0, 0, 1), Vec3d(2, 3, 1)};
  EXPECT_FALSE(panel.isEmpty());
  EXPECT_EQ(panel.volume(), 0.0);
  EXPECT_TRUE(panel.contains(Vec3d(1, 1, 1)));
  EXPECT_FALSE(panel.contains(Vec3d(1, 1, 1 + 1e-12)));
  const Aabb<double> inverted{Vec3d(0, 0, 1), Vec3d(2, 3, 0.5)};  // min > max on one axis
  EXPECT_TRUE(inverted.isEmpty());
  EXPECT_EQ(inverted.volume(), 0.0);
}

TEST(Volumes, ObbBasics) {
  Obb<double> b;
  EXPECT_TRUE(b.isAxisAligned());
  EXPECT_EQ(b.volume(), 0.0);
  b.center = Vec3d(1, 2, 3);
  b.halfExtents = Vec3d(0.5, 1, 2);
  EXPECT_EQ(b.volume(), 8.0);
  // Corner bit order: bit k chooses + along axis k.
  EXPECT_EQ(b.corner(0), Vec3d(0.5, 1, 1));
  EXPECT_EQ(b.corner(1), Vec3d(1.5, 1, 1));
  EXPECT_EQ(b.corner(2), Vec3d(0.5, 3, 1));
  EXPECT_EQ(b.corner(4), Vec3d(0.5, 1, 5));
  EXPECT_EQ(b.corner(7), Vec3d(1.5, 3, 5));
  EXPECT_TRUE(b.contains(b.corner(7)));
  EXPECT_FALSE(b.contains(Vec3d(1.5 + 1e-9, 2, 3)));
  // fromAabb
  const Obb<double> f = Obb<double>::fromAabb(Aabb<double>{Vec3d(0, 0, 0), Vec3d(2, 4, 6)});
  EXPECT_EQ(f.center, Vec3d(1, 2, 3));
  EXPECT_EQ(f.halfExtents, Vec3d(1, 2, 3));
  EXPECT_TRUE(f.isAxisAligned());
  // A 90 degree rotation about z (exact): not axis aligned; the corners move accordingly.
  Obb<double> r = b;
  r.axes << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  EXPECT_FALSE(r.isAxisAligned());
  // axis 0 = world y, axis 1 = world -x: corner 1 = c + 0.5 y + 1 x - 2 z.
  EXPECT_EQ(r.corner(1), Vec3d(2, 2.5, 1));
  EXPECT_EQ(r.corner(2), Vec3d(0, 1.5, 1));  // c - 0.5 y - 1 x - 2 z
  EXPECT_TRUE(r.contains(Vec3d(0, 2.5, 5)));
  EXPECT_TRUE(r.contains(Vec3d(1.5, 2, 3)));    // 0.5 along world x: within the half extent 1
  EXPECT_FALSE(r.contains(Vec3d(1, 2.75, 3)));  // inside the unrotated box, outside this one
  EXPECT_TRUE(b.contains(Vec3d(1, 2.75, 3)));
  const Obb<float> rf = r.cast<float>();
  EXPECT_EQ(rf.corner(1), Vec3<float>(2, 2.5f, 1));
}

TEST(Volumes, ObbContainsItsCornersWithinRounding) {
  std::mt19937_64 rng(7);
  int exactMisses = 0;
  for (int it = 0; it < 20000; ++it) {
    const Obb<double> b = randomObb(rng, 100);
    const double tol = 8 * kU * (b.center.cwiseAbs().maxCoeff() + b.halfExtents.sum());
    for (int i = 0; i < 8; ++i) {
      EXPECT_TRUE(b.contains(b.corner(i), tol));
      if (!b.contains(b.corner(i))) ++exactMisses;
    }
  }
  // With tol = 0 rounding puts some corners of rotated boxes just outside: containment needs a tol.
  std::printf("corners outside with tol = 0 (rotated boxes, rounding): %d of 160000\n", exactMisses);
}

TEST(Volumes, AabbOfObbIsTheAabbOfItsCornersRoundedOutward) {
  // volumes.h: the AABB |axes| e around the centre, rounded outward (kOutwardRounding) so that it
  // contains the OBB despite rounding. Oracle: the 8 corners in long double from the double data
  // (exact to ~1e-19 relative). Containment is checked exactly; tightness to 16 u (|c_k| + h_k) on each
  // side (the documented padding is 4 epsilon = 8 u of the same magnitude, plus the rounding).
  std::mt19937_64 rng(11);
  for (const double scale : {1.0, 1e3, 5e6}) {
    for (int it = 0; it < 20000; ++it) {
      const Obb<double> b = randomObb(rng, scale);
      const Aabb<double> a = aabbOf(b);
      Vec3<ld> mn = Vec3<ld>::Constant(1e300L), mx = Vec3<ld>::Constant(-1e300L);
      for (int i = 0; i < 8; ++i) {
        const Vec3<ld> p = cornerLd(b, i);
        mn = mn.cwiseMin(p);
        mx = mx.cwiseMax(p);
      }
      for (int k = 0; k < 3; ++k) {
        const ld hk = std::fabs(ld(b.axes(k, 0))) * b.halfExtents[0] + std::fabs(ld(b.axes(k, 1))) * b.halfExtents[1] +
                      std::fabs(ld(b.axes(k, 2))) * b.halfExtents[2];
        const ld tight = 16 * ld(kU) * (std::fabs(ld(b.center[k])) + hk);
        ASSERT_LE(ld(a.min[k]), mn[k]) << "aabbOf does not contain a corner (scale " << scale << ")";
        ASSERT_GE(ld(a.max[k]), mx[k]) << "aabbOf does not contain a corner (scale " << scale << ")";
        EXPECT_LE(mn[k] - ld(a.min[k]), tight) << "scale " << scale;
        EXPECT_LE(ld(a.max[k]) - mx[k], tight) << "scale " << scale;
      }
    }
  }
  // Identity and signed-permutation axes: the AABB is c -+ (permuted h), up to the outward padding.
  Obb<double> p;
  p.center = Vec3d(0.25, -3.5, 8);
  p.halfExtents = Vec3d(1.5, 0.75, 0);
  p.axes << 0, 0, -1, 1, 0, 0, 0, -1, 0;
  const Aabb<double> a = aabbOf(p);
  const Vec3d lo(0.25 - 0, -3.5 - 1.5, 8 - 0.75), hi(0.25 + 0, -3.5 + 1.5, 8 + 0.75);
  for (int k = 0; k < 3; ++k) {
    const double tight = 16 * kU * (std::fabs(p.center[k]) + (hi[k] - lo[k]) / 2);
    EXPECT_LE(a.min[k], lo[k]);
    EXPECT_GE(a.min[k], lo[k] - tight);
    EXPECT_GE(a.max[k], hi[k]);
    EXPECT_LE(a.max[k], hi[k] + tight);
  }
  // A rotation about z by atan(4/3) (entries 0.6, 0.8): half extents 0.6 h0 + 0.8 h1 etc.
  Obb<double> q;
  q.halfExtents = Vec3d(1, 2, 3);
  q.axes << 0.6, -0.8, 0, 0.8, 0.6, 0, 0, 0, 1;
  const Aabb<double> qa = aabbOf(q);
  EXPECT_NEAR(qa.max.x(), 0.6 * 1 + 0.8 * 2, 16 * kU * 2.2);
  EXPECT_NEAR(qa.max.y(), 0.8 * 1 + 0.6 * 2, 16 * kU * 2.2);
  EXPECT_GE(qa.max.z(), 3.0);
  EXPECT_NEAR(qa.max.z(), 3.0, 16 * kU * 3);
}

TEST(Volumes, SimilarityKeepsAnObbExact) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(-1, 1), sc(-2, 1);
  for (int it = 0; it < 20000; ++it) {
    const Obb<double> b = randomObb(rng, 50);
    Similarity<double> s;
    s.rotation = randomRotation(rng);
    s.scale = std::pow(10.0, sc(rng));  // 0.01 .. 10, uniform scale
    s.translation = Vec3d(u(rng), u(rng), u(rng)) * 1e3;
    const Obb<double> t = s.apply(b);
    EXPECT_LT(axesError(t.axes), 1e-14);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(t.halfExtents[k], s.scale * b.halfExtents[k], 2 * kU * s.scale * b.halfExtents[k]);
    // Transformed corners (long double, from the double data) equal the corners of the transformed box.
    const Mat3<ld> R = s.rotation.cast<ld>();
    const double tol = 64 * kU * (1e3 + s.scale * (50 + b.halfExtents.sum()));
    for (int i = 0; i < 8; ++i) {
      const Vec3<ld> expect = ld(s.scale) * (R * cornerLd(b, i)) + s.translation.cast<ld>();
      const Vec3d got = t.corner(i);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(double(ld(got[k]) - expect[k]), 0.0, tol);
      // and the point form of apply agrees with it
      EXPECT_LT((s.apply(b.corner(i)) - got).cwiseAbs().maxCoeff(), tol);
    }
    // The AABB form: the exact AABB of the transformed AABB contains the 8 transformed corners and
    // touches them (up to rounding).
    const Aabb<double> ab = aabbOf(b);
    const Aabb<double> ta = s.apply(ab);
    Vec3<ld> mn = Vec3<ld>::Constant(1e300L), mx = Vec3<ld>::Constant(-1e300L);
    for (int i = 0; i < 8; ++i) {
      const Vec3<ld> c((i & 1) ? ld(ab.max.x()) : ld(ab.min.x()), (i & 2) ? ld(ab.max.y()) : ld(ab.min.y()),
                       (i & 4) ? ld(ab.max.z()) : ld(ab.min.z()));
      const Vec3<ld> p = ld(s.scale) * (R * c) + s.translation.cast<ld>();
      mn = mn.cwiseMin(p);
      mx = mx.cwiseMax(p);
    }
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(double(ld(ta.min[k]) - mn[k]), 0.0, tol);
      EXPECT_NEAR(double(ld(ta.max[k]) - mx[k]), 0.0, tol);
    }
  }
}

TEST(Volumes, SimilarityInverseAndCompose) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1, 1), sc(-1, 1);
  const Similarity<double> id;
  EXPECT_EQ(id.apply(Vec3d(1, 2, 3)), Vec3d(1, 2, 3));
  for (int it = 0; it < 20000; ++it) {
    Similarity<double> s1, s2;
    s1.rotation = randomRotation(rng);
    s2.rotation = randomRotation(rng);
    s1.scale = std::pow(10.0, sc(rng));
    s2.scale = std::pow(10.0, sc(rng));
    s1.translation = Vec3d(u(rng), u(rng), u(rng)) * 100;
    s2.translation = Vec3d(u(rng), u(rng), u(rng)) * 100;
    const Vec3d p = Vec3d(u(rng), u(rng), u(rng)) * 10;
    const double tol = 1e-12 * (1 + 100 * 10 + 10 * 10 * 10);
    // compose: (s1 * s2)(p) = s1(s2(p))
    const Similarity<double> c = s1 * s2;
    EXPECT_LT((c.apply(p) - s1.apply(s2.apply(p))).cwiseAbs().maxCoeff(), tol);
    EXPECT_NEAR(c.scale, s1.scale * s2.scale, 4 * kU * c.scale);
    EXPECT_LT(axesError(c.rotation), 1e-14);
    // inverse, both ways
    const Similarity<double> i1 = s1.inverse();
    EXPECT_LT((i1.apply(s1.apply(p)) - p).cwiseAbs().maxCoeff(), tol);
    EXPECT_LT((s1.apply(i1.apply(p)) - p).cwiseAbs().maxCoeff(), tol);
    EXPECT_LT(((s1 * i1).apply(p) - p).cwiseAbs().maxCoeff(), tol);
    EXPECT_LT(((i1 * s1).apply(p) - p).cwiseAbs().maxCoeff(), tol);
    EXPECT_NEAR(i1.scale * s1.scale, 1.0, 4 * kU);
    // inverse of a composition
    EXPECT_LT(((s1 * s2).inverse().apply(p) - s2.inverse().apply(s1.inverse().apply(p))).cwiseAbs().maxCoeff(), tol);
  }
  // Hand-checked: rotate 90 degrees about z, scale 2, translate (1, 0, 0).
  Similarity<double> s;
  s.rotation << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  s.scale = 2;
  s.translation = Vec3d(1, 0, 0);
  EXPECT_EQ(s.apply(Vec3d(1, 0, 0)), Vec3d(1, 2, 0));
  EXPECT_EQ(s.inverse().apply(Vec3d(1, 2, 0)), Vec3d(1, 0, 0));
  Obb<double> b;
  b.center = Vec3d(1, 0, 0);
  b.halfExtents = Vec3d(1, 0.5, 0.25);
  const Obb<double> t = s.apply(b);
  EXPECT_EQ(t.center, Vec3d(1, 2, 0));
  EXPECT_EQ(t.halfExtents, Vec3d(2, 1, 0.5));
  EXPECT_EQ(t.axes, s.rotation);
  // The AABB form (aabbOf: rounded outward by a few ulps of the magnitudes).
  const Aabb<double> ta = s.apply(Aabb<double>::fromCenterHalfExtents(b.center, b.halfExtents));
  const Vec3d lo(0, 0, -0.5), hi(2, 4, 0.5);
  for (int k = 0; k < 3; ++k) {
    EXPECT_LE(ta.min[k], lo[k]);
    EXPECT_GE(ta.max[k], hi[k]);
    EXPECT_NEAR(ta.min[k], lo[k], 16 * kU * 4);
    EXPECT_NEAR(ta.max[k], hi[k], 16 * kU * 4);
  }
}

// Orthogonal polar factor by Newton's iteration X <- (X + X^-T) / 2 in long double (det m > 0).
Mat3<ld> polarNewton(const Mat3d& m) {
  Mat3<ld> x = m.cast<ld>();
  for (int i = 0; i < 60; ++i) x = (x + x.inverse().transpose()) / ld(2);
  return x;
}

double frob(const Mat3d& a, const Mat3d& b) { return (a - b).norm(); }

TEST(Volumes, OrthonormalizedIsTheNearestRotation) {
  std::mt19937_64 rng(19);
  std::normal_distribution<double> n(0, 1);
  for (const double noise : {1e-9, 1e-4, 1e-2, 0.2}) {
    for (int it = 0; it < 2000; ++it) {
      const Mat3d R = randomRotation(rng);
      Mat3d m = R;
      for (int i = 0; i < 9; ++i) m.data()[i] += noise * n(rng);
      const Mat3d r = orthonormalized(m);
      EXPECT_LT(axesError(r), 1e-14);
      EXPECT_NEAR(r.determinant(), 1.0, 1e-14);
      // Independent oracle: the polar factor.
      const Mat3<ld> p = polarNewton(m);
      EXPECT_LT((r.cast<ld>() - p).cwiseAbs().maxCoeff(), 1e-13L) << "noise " << noise;
      // Nearest: no nearby rotation is closer, and it is at least as close as R.
      EXPECT_LE(frob(r, m), frob(R, m) + 1e-15);
      for (int k = 0; k < 4; ++k) {
        const Vec3d w(n(rng), n(rng), n(rng));
        const Mat3d q = r * Eigen::AngleAxisd(1e-4, w.normalized()).toRotationMatrix();
        EXPECT_LE(frob(r, m), frob(q, m) + 1e-15);
      }
    }
  }
  // A reflection (det < 0): the result is still a rotation, and the nearest one.
  for (int it = 0; it < 2000; ++it) {
    Mat3d m = randomRotation(rng) * Eigen::Vector3d(1, 1, -1).asDiagonal();
    for (int i = 0; i < 9; ++i) m.data()[i] += 1e-3 * n(rng);
    const Mat3d r = orthonormalized(m);
    EXPECT_LT(axesError(r), 1e-14);
    EXPECT_NEAR(r.determinant(), 1.0, 1e-14);
    for (int k = 0; k < 8; ++k) {
      const Vec3d w(n(rng), n(rng), n(rng));
      const Mat3d q = r * Eigen::AngleAxisd(k < 4 ? 1e-3 : 0.3, w.normalized()).toRotationMatrix();
      EXPECT_LE(frob(r, m), frob(q, m) + 1e-15);
    }
  }
  // An exact rotation comes back unchanged (to rounding); float works too.
  const Mat3d R = Eigen::AngleAxisd(0.7, Vec3d(1, 2, 3).normalized()).toRotationMatrix();
  EXPECT_LT((orthonormalized(R) - R).cwiseAbs().maxCoeff(), 1e-15);
  const Mat3<float> rf = orthonormalized(Mat3<float>(R.cast<float>() * 1.001f));
  EXPECT_LT(axesError(rf), 1e-5f);
  EXPECT_LT((rf - R.cast<float>()).cwiseAbs().maxCoeff(), 1e-5f);
}

// volumes.h states the Obb contract "axes orthonormal to within kAxesTolerance<T> (see
// orthonormalized())" with kAxesTolerance<float> = 2e-7, "what rounding a double rotation to float
// leaves". An earlier orthonormalized<float> ran the SVD in float and left up to ~2e-6 (above 2e-7 for
// ~94% of slightly perturbed rotations, and above even kParallelEpsilon<float> = 1e-6). Oracle: the
// same matrix orthonormalized in double and rounded to float, and the tolerance itself.
TEST(Volumes, OrthonormalizedFloatMeetsTheFloatAxesContract) {
  std::mt19937_64 rng(29);
  std::normal_distribution<double> n(0, 1);
  float worst = 0, worstViaDouble = 0;
  int over = 0;
  for (int it = 0; it < 10000; ++it) {
    Mat3<float> m = randomRotation(rng).cast<float>();
    for (int i = 0; i < 9; ++i) m.data()[i] += float(1e-3 * n(rng));
    const float e = axesError(orthonormalized(m));
    worst = std::max(worst, e);
    if (e > kAxesTolerance<float>) ++over;
    worstViaDouble = std::max(worstViaDouble, axesError(Mat3<float>(orthonormalized(Mat3d(m.cast<double>())).cast<float>())));
  }
  std::printf("orthonormalized<float>: worst axesError %.2e, %d of 10000 above kAxesTolerance<float> = %.0e; "
              "via double and rounded: %.2e\n", worst, over, kAxesTolerance<float>, worstViaDouble);
  EXPECT_LE(worstViaDouble, kAxesTolerance<float>);
  EXPECT_LE(worst, kAxesTolerance<float>) << "orthonormalized<float> leaves axes outside the float contract";
}

TEST(Volumes, AxesError) {
  EXPECT_EQ(axesError(Mat3d(Mat3d::Identity())), 0.0);
  // Column 1 scaled by 1 + d: (A^T A)_11 - 1 = 2d + d^2.
  const double d = 1e-6;
  Mat3d a = Mat3d::Identity();
  a(1, 1) = 1 + d;
  EXPECT_NEAR(axesError(a), 2 * d + d * d, 4 * kU);  // rounding of (1 + d)^2 - 1
  // A shear: a(0, 1) = d gives (A^T A)_01 = d and (A^T A)_11 = 1 + d^2.
  Mat3d s = Mat3d::Identity();
  s(0, 1) = d;
  EXPECT_NEAR(axesError(s), d, 4 * kU);
  // Rotations: double rotations from quaternions are well inside kAxesTolerance<double>, also after
  // chaining a few products; rounding a double rotation to float stays within kAxesTolerance<float>.
  std::mt19937_64 rng(23);
  double worstChain = 0, worstFloat = 0;
  for (int it = 0; it < 20000; ++it) {
    Mat3d r = randomRotation(rng);
    for (int k = 0; k < 4; ++k) r = r * randomRotation(rng);
    worstChain = std::max(worstChain, axesError(r));
    worstFloat = std::max(worstFloat, double(axesError(Mat3<float>(r.cast<float>()))));
  }
  EXPECT_LT(worstChain, kAxesTolerance<double>);
  EXPECT_LT(worstFloat, double(kAxesTolerance<float>));
  std::printf("axesError: 5 chained double rotations %.2e (tolerance %.0e), rounded to float %.2e (tolerance %.0e)\n",
              worstChain, kAxesTolerance<double>, worstFloat, double(kAxesTolerance<float>));
}

}  // namespace
}  // namespace nestwalk
