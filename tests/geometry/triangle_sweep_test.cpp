// sweepBoxTriangle (triangle_sweep.h): the interval of t over which a translating box touches a
// triangle, against an independent reference built only on the static distance of triangle_box.h
// (itself checked against CGAL and FCL): under a translation the distance between two convex sets
// is a convex function of t, so its zero set is an interval, found here by golden-section search
// for a minimum and bisection on either side. Random boxes (rotated and axis-aligned, some flat),
// triangles (some degenerate: a segment, a point) and motions aimed near the triangle; hard cases:
// a box sliding along the triangle's plane touching it, the same 1 nm above it, motion parallel to
// an edge, and everything again at UTM magnitudes.
#include "nestwalk/geometry/triangle_sweep.h"

#include "tests/geometry/test_shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <random>

namespace nestwalk {
namespace {

using V3 = Vec3<double>;

struct Interval {
  double enter, exit;
};

/// The reference interval of t in [lo, hi] over which the box moved by t d touches the triangle;
/// nullopt when the smallest distance over [lo, hi] is above `apart` (clearly apart).
/// `touching` is the distance taken for contact (the static test is exact, so 0 up to the rounding
/// of the box's frame).
std::optional<Interval> referenceInterval(const Triangle& tri, const Obb<double>& box, const V3& d, double lo,
                                          double hi, double apart) {
  auto f = [&](double t) {
    Obb<double> b = box;
    b.center += t * d;
    return triangleBoxDistance(tri, b);
  };
  // Golden-section search for a minimiser of the convex f.
  const double g = (std::sqrt(5.0) - 1) / 2;
  double a = lo, b = hi, x1 = b - g * (b - a), x2 = a + g * (b - a), f1 = f(x1), f2 = f(x2);
  for (int i = 0; i < 200 && f1 > 0 && f2 > 0; ++i) {
    if (f1 < f2) {
      b = x2; x2 = x1; f2 = f1; x1 = b - g * (b - a); f1 = f(x1);
    } else {
      a = x1; x1 = x2; f1 = f2; x2 = a + g * (b - a); f2 = f(x2);
    }
  }
  const double tMin = f1 <= f2 ? x1 : x2;
  if (f(tMin) > 0) {
    if (f(tMin) > apart) return std::nullopt;
    return Interval{NAN, NAN};  // undecided: within `apart` of touching
  }
  // Bisection for the boundaries of the zero set.
  auto boundary = [&](double outside, double inside) {
    for (int i = 0; i < 200; ++i) {
      const double m = 0.5 * (outside + inside);
      if (m == outside || m == inside) break;
      (f(m) > 0 ? outside : inside) = m;
    }
    return inside;
  };
  return Interval{f(lo) > 0 ? boundary(lo, tMin) : lo, f(hi) > 0 ? boundary(hi, tMin) : hi};
}

struct Case {
  Triangle tri;
  Obb<double> box;
  V3 d;
};

Case randomCase(std::mt19937& rng, const V3& offset) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_real_distribution<double> size(0.01, 1.0);
  Case c;
  const V3 centre(u(rng), u(rng), u(rng));
  const double scale = size(rng) * 2;
  for (V3& p : c.tri) p = offset + centre + scale * V3(u(rng), u(rng), u(rng));
  switch (rng() % 8) {
    case 0: c.tri[2] = c.tri[1]; break;                        // a segment
    case 1: c.tri[1] = c.tri[2] = c.tri[0]; break;             // a point
    case 2: c.tri[2] = 0.5 * (c.tri[0] + c.tri[1]); break;     // collinear
    default: break;
  }
  for (int k = 0; k < 3; ++k) c.box.halfExtents[k] = rng() % 10 == 0 ? 0.0 : size(rng);
  if (rng() % 3 != 0) c.box.axes = testshapes::randomRotation(rng);
  // Aim the motion at a point near the triangle, from 1 to 3 lengths away.
  const V3 target = (c.tri[0] + c.tri[1] + c.tri[2]) / 3.0 + 0.8 * V3(u(rng), u(rng), u(rng));
  const V3 direction = V3(u(rng), u(rng), u(rng)).normalized();
  const double length = 0.5 + 4.5 * (u(rng) + 1) / 2;
  c.d = direction * length;
  c.box.center = target - (0.3 + 0.4 * (u(rng) + 1) / 2) * c.d;
  return c;
}

/// Checks one case against the reference over the window [lo, hi]; returns whether it touched.
bool checkCase(const Case& c, double lo, double hi, const char* label, int n) {
  const SweepResult r = sweepBoxTriangle(c.box, c.d, c.tri, lo, hi);
  const bool touches = r.enter <= r.exit && r.enter <= hi && r.exit >= lo;
  const double scale = c.d.norm();
  const auto ref = referenceInterval(c.tri, c.box, c.d, lo, hi, 1e-9 * scale);
  if (ref && std::isnan(ref->enter)) return touches;  // within a nanometre of touching: either answer
  EXPECT_EQ(touches, ref.has_value()) << label << " case " << n;
  if (!touches || !ref) return false;
  // The sweep is never late: its interval holds the reference's, up to the rounding of moving the
  // box's centre (an ulp of its coordinates: 1e-9 m at UTM magnitudes) over the speed. It is
  // early or late by no more than its slack (1e-12 of the local magnitudes, ~2e-11 m) as a
  // distance: at its boundaries the box is that close to the triangle. (As a time, near-grazing
  // motions stretch that by 1 / sin of the approach angle, so times are not compared directly.)
  const double centreUlp = 16 * std::numeric_limits<double>::epsilon() * c.box.center.cwiseAbs().maxCoeff();
  const double late = (1e-12 + centreUlp) / scale, close = 1e-10 + centreUlp;
  auto distanceAt = [&](double t) {
    Obb<double> b = c.box;
    b.center += t * c.d;
    return triangleBoxDistance(c.tri, b);
  };
  if (ref->enter > lo) {
    EXPECT_LE(r.enter, ref->enter + late) << label << " case " << n;
    EXPECT_LE(distanceAt(r.enter), close) << label << " case " << n;
    // The normal points from the triangle toward the box, against the motion, and separates them
    // just before the contact.
    EXPECT_NEAR(r.normal.norm(), 1.0, 1e-12) << label << " case " << n;
    EXPECT_LE(r.normal.dot(c.d), 1e-12 * scale) << label << " case " << n;
    Obb<double> before = c.box;
    before.center += (r.enter - 1e-6) * c.d;
    double boxLow = before.center.dot(r.normal);
    for (int k = 0; k < 3; ++k) boxLow -= before.halfExtents[k] * std::abs(before.axes.col(k).dot(r.normal));
    double triHigh = -INFINITY;
    for (const V3& p : c.tri) triHigh = std::max(triHigh, p.dot(r.normal));
    EXPECT_GE(boxLow - triHigh, -close) << label << " case " << n;
  } else {
    EXPECT_LE(r.enter, lo + late) << label << " case " << n;
  }
  if (ref->exit < hi) {
    EXPECT_GE(r.exit, ref->exit - late) << label << " case " << n;
    EXPECT_LE(distanceAt(r.exit), close) << label << " case " << n;
  } else {
    EXPECT_GE(r.exit, hi - late) << label << " case " << n;
  }
  return true;
}

void randomCases(const V3& offset, unsigned seed, const char* label) {
  std::mt19937 rng(seed);
  int touched = 0;
  const int cases = 3000;
  for (int n = 0; n < cases; ++n) touched += checkCase(randomCase(rng, offset), -0.5, 1.5, label, n);
  std::printf("%s: %d of %d random sweeps touch, all as the distance reference\n", label, touched, cases);
  EXPECT_GT(touched, cases / 5);
  EXPECT_LT(touched, cases * 4 / 5);
}

TEST(TriangleSweep, RandomSweepsMatchTheDistanceReference) { randomCases(V3::Zero(), 11, "near the origin"); }

TEST(TriangleSweep, RandomSweepsMatchTheDistanceReferenceAtUtmMagnitudes) {
  randomCases(V3(512345.0, 4476543.0, 1210.0), 12, "at UTM magnitudes");
}

TEST(TriangleSweep, SlidingAlongThePlaneTouchesWholeStepAndANanometreAboveNever) {
  // The triangle lies in z = 0; the box's bottom face slides over it.
  const Triangle tri = {V3(0, 0, 0), V3(2, 0, 0), V3(0, 2, 0)};
  Obb<double> box;
  box.halfExtents = V3(0.25, 0.25, 0.5);
  box.center = V3(-1.0, 0.5, 0.5);
  const V3 d(4, 0, 0);
  // Touching: the box enters the triangle's span sideways at x = -0.25 .. leaves at x where the
  // hypotenuse x + y = 2 passes the box's corner (x - 0.25) + (0.5 - 0.25) = 2.
  const SweepResult touching = sweepBoxTriangle(box, d, tri, 0.0, 1.0);
  ASSERT_FALSE(touching.empty());
  // Up to the sweep's slack (1e-12 of the magnitudes, ~1e-11 m) over the speed.
  EXPECT_NEAR(touching.enter, (-0.25 - -1.0) / 4, 1e-11);
  EXPECT_NEAR(touching.exit, (2.0 - 0.25 + 0.25 - -1.0) / 4, 1e-11);
  for (double gap : {1e-9, 1e-6}) {
    Obb<double> above = box;
    above.center.z() += gap;
    const SweepResult r = sweepBoxTriangle(above, d, tri, 0.0, 1.0);
    EXPECT_FALSE(r.enter <= r.exit && r.enter <= 1.0 && r.exit >= 0.0) << "gap " << gap;
  }
}

TEST(TriangleSweep, MotionAlongAnEdgeAndHeadOnGiveTheExactTimes) {
  // A unit cube (half extents 0.5) moving along +x toward a triangle whose nearest vertex is at
  // x = 3: contact when the front face reaches x = 3, t = (3 - 0.5) / 5.
  const Triangle tri = {V3(3, 0, 0), V3(4, 0.2, 0.1), V3(4, -0.2, -0.1)};
  Obb<double> cube;
  cube.halfExtents = V3::Constant(0.5);
  const SweepResult headOn = sweepBoxTriangle(cube, V3(5, 0, 0), tri);
  EXPECT_NEAR(headOn.enter, 0.5, 1e-11);
  EXPECT_EQ(headOn.normal, V3(-1, 0, 0));
  // Along an edge: a segment on the line y = 0.5, z = 0 (on the cube's +y face plane), moving
  // parallel to it: the cube touches it over the whole overlap of their x ranges.
  const Triangle edge = {V3(2, 0.5, 0), V3(3, 0.5, 0), V3(3, 0.5, 0)};
  const SweepResult along = sweepBoxTriangle(cube, V3(4, 0, 0), edge, 0.0, 1.0);
  EXPECT_NEAR(along.enter, 1.5 / 4, 1e-11);
  EXPECT_NEAR(along.exit, 3.5 / 4, 1e-11);
}

}  // namespace
}  // namespace nestwalk
