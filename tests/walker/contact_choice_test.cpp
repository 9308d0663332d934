// obbSurfaceGap (contact_choice.h): whether a unit's inner OBB is tight enough for the nested test
// alone, against an independent dense brute force: the largest distance from a fine grid of points
// on the OBB's faces to the triangles, each distance by a loop over every triangle. Shapes on
// either side of the 10 mm threshold, none within 1.5 mm of it: a box in its own OBB (gap 0), the
// same OBB grown by 3 mm and by 10 mm (gaps 5.2 and 17.3 mm, at the corners), a 32-sided pole of radius 2 cm and of 3 cm in its square box
// (gap 0.414 r: 8.3 and 12.4 mm), an L-shaped piece; each also rotated and moved to UTM
// magnitudes (the verdict may not change).
#include "nestwalk/walker/contact_choice.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace nestwalk {
namespace {

using V3 = Vec3<double>;

std::vector<Triangle> boxTriangles(const V3& lo, const V3& hi) {
  auto corner = [&](int i) { return V3(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z()); };
  const int faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  std::vector<Triangle> out;
  for (const auto& f : faces) {
    out.push_back({corner(f[0]), corner(f[1]), corner(f[2])});
    out.push_back({corner(f[0]), corner(f[2]), corner(f[3])});
  }
  return out;
}

/// A prism of `sides` sides around the z axis, radius r, from z = 0 to h, capped.
std::vector<Triangle> prism(int sides, double r, double h) {
  std::vector<Triangle> out;
  for (int i = 0; i < sides; ++i) {
    const double a = 2 * std::numbers::pi * i / sides, b = 2 * std::numbers::pi * (i + 1) / sides;
    const V3 p(r * std::cos(a), r * std::sin(a), 0), q(r * std::cos(b), r * std::sin(b), 0), up(0, 0, h);
    out.push_back({p, q, q + up});
    out.push_back({p, q + up, p + up});
    out.push_back({V3::Zero(), q, p});
    out.push_back({up, p + up, q + up});
  }
  return out;
}

/// Distance from a point to a triangle by its closest point (Ericson, Real-Time Collision
/// Detection 5.1.5), written here independently of the engine's box-triangle distance.
double pointTriangle(const V3& p, const Triangle& t) {
  const V3 &a = t[0], &b = t[1], &c = t[2];
  const V3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return (p - a).norm();
  const V3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return (p - b).norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const V3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return (p - c).norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  const double denom = 1 / (va + vb + vc);
  return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}

NearestTriangleQuery bruteNearest(const std::vector<Triangle>& triangles) {
  return [&triangles](const V3& p, std::optional<Triangle>& nearest) {
    double best = std::numeric_limits<double>::infinity();
    nearest.reset();
    for (const Triangle& t : triangles) {
      const double d = pointTriangle(p, t);
      if (d < best) {
        best = d;
        nearest = t;
      }
    }
    return best;
  };
}

/// The largest distance from a grid of points `spacing` apart on each face of the box to the
/// triangles, and the grid's half cell diagonal (the true gap is within that of the sampled one,
/// the distance being 1-Lipschitz).
struct DenseGap {
  double sampled, cellRadius;
};
DenseGap denseGap(const Obb<double>& box, const std::vector<Triangle>& triangles, double spacing) {
  DenseGap g{0, 0};
  for (int axis = 0; axis < 3; ++axis) {
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    const int na = std::max(1, int(std::ceil(2 * box.halfExtents[a] / spacing)));
    const int nb = std::max(1, int(std::ceil(2 * box.halfExtents[b] / spacing)));
    g.cellRadius = std::max(g.cellRadius, std::hypot(box.halfExtents[a] / na, box.halfExtents[b] / nb));
    for (double side : {-1.0, 1.0})
      for (int i = 0; i <= na; ++i)
        for (int j = 0; j <= nb; ++j) {
          const V3 p = box.center + side * box.halfExtents[axis] * box.axes.col(axis) +
                       (2.0 * i / na - 1) * box.halfExtents[a] * box.axes.col(a) +
                       (2.0 * j / nb - 1) * box.halfExtents[b] * box.axes.col(b);
          double d = std::numeric_limits<double>::infinity();
          for (const Triangle& t : triangles) d = std::min(d, pointTriangle(p, t));
          g.sampled = std::max(g.sampled, d);
        }
  }
  return g;
}

struct Shape {
  const char* name;
  std::vector<Triangle> triangles;
  Obb<double> box;
};

std::vector<Shape> shapes() {
  std::vector<Shape> out;
  const V3 lo(-0.3, -0.2, 0), hi(0.3, 0.2, 0.5);
  const Obb<double> own{0.5 * (lo + hi), Mat3<double>::Identity(), 0.5 * (hi - lo)};
  out.push_back({"box in its own OBB", boxTriangles(lo, hi), own});
  // Grown by g on every side, the gap is at the corners: sqrt(3) g (5.2 mm and 17.3 mm).
  Obb<double> grown3 = own, grown10 = own;
  grown3.halfExtents.array() += 0.003;
  grown10.halfExtents.array() += 0.010;
  out.push_back({"box, OBB grown by 3 mm", boxTriangles(lo, hi), grown3});
  out.push_back({"box, OBB grown by 10 mm", boxTriangles(lo, hi), grown10});
  for (double r : {0.02, 0.03})
    out.push_back({r == 0.02 ? "pole r = 2 cm" : "pole r = 3 cm", prism(32, r, 3.0),
                   Obb<double>{V3(0, 0, 1.5), Mat3<double>::Identity(), V3(r, r, 1.5)}});
  std::vector<Triangle> l = boxTriangles(V3(0, 0, 0), V3(1.0, 0.1, 0.1));
  const std::vector<Triangle> upright = boxTriangles(V3(0, 0, 0), V3(0.1, 0.1, 0.8));
  l.insert(l.end(), upright.begin(), upright.end());
  out.push_back({"L-shaped piece", l, Obb<double>{V3(0.5, 0.05, 0.4), Mat3<double>::Identity(), V3(0.5, 0.05, 0.4)}});
  return out;
}

/// The shape rotated and moved far from the origin (the verdict may not depend on the frame).
Shape movedFar(const Shape& s) {
  const Mat3<double> R = Eigen::AngleAxisd(0.7, V3(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  const V3 offset(512345.25, 4476543.5, 1210.0);
  Shape m = s;
  for (Triangle& t : m.triangles)
    for (V3& p : t) p = R * p + offset;
  m.box.center = R * s.box.center + offset;
  m.box.axes = R * s.box.axes;
  return m;
}

TEST(ContactChoice, VerdictsAgreeWithADenseBruteForce) {
  for (const Shape& base : shapes()) {
    // The grid is refined until it decides: the sampled gap, give or take the cell radius, on one
    // side of the threshold. The shapes keep 1.5 mm away from it, so a 2 mm grid always decides.
    DenseGap dense{};
    for (double spacing = 0.064; spacing >= 0.002; spacing /= 2) {
      dense = denseGap(base.box, base.triangles, spacing);
      if (std::abs(dense.sampled - kTightObbGap) > dense.cellRadius) break;
    }
    ASSERT_GT(std::abs(dense.sampled - kTightObbGap), dense.cellRadius) << base.name;
    const bool tight = dense.sampled <= kTightObbGap;
    for (const Shape& s : {base, movedFar(base)}) {
      const GapVerdict v = obbSurfaceGap(s.box, bruteNearest(s.triangles));
      EXPECT_EQ(v.tight, tight) << s.name << ": dense gap " << dense.sampled * 1000 << " mm";
      // The lower bound is a distance from a point of the surface: never above the true gap.
      EXPECT_LE(v.lowerBound, dense.sampled + dense.cellRadius + 1e-9) << s.name;
      if (!tight) {
        EXPECT_GT(v.lowerBound, kTightObbGap) << s.name;
      }
      EXPECT_LE(v.probes, kMaxGapProbes) << s.name;
      std::printf("%-26s dense gap %6.2f mm: %s after %d distance queries (largest found %.2f mm)\n", s.name,
                  dense.sampled * 1000, v.tight ? "tight" : "exact stage", v.probes, v.lowerBound * 1000);
    }
  }
}

TEST(ContactChoice, AUnitWithoutTrianglesIsNeverTight) {
  // No triangles: every distance is infinite; the nested volumes must not be trusted as tight by
  // this test (the world decides such units separately: their volumes stand for them).
  const std::vector<Triangle> none;
  const GapVerdict v = obbSurfaceGap(Obb<double>{V3::Zero(), Mat3<double>::Identity(), V3(1, 1, 1)}, bruteNearest(none));
  EXPECT_FALSE(v.tight);
}

}  // namespace
}  // namespace nestwalk
