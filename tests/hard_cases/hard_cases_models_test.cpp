// Hard cases of degenerate equipment models, loaded as a user loads them (a scene file over a level
// GeoTIFF, models written as .osgt): a model with no triangles (points and lines only), a model of a
// single triangle, and a model whose points are all coplanar (a flat panel: an OBB with a zero half
// extent). For each: the volumes, the box tests (SAT, nested) and the triangle tests (the mesh trees
// behind nested+mesh and kdop18) against exact answers, and the walker with every method.
// Exact answers: the constructions are dyadic and axis-aligned where a contact is touched exactly
// (boxes resting on a panel, a face on a sign's plane), so contact is a closed-form predicate; the
// in-plane decisions are kept far (>= 5 cm) from any edge; elsewhere FCL's distance to the triangles
// as OSG's reader returns them (hard_case_util.h) and the long double SAT of sat_reference.h on the
// boxes given to the engine.
#include "nestwalk/geometry/nested.h"
#include "nestwalk/geometry/sat.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/walker/mesh_world.h"
#include "nestwalk/walker/walker.h"
#include "tests/geometry/sat_reference.h"
#include "tests/hard_cases/hard_case_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <cstdio>
#include <limits>
#include <random>
#include <string>

namespace nestwalk {
namespace {

using namespace nestwalk::hardcase;
using testref::Expect;

Obb<double> axisBox(const V3& c, const V3& h) { return {c, Mat3<double>::Identity(), h}; }

/// What satObbObb must answer for (a, b) by the long double reference and sat.h's documented band.
Expect satRequirement(const Obb<double>& a, const Obb<double>& b) {
  const testref::SatRef r = testref::ldSat(a, b);
  const testref::SatModel model{kParallelEpsilon<double>, kRoundingSlack<double>, 0};
  return testref::expectInflated(r, model, 32 * 0x1p-53L * (r.extent + r.absCoord), true);
}

/// Walks north from local (x, y0) to (x, y1) at `speed` with a fresh walker of `method`.
Walker& walkNorth(SceneRig& rig, const FlatSite& site, VolumeMethod method, double x, double y0, double y1, double speed) {
  Walker& w = rig.walker(method);
  const Eigen::Vector2d a = site.map(x, y0), b = site.map(x, y1);
  EXPECT_EQ(w.place({a.x(), a.y(), 0}, false, 0, false, 2.0), "");
  walkToward(w, b, speed, 0);
  return w;
}

// ------------------------------------------------------------------------------------------------
// Situation: a model without triangles. A survey frame drawn as the 8 corners of the box
// [-0.5, 0.5] x [-0.5, 0.5] x [0, 2] (GL_POINTS) and its 12 edges (GL_LINES). Exact answers: the
// volumes come from the points: the outer AABB is that box (placed), the inner OBB holds the 8
// points and, the points being a box's corners, is that box (volume 2). The nested method blocks
// the walker within 1 mm of the box (FCL, box against box). The exact methods test triangles and
// there are none: MeshWorld holds an empty tree (distance +infinity, overlaps false), and a unit
// without any triangle falls back to its nested volumes (a point cloud or a wireframe still stands
// in the way), so nested+mesh and kdop18 stop where nested does.
TEST(HardCase, DegenerateModel_NoTriangles) {
  ScratchFolder dir;
  const FlatSite site{{0.0, 64.0}};
  osg::ref_ptr<osg::Vec3Array> corners = new osg::Vec3Array;
  const Mesh frame = boxMesh(V3(-0.5, -0.5, 0), V3(0.5, 0.5, 2));
  for (const V3& p : frame.vertices) corners->push_back(osg::Vec3(float(p.x()), float(p.y()), float(p.z())));
  osg::ref_ptr<osg::DrawElementsUInt> edges = new osg::DrawElementsUInt(GL_LINES);
  for (std::uint32_t i = 0; i < 8; ++i)
    for (std::uint32_t bit : {1u, 2u, 4u})
      if (!(i & bit)) {
        edges->push_back(i);
        edges->push_back(i | bit);
      }
  osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
  g->setVertexArray(corners);
  g->addPrimitiveSet(new osg::DrawArrays(GL_POINTS, 0, 8));
  g->addPrimitiveSet(edges);
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->addDrawable(g);
  writeModel(*geode, dir / "frame.osgt");
  const Eigen::Vector2d at = site.map(0, 5);
  SceneRig rig(writeSceneFile(dir.path(), site.writeTerrain(dir.path()), site.origin(),
                              Json::array({equipment("frame", dir / "frame.osgt", at.x(), at.y())})));
  ASSERT_EQ(rig.scene().models[0].mesh.triangles.size(), 0u);
  const NestedVolume<double>& v = rig.scene().units[0].volume;
  const V3 lo(-0.5, 4.5, 0), hi(0.5, 5.5, 2);
  EXPECT_LT((v.outer.min - lo).cwiseAbs().maxCoeff(), 1e-12) << v.outer.min.transpose();
  EXPECT_LT((v.outer.max - hi).cwiseAbs().maxCoeff(), 1e-12) << v.outer.max.transpose();
  for (const V3& p : frame.vertices) EXPECT_TRUE(insideBox(v.inner, p + V3(0, 5, 0), 1e-9)) << p.transpose();
  EXPECT_NEAR(v.inner.volume(), 2.0, 1e-9) << "the box of a box's corners";

  MeshQueryCounters c;
  EXPECT_EQ(rig.meshes().triangles(0), 0u);
  const Obb<double> around = axisBox(V3(0, 5, 1), V3(1, 1, 1.5));
  EXPECT_FALSE(rig.meshes().overlaps(0, around, c));
  EXPECT_EQ(rig.meshes().distance(0, around, c), std::numeric_limits<double>::infinity());

  const Mesh box = boxMesh(lo, hi);  // the frame's solid box, for the nested stop
  Walker& nested = walkNorth(rig, site, VolumeMethod::Nested, 0.2, -1, 10, 5.0);
  EXPECT_TRUE(nested.state().blocked);
  const double gap = fclBoxMeshDistance(bodyBox(nested), box);
  EXPECT_GT(gap, 0.0);
  EXPECT_LE(gap, 1e-3);
  for (VolumeMethod method : {VolumeMethod::NestedMesh, VolumeMethod::Kdop18}) {
    Walker& w = walkNorth(rig, site, method, 0.2, -1, 10, 5.0);
    EXPECT_TRUE(w.state().blocked) << volumeMethodName(method);
    const double g = fclBoxMeshDistance(bodyBox(w), box);
    EXPECT_GT(g, 0.0) << volumeMethodName(method);
    EXPECT_LE(g, 1e-3) << volumeMethodName(method);
  }
  std::printf("  nested stops %.3f mm short of the frame's box; so do nested+mesh and kdop18 (no triangles: volumes)\n",
              1e3 * gap);
}

// ------------------------------------------------------------------------------------------------
// Situation: a model of a single triangle. A sign (-1, 0, 0.2), (1, 0, 0.2), (0.3, 0, 1) in the
// model's plane y = 0, placed at local (0, 5): the plane y = 5. Its OBB is flat (a zero half extent,
// obb_fit.h) and holds the three corners. Axis-aligned test boxes (the body's size) with their north
// face at y = 5 - g (g = 0: on the plane; 2^-30 and 2^-20 m short of it; 2^-20 m across it) and x
// ranges inside the triangle's reach, across its right corner, or 5 cm clear of it. Exact answer:
// contact iff g <= 0 and the x-z rectangle meets the triangle (decided with margins >= 5 cm); the
// triangle tests must give it exactly, distance g when the rectangle meets it; satObbObb must not
// miss a contact and must separate where the reference separates beyond sat.h's band. Walking into
// it head-on every method stops within 1 mm; 5 cm clear of its corner every method walks past.
TEST(HardCase, DegenerateModel_SingleTriangle) {
  ScratchFolder dir;
  const FlatSite site{{0.0, 64.0}};
  Mesh sign;
  sign.vertices = {V3(-1, 0, 0.2), V3(1, 0, 0.2), V3(0.3, 0, 1.0)};
  sign.triangles = {{0, 1, 2}};
  writeModel(*toGeode(sign), dir / "sign.osgt");
  const Eigen::Vector2d at = site.map(0, 5);
  SceneRig rig(writeSceneFile(dir.path(), site.writeTerrain(dir.path()), site.origin(),
                              Json::array({equipment("sign", dir / "sign.osgt", at.x(), at.y())})));
  const Mesh placed = transformed(readBack(dir / "sign.osgt"), instanceToLocal(0, 0, 0, 1, V3(0, 5, 0)));
  const NestedVolume<double>& v = rig.scene().units[0].volume;
  EXPECT_EQ(v.inner.halfExtents.minCoeff(), 0.0) << "a triangle's OBB is flat";
  for (const V3& p : placed.vertices) EXPECT_TRUE(insideBox(v.inner, p, 1e-9)) << p.transpose();

  const V3 half(0.25, 0.25, 0.9);
  struct Lateral {
    double x;
    bool meets;  // the box's x-z rectangle (z in [0, 1.8]) meets the triangle
  };
  const Lateral laterals[] = {{0.0, true}, {-0.5, true}, {1.2, true}, {1.3, false}, {-1.3, false}};
  const double gaps[] = {0.0, 0x1p-30, 0x1p-20, -0x1p-20};
  int checked = 0;
  for (const Lateral& l : laterals)
    for (double g : gaps) {
      const Obb<double> box = axisBox(V3(l.x, 5 - g - half.y(), half.z()), half);
      ASSERT_EQ(box.center.y() + half.y(), 5 - g) << "the construction must be exact";
      const bool contact = g <= 0 && l.meets;
      MeshQueryCounters c;
      EXPECT_EQ(rig.meshes().overlaps(0, box, c), contact) << "x " << l.x << " g " << g;
      const double d = rig.meshes().distance(0, box, c);
      if (contact) {
        EXPECT_EQ(d, 0.0);
      } else if (l.meets) {
        EXPECT_EQ(d, g) << "x " << l.x << ": the distance across the plane";
      } else {
        EXPECT_NEAR(d, fclBoxMeshDistance(box, placed), 1e-9) << "x " << l.x << " g " << g;
      }
      const bool sat = satObbObb(v.inner, box).overlap;
      if (contact) {
        EXPECT_TRUE(sat) << "satObbObb missed a contact, x " << l.x << " g " << g;
        EXPECT_TRUE(testNested(NestedVolume<double>::fromObb(box), v).overlap) << "testNested missed a contact";
      } else {
        const Expect need = satRequirement(v.inner, box);
        if (need != Expect::Either) {
          EXPECT_EQ(sat, need == Expect::Overlap) << "x " << l.x << " g " << g;
        }
      }
      ++checked;
    }
  for (VolumeMethod method : {VolumeMethod::Nested, VolumeMethod::NestedMesh, VolumeMethod::Kdop18}) {
    Walker& head = walkNorth(rig, site, method, 0.0, 0, 10, 13.0);
    EXPECT_TRUE(head.state().blocked) << volumeMethodName(method);
    const double gap = fclBoxMeshDistance(bodyBox(head), placed);
    EXPECT_GT(gap, 0.0) << volumeMethodName(method);
    EXPECT_LE(gap, 1e-3) << volumeMethodName(method);
    Walker& past = walkNorth(rig, site, method, 1.3, 0, 10, 13.0);
    EXPECT_FALSE(past.state().blocked) << volumeMethodName(method) << " 5 cm clear of the corner";
  }
  std::printf("  %d boxes against the triangle: triangle tests exact, SAT without a missed contact\n", checked);
}

// ------------------------------------------------------------------------------------------------
// Situation: a model whose points are all coplanar. A 2 x 1 m panel of 16 triangles in the model's
// plane z = 1 (a table top without legs), placed level at local (0, 5) and pitched 30 degrees at
// (4, 5). Its OBB is flat (a zero half extent) and, the triangles tiling a rectangle, is that
// rectangle: half extents (1, 0.5, 0). Level panel, exact answers: boxes resting on it (bottom at
// z = 1 + g) or hanging under it (top at 1 - g), over it, across its edge or 0.1 m off it, with
// g = 0, 2^-40, 2^-20, -2^-20: contact iff g <= 0 and the footprints meet; the triangle tests give
// it exactly (g = 2^-40 is 9e-13 m: separated), the distance is g; satObbObb and the nested test
// never miss it, and separate at 2^-20 m (2^-40 m lies inside sat.h's band: either). Pitched panel:
// the triangle distance equals FCL's, and the SAT on the flat OBB agrees with it outside sat.h's
// band (the OBB is the panel). Walking into the level panel's edge at 1.4 and 50 m/s (a zero-
// thickness object), every method stops within 1 mm.
TEST(HardCase, DegenerateModel_CoplanarPanel) {
  ScratchFolder dir;
  const FlatSite site{{0.0, 64.0}};
  Mesh panel;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 5; ++i) panel.vertices.emplace_back(-1 + 0.5 * i, -0.5 + 0.5 * j, 1.0);
  for (std::uint32_t j = 0; j < 2; ++j)
    for (std::uint32_t i = 0; i < 4; ++i) {
      const std::uint32_t a = 5 * j + i;
      panel.triangles.push_back({a, a + 1, a + 6});
      panel.triangles.push_back({a, a + 6, a + 5});
    }
  writeModel(*toGeode(panel), dir / "panel.osgt");
  const Eigen::Vector2d a = site.map(0, 5), b = site.map(4, 5);
  SceneRig rig(writeSceneFile(dir.path(), site.writeTerrain(dir.path()), site.origin(),
                              Json::array({equipment("level", dir / "panel.osgt", a.x(), a.y()),
                                           equipment("pitched", dir / "panel.osgt", b.x(), b.y(), 0, 30)})));
  const Mesh level = transformed(readBack(dir / "panel.osgt"), instanceToLocal(0, 0, 0, 1, V3(0, 5, 0)));
  const Mesh pitched = transformed(readBack(dir / "panel.osgt"), instanceToLocal(0, 30, 0, 1, V3(4, 5, 0)));
  for (int u = 0; u < 2; ++u) {
    const Obb<double>& inner = rig.scene().units[std::size_t(u)].volume.inner;
    EXPECT_EQ(inner.halfExtents.minCoeff(), 0.0) << "unit " << u << ": coplanar points give a flat OBB";
    EXPECT_LT((inner.halfExtents - V3(1, 0.5, 0)).cwiseAbs().maxCoeff(), 1e-9) << "unit " << u << ": " << inner.halfExtents.transpose();
    for (const V3& p : (u == 0 ? level : pitched).vertices) EXPECT_TRUE(insideBox(inner, p, 1e-9));
  }
  const NestedVolume<double>& v = rig.scene().units[0].volume;
  EXPECT_LT(std::abs(v.outer.min.z() - 1.0), 1e-14);
  EXPECT_LT(std::abs(v.outer.max.z() - 1.0), 1e-14);

