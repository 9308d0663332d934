// Triangle-box overlap and distance (triangle_box.h) against FCL 0.7 and against hand-computed
// cases. (The exact-arithmetic oracle, CGAL, is in tests/geometry_cgal/triangle_box_cgal_test.cpp.)
//
// Data: rotated boxes (uniform random rotations) with centres at the origin or at UTM magnitudes
// (x ~ 5e5, y ~ 4.5e6 m), triangles within a few metres of them. Centres are on a 2^-10 m grid and
// the triangles' offsets from the centre on a 2^-24 m grid, so the world coordinates are exact
// and "the same case in the box's local frame" (what FCL gets: box at the origin, triangle minus
// the centre) is exactly the same geometry. A quarter of the triangles have an edge within 1e-7 rad
// of a box axis (near-parallel edge axes), a fifth have a vertex within 1e-7 m of a face.
//
// Oracles and what must agree:
//  - overlap: fcl::collide(fcl::Box, fcl::TriangleP) (libccd's GJK/MPR, tolerance ~1e-6): the
//    verdicts must agree wherever our distance from the triangle to the box is above 1e-6 m (GJK's
//    tolerance band); the disagreements inside the band are counted and printed.
//  - distance: fcl::distance between the box as a 12-triangle BVHModel and the triangle as a
//    one-triangle BVHModel, which runs PQP's exact-in-double triangle-triangle distance; for
//    separated pairs (the surfaces' distance is then the solids') ours must agree within 1e-9
//    relative (1e-12 m absolute near zero); so must fcl::distance(fcl::Box, one-triangle
//    BVHModel), which runs libccd's GJK (distance_tolerance set to 1e-12). The worst relative
//    errors (distances above 1 um) are printed.
//  - the same case at the origin and at UTM magnitudes: identical verdicts and distances within
//    1e-9 relative.
#include "nestwalk/geometry/triangle_box.h"

#include "tests/geometry/test_shapes.h"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

