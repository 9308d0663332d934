// Convex hull (convex_hull.h): dimension detection, containment, topology and exact vertex sets
// of known polytopes.
//
// Independent values: the vertex sets and volumes of known polytopes (cube, octahedron, square),
// Euler's formula for a triangulated sphere (F = 2V - 4), and containment checked point by point
// against every face plane. Containment tolerance: 1e-10 x the points' AABB diagonal (qhull merges
// facets within its own precision, ~1e-15 relative; 1e-10 leaves five orders of margin).
#include "nestwalk/geometry/convex_hull.h"

#include <Eigen/Geometry>
#include "tests/geometry/test_shapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <vector>

namespace nestwalk {
namespace {

using V3 = Vec3<double>;

constexpr double kContainRel = 1e-10;


using testshapes::diagonal;
using testshapes::randomRotation;

// Volume enclosed by the (outward) triangles, by the divergence theorem.
double enclosedVolume(const ConvexHull& h) {
  double v = 0.0;
  const V3 o = h.vertices[0];
  for (const auto& t : h.triangles) {
    v += (h.vertices[t[0]] - o).dot((h.vertices[t[1]] - o).cross(h.vertices[t[2]] - o)) / 6.0;
  }
  return v;
}

// Every point is on the inner side of every face plane (within tol), every face is outward
// (the vertices' mean is strictly inside), and the hull is a closed triangulated sphere.
void expectValidSolidHull(const ConvexHull& h, const std::vector<V3>& pts) {
  ASSERT_EQ(h.dimension, 3);
  const double tol = kContainRel * diagonal(pts);
  V3 mean = V3::Zero();
  for (const V3& v : h.vertices) mean += v;
  mean /= static_cast<double>(h.vertices.size());
  std::set<std::pair<int, int>> directed;
  int worstOutside = 0;
  for (const auto& t : h.triangles) {
    for (int k = 0; k < 3; ++k) {
      ASSERT_GE(t[k], 0);
      ASSERT_LT(t[k], static_cast<int>(h.vertices.size()));
      // Each directed edge appears once in a consistently oriented closed surface.
      EXPECT_TRUE(directed.insert({t[k], t[(k + 1) % 3]}).second);
    }
    const V3 a = h.vertices[t[0]];
    const V3 c = (h.vertices[t[1]] - a).cross(h.vertices[t[2]] - a);
    const double len = c.norm();
    if (len <= 1e-12 * diagonal(pts) * diagonal(pts)) continue;  // a degenerate sliver of "Qt"
    const V3 n = c / len;
    EXPECT_LT(n.dot(mean - a), 0.0);
    for (const V3& p : pts) {
      if (n.dot(p - a) > tol) ++worstOutside;
    }
  }
  EXPECT_EQ(worstOutside, 0);
  // Every directed edge has its reverse (closed), and Euler: F = 2V - 4.
  for (const auto& e : directed) EXPECT_TRUE(directed.count({e.second, e.first}));
  EXPECT_EQ(h.triangles.size(), 2 * h.vertices.size() - 4);
  // Hull vertices are input points, exactly.
  std::set<std::array<double, 3>> input;
  for (const V3& p : pts) input.insert({p.x(), p.y(), p.z()});
  for (const V3& v : h.vertices) EXPECT_TRUE(input.count({v.x(), v.y(), v.z()}));
}

TEST(ConvexHull, EmptyInputHasDimensionMinusOne) {
  const ConvexHull h = convexHull({});
  EXPECT_EQ(h.dimension, -1);
  EXPECT_TRUE(h.vertices.empty());
  EXPECT_TRUE(h.triangles.empty());
}

TEST(ConvexHull, SinglePointAndRepeatsHaveDimensionZero) {
  const V3 p(1.5, -2.25, 7.0);
  for (int n : {1, 2, 17}) {
    const ConvexHull h = convexHull(std::vector<V3>(n, p));
    EXPECT_EQ(h.dimension, 0);
    ASSERT_EQ(h.vertices.size(), 1u);
    EXPECT_EQ(h.vertices[0], p);
    EXPECT_TRUE(h.triangles.empty());
  }
}

TEST(ConvexHull, CollinearPointsGiveTheTwoEnds) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-3.0, 5.0);
  const V3 o(10.0, -4.0, 2.0), d = V3(1.0, 2.0, -0.5).normalized();
  std::vector<V3> pts;
  for (int i = 0; i < 200; ++i) pts.push_back(o + u(rng) * d);
  const V3 lo = o - 3.5 * d, hi = o + 6.0 * d;  // the ends, placed mid-list
  pts.insert(pts.begin() + 57, hi);
  pts.insert(pts.begin() + 120, lo);
  const ConvexHull h = convexHull(pts);
  EXPECT_EQ(h.dimension, 1);
  ASSERT_EQ(h.vertices.size(), 2u);
  EXPECT_TRUE((h.vertices[0] == lo && h.vertices[1] == hi) || (h.vertices[0] == hi && h.vertices[1] == lo));
  EXPECT_TRUE(h.triangles.empty());
}