  // Level panel: boxes of half extents (0.25, 0.125, 0.375) resting on it or hanging under it.
  const V3 half(0.25, 0.125, 0.375);
  struct Place {
    double x;
    bool meets;
  };
  const Place places[] = {{0.125, true}, {0.875, true}, {-1.125, true}, {1.375, false}, {-1.375, false}};
  const double gaps[] = {0.0, 0x1p-40, 0x1p-20, -0x1p-20};
  MeshQueryCounters c;
  for (const Place& p : places)
    for (double g : gaps)
      for (int side : {+1, -1}) {
        const Obb<double> box = axisBox(V3(p.x, 5.125, 1 + side * (g + half.z())), half);
        ASSERT_EQ(box.center.z() - side * half.z(), 1 + side * g) << "the construction must be exact";
        const bool contact = g <= 0 && p.meets;
        const std::string what = "x " + std::to_string(p.x) + " g " + std::to_string(g) + (side > 0 ? " above" : " below");
        EXPECT_EQ(rig.meshes().overlaps(0, box, c), contact) << what;
        if (p.meets) {
          EXPECT_EQ(rig.meshes().distance(0, box, c), std::max(g, 0.0)) << what;
        }
        const bool sat = satObbObb(v.inner, box).overlap;
        const bool nested = testNested(NestedVolume<double>::fromObb(box), v).overlap;
        if (contact) {
          EXPECT_TRUE(sat) << "satObbObb missed a contact: " << what;
          EXPECT_TRUE(nested) << "testNested missed a contact: " << what;
        } else if (g >= 0x1p-20 || !p.meets) {
          EXPECT_FALSE(sat) << what;
          EXPECT_FALSE(nested) << what;
        }
      }