namespace nestwalk {
namespace {

using V3 = Vec3<double>;

double snap(double v, double unit) { return std::round(v / unit) * unit; }

Obb<double> axisBox(const V3& centre, const V3& half) { return {centre, Mat3<double>::Identity(), half}; }

// ---- Hand-computed cases. ----

TEST(TriangleBox, TouchingCountsAsOverlap) {
  const Obb<double> box = axisBox(V3(1, 2, 3), V3(0.5, 0.25, 1));
  // A vertex exactly on the +x face, the rest beyond it.
  EXPECT_TRUE(triangleBoxOverlap({V3(1.5, 2, 3), V3(3, 2, 3), V3(3, 3, 3)}, box));
  // An edge lying in the +z face plane, crossing the face.
  EXPECT_TRUE(triangleBoxOverlap({V3(0, 2, 4), V3(2, 2, 4), V3(1, 2, 6)}, box));
  // Coplanar with the -y face and covering it.
  EXPECT_TRUE(triangleBoxOverlap({V3(-5, 1.75, -5), V3(5, 1.75, -5), V3(0, 1.75, 10)}, box));
  // One ulp beyond the +x face: separated.
  EXPECT_FALSE(triangleBoxOverlap({V3(std::nextafter(1.5, 2.0), 2, 3), V3(3, 2, 3), V3(3, 3, 3)}, box));
  // Touching an edge of the box with an edge of the triangle (crossing edges, the edge axis decides).
  const Obb<double> unit = axisBox(V3::Zero(), V3(1, 1, 1));
  EXPECT_TRUE(triangleBoxOverlap({V3(2, 0, 1), V3(0, 2, 1), V3(3, 3, 5)}, unit));   // touches (1, 1, 1)
  EXPECT_FALSE(triangleBoxOverlap({V3(2.0000001, 0, 1), V3(0, 2.0000001, 1), V3(3, 3, 5)}, unit));
}

TEST(TriangleBox, EdgeAndNormalAxesSeparate) {
  const Obb<double> unit = axisBox(V3::Zero(), V3(1, 1, 1));
  // The triangle's normal separates: a plane x + y + z = 3.5 cutting no corner (the corner sum is 3).
  EXPECT_FALSE(triangleBoxOverlap({V3(3.5, 0, 0), V3(0, 3.5, 0), V3(0, 0, 3.5)}, unit));
  EXPECT_TRUE(triangleBoxOverlap({V3(3, 0, 0), V3(0, 3, 0), V3(0, 0, 3)}, unit));  // through (1, 1, 1)
  // A large triangle slicing through the box with every vertex outside it.
  EXPECT_TRUE(triangleBoxOverlap({V3(-10, -10, 0.5), V3(10, -10, 0.5), V3(0, 10, 0.5)}, unit));
  // A triangle containing the box's interior point (the box inside the triangle's plane is impossible;
  // a tiny box inside a big triangle's slab).
  EXPECT_TRUE(triangleBoxOverlap({V3(-10, -10, 0), V3(10, -10, 0), V3(0, 10, 0)}, axisBox(V3(0, 0, 0), V3(0, 0, 0))));
}

TEST(TriangleBox, DegenerateTriangles) {
  const Obb<double> unit = axisBox(V3::Zero(), V3(1, 1, 1));
  // A point: inside, on a corner, outside.
  EXPECT_TRUE(triangleBoxOverlap({V3(0.5, 0.5, 0.5), V3(0.5, 0.5, 0.5), V3(0.5, 0.5, 0.5)}, unit));
  EXPECT_TRUE(triangleBoxOverlap({V3(1, -1, 1), V3(1, -1, 1), V3(1, -1, 1)}, unit));
  EXPECT_FALSE(triangleBoxOverlap({V3(1, -1, 1.5), V3(1, -1, 1.5), V3(1, -1, 1.5)}, unit));
  // A segment (collinear triangle) crossing the box with both ends outside.
  EXPECT_TRUE(triangleBoxOverlap({V3(-3, -3, 0), V3(3, 3, 0), V3(0, 0, 0)}, unit));
  // A segment passing a corner diagonally: the edge axis z x (1, -1, 0) separates it.
  EXPECT_FALSE(triangleBoxOverlap({V3(2.5, 0, 0), V3(0, 2.5, 0), V3(1.25, 1.25, 0)}, unit));
  EXPECT_TRUE(triangleBoxOverlap({V3(2, 0, 0), V3(0, 2, 0), V3(1, 1, 0)}, unit));  // through (1, 1, 0)
  // Two coincident vertices.
  EXPECT_FALSE(triangleBoxOverlap({V3(2.5, 0, 0), V3(2.5, 0, 0), V3(0, 2.5, 0)}, unit));
  // A flat box (zero half extent) and a segment in its plane.
  EXPECT_TRUE(triangleBoxOverlap({V3(-2, 0.5, 0), V3(2, 0.5, 0), V3(0, 0.5, 0)}, axisBox(V3::Zero(), V3(1, 1, 0))));
}

TEST(TriangleBox, DistanceOfHandComputedCases) {
  const Obb<double> unit = axisBox(V3::Zero(), V3(1, 1, 1));
  // Parallel to the top face, 0.5 above it (face-face: a box corner against the triangle's face).
  EXPECT_DOUBLE_EQ(triangleBoxDistance({V3(-5, -5, 1.5), V3(5, -5, 1.5), V3(0, 5, 1.5)}, unit), 0.5);
  // A vertex in front of the +x face.
  EXPECT_DOUBLE_EQ(triangleBoxDistance({V3(3, 0, 0), V3(5, 1, 0), V3(5, -1, 0)}, unit), 2.0);
  // Edge-edge: the triangle's edge along (1, -1, 0) at z = 0 passing the corner edge (x = y = 1)
  // at distance (2.5 - 2) / sqrt(2).
  EXPECT_NEAR(triangleBoxDistance({V3(2.5, 0, 0), V3(0, 2.5, 0), V3(5, 5, 0)}, unit), 0.5 / std::sqrt(2.0), 1e-15);
  // Overlap gives 0; a degenerate (point) triangle gives the point-box distance.
  EXPECT_EQ(triangleBoxDistance({V3(0, 0, 0), V3(3, 0, 0), V3(0, 3, 0)}, unit), 0.0);
  EXPECT_DOUBLE_EQ(triangleBoxDistance({V3(4, 5, 1), V3(4, 5, 1), V3(4, 5, 1)}, unit), 5.0);
  // Rotated box: a unit cube turned 45 degrees about z, a vertex on the x axis at x = 3.
  Obb<double> turned = unit;
  turned.axes = Eigen::AngleAxisd(std::numbers::pi / 4, V3::UnitZ()).toRotationMatrix();
  EXPECT_NEAR(triangleBoxDistance({V3(3, 0, 0), V3(6, 1, 0), V3(6, -1, 0)}, turned), 3 - std::sqrt(2.0), 1e-14);
}

// ---- FCL cross-checks. ----

struct Case {
  Obb<double> box;  // at the case's origin
  Triangle tri;     // world coordinates
  Triangle local;   // tri - box.center, exactly
};

// A random case around `origin` (see the file comment for the grids).
Case randomCase(std::mt19937& rng, const V3& origin) {
  std::uniform_real_distribution<double> unit(-1, 1), ext(0.02, 1.5), len(0.05, 3);
  Case c;
  c.box.center = origin + V3(snap(2 * unit(rng), 0x1p-10), snap(2 * unit(rng), 0x1p-10), snap(2 * unit(rng), 0x1p-10));
  c.box.axes = testshapes::randomRotation(rng);
  c.box.halfExtents = V3(snap(ext(rng), 0x1p-20), snap(ext(rng), 0x1p-20), snap(ext(rng), 0x1p-20));
  const double reach = c.box.halfExtents.norm() + 0.3;
  V3 corner[3];
  corner[0] = V3(unit(rng), unit(rng), unit(rng)) * reach;
  const unsigned kind = rng() % 5;
  if (kind == 0) {
    // A vertex within ~1e-7 m of the +x face (inside or out), the triangle leaving the box.
    const V3& h = c.box.halfExtents;
    const V3 onFace(h.x() + 1e-7 * unit(rng), h.y() * unit(rng), h.z() * unit(rng));
    corner[0] = c.box.axes * onFace;
    for (int i = 1; i < 3; ++i)
      corner[i] = corner[0] + c.box.axes * V3(std::abs(unit(rng)), unit(rng), unit(rng)) * len(rng);
  } else if (kind == 1) {
    // An edge within ~1e-7 rad of a box axis.
    const int k = int(rng() % 3);
    const V3 along = c.box.axes.col(k) + 1e-7 * V3(unit(rng), unit(rng), unit(rng));
    corner[1] = corner[0] + along * len(rng);
    corner[2] = corner[0] + V3(unit(rng), unit(rng), unit(rng)) * len(rng);
  } else {
    for (int i = 1; i < 3; ++i) corner[i] = corner[0] + V3(unit(rng), unit(rng), unit(rng)) * len(rng);
  }
  for (int i = 0; i < 3; ++i) {
    for (int m = 0; m < 3; ++m) c.local[i][m] = snap(corner[i][m], 0x1p-24);
    c.tri[i] = c.box.center + c.local[i];
  }
  return c;
}

Obb<double> atOrigin(const Obb<double>& box) { return {V3::Zero(), box.axes, box.halfExtents}; }

fcl::Transform3d rotationOnly(const Obb<double>& box) {
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.linear() = box.axes;
  return tf;
}

std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> oneTriangleModel(const Triangle& t) {
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  model->beginModel();
  model->addTriangle(t[0], t[1], t[2]);
  model->endModel();
  return model;
}

fcl::Boxd fclBox(const Obb<double>& b) { return {2 * b.halfExtents.x(), 2 * b.halfExtents.y(), 2 * b.halfExtents.z()}; }

// libccd's GJK between the solid box and the one-triangle model (FCL has no box-TriangleP pair).
bool fclCollide(const Case& c) {
  const fcl::Boxd box = fclBox(c.box);
  const auto tri = oneTriangleModel(c.local);
  fcl::CollisionRequestd request;
  fcl::CollisionResultd result;
  fcl::collide(&box, rotationOnly(c.box), tri.get(), fcl::Transform3d::Identity(), request, result);
  return result.isCollision();
}

// The box's surface as 12 triangles, in its own frame.
std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> boxSurfaceModel(const V3& h) {
  static const int kFaces[12][3] = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
                                    {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
  const Obb<double> box{V3::Zero(), Mat3<double>::Identity(), h};
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  model->beginModel();
  for (const auto& f : kFaces) model->addTriangle(box.corner(f[0]), box.corner(f[1]), box.corner(f[2]));
  model->endModel();
  return model;
}

// PQP's triangle-triangle distance between the box's surface and the triangle (local frame).
double fclSurfaceDistance(const Case& c) {
  const auto box = boxSurfaceModel(c.box.halfExtents);
  const auto tri = oneTriangleModel(c.local);
  fcl::DistanceRequestd request;
  fcl::DistanceResultd result;
  return fcl::distance(box.get(), rotationOnly(c.box), tri.get(), fcl::Transform3d::Identity(), request, result);
}

// libccd's GJK between the solid box and the one-triangle model.
double fclGjkDistance(const Case& c) {
  const fcl::Boxd box = fclBox(c.box);
  const auto tri = oneTriangleModel(c.local);
  fcl::DistanceRequestd request;
  request.distance_tolerance = 1e-12;
  fcl::DistanceResultd result;
  return fcl::distance(&box, rotationOnly(c.box), tri.get(), fcl::Transform3d::Identity(), request, result);
}

constexpr double kGjkBand = 1e-6;             // metres: libccd's tolerance in fcl::collide
constexpr double kDistanceRelative = 1e-9;
constexpr double kDistanceAbsolute = 1e-12;   // metres, for distances near zero

void crossCheckWithFcl(const V3& origin, const char* label) {
  std::mt19937 rng(origin.x() == 0 ? 11 : 12);
  const int kCases = 3000;
  int overlaps = 0, inBand = 0, distanceChecks = 0;
  double worstRelative = 0, worstGjk = 0;
  for (int n = 0; n < kCases; ++n) {
    const Case c = randomCase(rng, origin);
    const bool ours = triangleBoxOverlap(c.tri, c.box);
    const double distance = triangleBoxDistance(c.tri, c.box);
    ASSERT_EQ(ours, distance == 0) << label << " case " << n;
    overlaps += ours;
    // The same case in the local frame: the same verdict, the same distance.
    const Obb<double> local = atOrigin(c.box);
    ASSERT_EQ(ours, triangleBoxOverlap(c.local, local)) << label << " case " << n;
    ASSERT_NEAR(distance, triangleBoxDistance(c.local, local), kDistanceRelative * distance + kDistanceAbsolute);

    if (ours != fclCollide(c)) {
      ASSERT_LE(distance, kGjkBand) << label << " case " << n << ": FCL disagrees outside its tolerance band";
      ++inBand;
    }
    if (!ours) {
      const double reference = fclSurfaceDistance(c);
      const double relative = std::abs(distance - reference) / std::max(reference, 1e-300);
      ASSERT_NEAR(distance, reference, kDistanceRelative * reference + kDistanceAbsolute) << label << " case " << n;
      worstRelative = std::max(worstRelative, reference > 1e-6 ? relative : 0.0);
      const double gjk = fclGjkDistance(c);
      ASSERT_NEAR(distance, gjk, kDistanceRelative * gjk + kDistanceAbsolute) << label << " case " << n;
      worstGjk = std::max(worstGjk, reference > 1e-6 ? std::abs(gjk - reference) / reference : 0.0);
      ++distanceChecks;
    }
  }
  std::printf("[%s] %d cases, %d overlapping; fcl::collide disagreements inside its %g m band: %d; "
              "%d distances: worst relative difference to PQP (box surface mesh) %.2e; libccd GJK vs PQP: %.2e\n",
              label, kCases, overlaps, kGjkBand, inBand, distanceChecks, worstRelative, worstGjk);
  EXPECT_GT(overlaps, kCases / 10);
  EXPECT_GT(distanceChecks, kCases / 10);
}

TEST(TriangleBoxFcl, AgreesAtTheOrigin) { crossCheckWithFcl(V3::Zero(), "origin"); }
TEST(TriangleBoxFcl, AgreesAtUtmMagnitudes) { crossCheckWithFcl(V3(512345.0, 4476543.0, 1210.0), "utm"); }

}  // namespace
}  // namespace nestwalk