TEST(ConvexHull, CoplanarPointsGiveThePolygon) {
  // A rotated, translated 4 x 2 rectangle with interior points and points on its edges.
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Eigen::Matrix3d r = randomRotation(rng);
  const V3 t(100.0, 50.0, -20.0);
  auto place = [&](double x, double y) { return V3(r * V3(x, y, 0.0) + t); };
  const std::vector<V3> corners = {place(-2, -1), place(2, -1), place(2, 1), place(-2, 1)};
  std::vector<V3> pts;
  for (int i = 0; i < 300; ++i) pts.push_back(place(-1.9 + 3.8 * u(rng), -0.9 + 1.8 * u(rng)));
  for (int i = 0; i < 20; ++i) pts.push_back(place(-2.0 + 4.0 * u(rng), 1.0));  // on an edge
  for (const V3& c : corners) pts.insert(pts.begin() + static_cast<long>(u(rng) * pts.size()), c);
  const ConvexHull h = convexHull(pts);
  ASSERT_EQ(h.dimension, 2);
  // The vertices are the four corners (the edge points are dropped as collinear).
  ASSERT_EQ(h.vertices.size(), 4u);
  for (const V3& c : corners) EXPECT_NE(std::find(h.vertices.begin(), h.vertices.end(), c), h.vertices.end());
  // The fan covers the rectangle on both sides: total triangle area 2 x 8.
  double area = 0.0;
  for (const auto& tri : h.triangles) {
    area +=
        0.5 * (h.vertices[tri[1]] - h.vertices[tri[0]]).cross(h.vertices[tri[2]] - h.vertices[tri[0]]).norm();
  }
  EXPECT_NEAR(area, 16.0, 1e-12 * 16.0);
}

TEST(ConvexHull, CubeCornersWithInteriorPointsHaveEightVertices) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-0.999, 0.999);
  for (const V3& offset : {V3(0, 0, 0), V3(550000.0, 4650000.0, 300.0)}) {
    std::vector<V3> pts;
    for (int i = 0; i < 8; ++i) pts.push_back(offset + V3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1));
    for (int i = 0; i < 500; ++i) pts.push_back(offset + V3(u(rng), u(rng), u(rng)));
    std::shuffle(pts.begin(), pts.end(), rng);
    const ConvexHull h = convexHull(pts);
    expectValidSolidHull(h, pts);
    EXPECT_EQ(h.vertices.size(), 8u);
    EXPECT_EQ(h.triangles.size(), 12u);
    EXPECT_NEAR(enclosedVolume(h), 8.0, 1e-9);
  }
}