  // Pitched panel: random boxes around it.
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> U(-1, 1);
  const Obb<double>& tilted = rig.scene().units[1].volume.inner;
  int contacts = 0, outsideBand = 0;
  for (int k = 0; k < 300; ++k) {
    const Obb<double> box{V3(4 + 1.3 * U(rng), 5 + 0.9 * U(rng), 0.9 + 0.6 * U(rng)),
                          Eigen::AngleAxisd(std::numbers::pi * U(rng), V3(U(rng), U(rng), U(rng)).normalized()).toRotationMatrix(),
                          V3(0.02 + 0.2 * std::abs(U(rng)), 0.02 + 0.2 * std::abs(U(rng)), 0.02 + 0.2 * std::abs(U(rng)))};
    const double ref = fclBoxMeshDistance(box, pitched);
    EXPECT_NEAR(rig.meshes().distance(1, box, c), ref, 1e-9) << "box " << k;
    const bool sat = satObbObb(tilted, box).overlap;
    if (ref == 0) {
      EXPECT_TRUE(sat) << "box " << k << ": SAT missed a contact with the pitched panel";
      ++contacts;
    } else if (ref > 1e-6) {
      EXPECT_FALSE(sat) << "box " << k << ": " << ref << " m from the panel, SAT says overlap";
      ++outsideBand;
    }
  }
  EXPECT_GT(contacts, 20);

  for (VolumeMethod method : {VolumeMethod::Nested, VolumeMethod::NestedMesh, VolumeMethod::Kdop18})
    for (double speed : {1.4, 50.0}) {
      Walker& w = walkNorth(rig, site, method, 0.3, 0, 10, speed);
      const std::string what = std::string(volumeMethodName(method)) + " at " + std::to_string(speed) + " m/s";
      EXPECT_TRUE(w.state().blocked) << what;
      const double gap = fclBoxMeshDistance(bodyBox(w), level);
      EXPECT_GT(gap, 0.0) << what;
      EXPECT_LE(gap, 1e-3) << what;
      const double front = w.state().feet.y() - site.origin().y() + 0.25;
      EXPECT_LT(front, 4.5) << what;
      EXPECT_GE(front, 4.5 - 1e-3) << what;
    }
  std::printf("  pitched panel: %d boxes in contact, %d more than 1 um away; SAT on the flat OBB agreed on all\n", contacts,
              outsideBand);
}

}  // namespace
}  // namespace nestwalk