TEST(ConvexHull, OctahedronVolume) {
  // |x| + |y| + |z| <= 1 has volume 4/3; its 6 vertices plus interior points.
  std::mt19937 rng(14);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<V3> pts = {V3(1, 0, 0), V3(-1, 0, 0), V3(0, 1, 0), V3(0, -1, 0), V3(0, 0, 1), V3(0, 0, -1)};
  while (pts.size() < 400) {
    const V3 p(u(rng), u(rng), u(rng));
    if (p.cwiseAbs().sum() < 0.99) pts.push_back(p);
  }
  const ConvexHull h = convexHull(pts);
  expectValidSolidHull(h, pts);
  EXPECT_EQ(h.vertices.size(), 6u);
  EXPECT_NEAR(enclosedVolume(h), 4.0 / 3.0, 1e-12);
}

TEST(ConvexHull, RandomCloudsAreContained) {
  std::mt19937 rng(15);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 12; ++trial) {
    SCOPED_TRACE(trial);
    const Eigen::Matrix3d r = randomRotation(rng);
    const V3 scale(1.0 + 9.0 * std::abs(u(rng)), 1.0 + 3.0 * std::abs(u(rng)), 0.05 + std::abs(u(rng)));
    const V3 offset = 1000.0 * V3(u(rng), u(rng), u(rng));
    std::vector<V3> pts;
    const int n = 50 + 150 * trial;
    for (int i = 0; i < n; ++i) {
      V3 x = trial % 3 == 0   ? V3(u(rng), u(rng), u(rng))               // box volume
             : trial % 3 == 1 ? V3(g(rng), g(rng), g(rng)).normalized()  // sphere surface
                              : V3(g(rng), g(rng), g(rng));              // gaussian
      pts.push_back(offset + r * scale.cwiseProduct(x));
    }
    expectValidSolidHull(convexHull(pts), pts);
  }
}

TEST(ConvexHull, FlatnessIsRelativeToTheExtent) {
  // A 10 m square sheet: noise of 1e-12 of its size is coplanar (dimension 2), 1e-6 is solid.
  std::mt19937 rng(16);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  const Eigen::Matrix3d r = randomRotation(rng);
  for (const auto& [noise, dim] : {std::pair{1e-11, 2}, std::pair{1e-5, 3}}) {
    std::vector<V3> pts;
    for (int i = 0; i < 300; ++i) pts.push_back(r * V3(u(rng), u(rng), noise * u(rng) / 5.0));
    EXPECT_EQ(convexHull(pts).dimension, dim) << "noise " << noise;
  }
  // Nearly collinear: a 10 m pole with 1e-11 m of sideways noise.
  std::vector<V3> pole;
  for (int i = 0; i < 100; ++i) pole.push_back(r * V3(1e-11 * u(rng) / 5.0, 1e-11 * u(rng) / 5.0, u(rng)));
  EXPECT_EQ(convexHull(pole).dimension, 1);
}

TEST(ConvexHull2d, SquareWithInteriorPointsIsCounterClockwise) {
  std::vector<Eigen::Vector2d> q = {{0.5, 0.5}, {1, 0}, {0.2, 0.7}, {1, 1}, {0, 0}, {0.5, 0.0}, {0, 1}};
  const std::vector<int> ring = convexHull2d(q);
  ASSERT_EQ(ring.size(), 4u);
  EXPECT_EQ(std::set<int>(ring.begin(), ring.end()), (std::set<int>{1, 3, 4, 6}));
  double area2 = 0.0;
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const auto& a = q[ring[i]];
    const auto& b = q[ring[(i + 1) % ring.size()]];
    area2 += a.x() * b.y() - a.y() * b.x();
  }
  EXPECT_DOUBLE_EQ(area2, 2.0);  // positive: counter-clockwise
  EXPECT_TRUE(convexHull2d({}).empty());
  EXPECT_EQ(convexHull2d({{1, 1}, {1, 1}}).size(), 1u);
  EXPECT_EQ(convexHull2d({{0, 0}, {1, 1}, {2, 2}}).size(), 2u);
}

}  // namespace
}  // namespace nestwalk
