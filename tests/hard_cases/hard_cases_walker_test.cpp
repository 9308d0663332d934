// Hard cases of the walker against equipment with the exact methods (nested+mesh: the nested test
// then the model's triangles through a k-DOP-18 tree; kdop18: the same tree without the nested test;
// engine/walker/mesh_world.h), on scenes written to a temporary folder: a level GeoTIFF, models
// built here and written as .osgt, scene.json. Situations: fast motion past a thin pole, a model
// whose OBB is far bigger than its triangles, a model in millimetres, models authored Y-up, and the
// same scene at UTM magnitudes and moved to the origin.
// Exact reference for every gap: FCL's distance (BVH-BVH, PQP's triangle-triangle distance) from
// the walker's body box to the model's triangles as OSG's reader returns them, placed by this
// suite's own transform (Eigen, the documented heading/pitch/roll/scale convention); closed forms
// where the geometry is axis-aligned. The engine's trees are not consulted for any reference.
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/walker/collision_world.h"
#include "nestwalk/walker/mesh_world.h"
#include "nestwalk/walker/walker.h"
#include "tests/hard_cases/hard_case_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <cstdio>
#include <random>
#include <string>

namespace nestwalk {
namespace {

using namespace nestwalk::hardcase;

const char* nameOf(VolumeMethod m) { return volumeMethodName(m); }

/// The stop of a walk into an obstacle: blocked by unit `unit`, outside the triangles, at most 1 mm
/// from them (FCL). Returns the gap.
double expectStoppedWithinAMillimetre(const Walker& w, const Mesh& localTriangles, int unit, const std::string& what) {
  const WalkerState& s = w.state();
  EXPECT_TRUE(s.blocked) << what;
  EXPECT_EQ(s.reason, BlockReason::Equipment) << what;
  EXPECT_EQ(s.blockedUnit, unit) << what;
  const double gap = fclBoxMeshDistance(bodyBox(w), localTriangles);
  EXPECT_GT(gap, 0.0) << what << ": the body touches or overlaps the triangles";
  EXPECT_LE(gap, 1e-3) << what << ": stopped " << gap << " m short";
  return gap;
}

// ------------------------------------------------------------------------------------------------
// Situation: fast motion past a thin object. A 5 cm pole (24-sided prism, radius 2.5 cm at the
// corners, 3 m tall) in a scene; the walker (body 0.5 x 0.5 x 1.8 m) walks north at it at 0.5 to
// 50 m/s (up to 0.83 m a step, 17 pole widths) with lateral offsets from centred to grazing
// (0.27 m: the body's side 2 cm past the axis, inside the pole's 2.5 cm) and one clear of it
// (0.3 m). Exact answer: the walker meets the pole iff the body's x range reaches the prism (closed
// form, |offset| <= 0.25 + 0.025); then at every step the FCL distance to the pole is > 0 and the
// body is short of the pole's axis, and the stop is within 1 mm; clear of it, the walk is free.
TEST(HardCase, FastMotionPastThinPole_MeshMethods) {
  ScratchFolder dir;
  const FlatSite site{{0.0, 64.0}};
  writeModel(*toGeode(cylinderMesh(0.025, 3.0, 24)), dir / "pole.osgt");
  const Eigen::Vector2d at = site.map(0, 5);
  const fs::path file = writeSceneFile(dir.path(), site.writeTerrain(dir.path()), site.origin(),
                                       Json::array({equipment("pole", dir / "pole.osgt", at.x(), at.y())}));
  SceneRig rig(file);
  const Mesh pole = transformed(readBack(dir / "pole.osgt"), instanceToLocal(0, 0, 0, 1, V3(0, 5, 0)));
  double worst = 0;
  int walks = 0;
  for (VolumeMethod method : {VolumeMethod::NestedMesh, VolumeMethod::Kdop18})
    for (double speed : {0.5, 1.4, 5.0, 13.0, 27.0, 50.0})
      for (double lateral : {0.0, 0.13, -0.2, 0.27, -0.2749, 0.3}) {
        Walker& w = rig.walker(method);
        const Eigen::Vector2d start = site.map(lateral, -5), end = site.map(lateral, 15);
        ASSERT_EQ(w.place({start.x(), start.y(), 0}, false, 0, false, 2.0), "");
        const bool meets = std::abs(lateral) <= 0.25 + 0.025;
        const std::string what = std::string(nameOf(method)) + " at " + std::to_string(speed) + " m/s, offset " + std::to_string(lateral);
        walkToward(w, end, speed, 0, [&](const Walker& v) {
          if (!meets) return;
          const Obb<double> body = bodyBox(v);
          ASSERT_LT(body.center.y(), 5.0) << what << ": past the pole";
          if (body.center.y() < 4.0) return;  // a metre away: FCL only near the pole
          ASSERT_GT(fclBoxMeshDistance(body, pole), 0.0) << what << ": into the pole";
        });
        ++walks;
        if (meets) {
          worst = std::max(worst, expectStoppedWithinAMillimetre(w, pole, 0, what));
        } else {
          EXPECT_FALSE(w.state().blocked) << what;
          EXPECT_NEAR(w.state().feet.y(), end.y(), 1e-9) << what << ": the walk is free";
        }
      }
  std::printf("  %d walks; largest stop gap to the pole's triangles %.3f mm\n", walks, 1e3 * worst);
}

// ------------------------------------------------------------------------------------------------
// Situation: a model whose OBB is much bigger than its triangles. An L of two 4 m bars (0.2 m thick,
// 2 m tall) meeting at a right angle: any box holding it covers the empty square between the bars,
// so the nested test blocks the walker coming down the diagonal long before the triangles, while
// nested+mesh and kdop18 go on to within 1 mm of the bars' inner faces. Exact answers: the FCL
// distance to the L's triangles at the stops (nested: > 10 cm; the mesh methods: in (0, 1 mm]) and
// the closed form of the mesh stop: the body, turned 45 degrees, is a diamond whose west and south
// corners lie 0.25 sqrt 2 from its centre; they meet both inner faces (x = 0.2 and y = 0.2) at once
// when the centre is at 0.2 + 0.25 sqrt 2 on both axes.
TEST(HardCase, LShapedModel_NestedBlocksEarlyMeshGoesOn) {
  ScratchFolder dir;
  const FlatSite site{{0.0, 64.0}};
  Mesh l = boxMesh(V3(0, 0, 0), V3(4, 0.2, 2));
  l.append(boxMesh(V3(0, 0, 0), V3(0.2, 4, 2)));
  writeModel(*toGeode(l), dir / "ell.osgt");
  const Eigen::Vector2d at = site.map(0, 0);
  SceneRig rig(writeSceneFile(dir.path(), site.writeTerrain(dir.path()), site.origin(),
                              Json::array({equipment("ell", dir / "ell.osgt", at.x(), at.y())})));
  const Mesh ell = transformed(readBack(dir / "ell.osgt"), instanceToLocal(0, 0, 0, 1, V3::Zero()));
  for (VolumeMethod method : {VolumeMethod::Nested, VolumeMethod::NestedMesh, VolumeMethod::Kdop18}) {
    Walker& w = rig.walker(method);
    const Eigen::Vector2d start = site.map(5, 5);
    ASSERT_EQ(w.place({start.x(), start.y(), 0}, false, 225, false, 2.0), "");
    walkToward(w, site.map(-1, -1), 1.4, 225);
    const double gap = fclBoxMeshDistance(bodyBox(w), ell);
    const V3 centre = bodyBox(w).center;
    std::printf("  %-11s stops at local (%.4f, %.4f), %.4f m from the L's triangles\n", nameOf(method), centre.x(),
                centre.y(), gap);
    EXPECT_TRUE(w.state().blocked) << nameOf(method);
    if (method == VolumeMethod::Nested) {
      EXPECT_GT(gap, 0.1) << "the nested volumes were expected to block early";
    } else {
      EXPECT_GT(gap, 0.0) << nameOf(method);
      EXPECT_LE(gap, 1e-3) << nameOf(method);
      const double touch = 0.2 + 0.25 * std::sqrt(2.0);
      EXPECT_NEAR(centre.x(), touch, 1e-3) << nameOf(method);
      EXPECT_NEAR(centre.y(), touch, 1e-3) << nameOf(method);
    }
  }
}

// ------------------------------------------------------------------------------------------------
// Situation: a model in millimetres (scale 0.001 in the scene). The pole of the first case authored
// in millimetres (radius 25, height 3000) stands beside the same pole in metres. Exact answers: the
// instance's outer AABB is the brute-force bounds of its transformed vertices (rounded outward only)
// and its inner OBB holds every one of them; the engine's triangle distance from boxes around it
// equals FCL's on the transformed triangles; both mesh methods stop within 1 mm of it.
TEST(HardCase, MillimetreModelUnits) {
  ScratchFolder dir;
  const FlatSite site{{0.0, 64.0}};
  writeModel(*toGeode(cylinderMesh(25.0, 3000.0, 24)), dir / "pole_mm.osgt");
  writeModel(*toGeode(cylinderMesh(0.025, 3.0, 24)), dir / "pole_m.osgt");
  const Eigen::Vector2d mm = site.map(-3, 5), m = site.map(3, 5);
  SceneRig rig(writeSceneFile(dir.path(), site.writeTerrain(dir.path()), site.origin(),
                              Json::array({equipment("mm", dir / "pole_mm.osgt", mm.x(), mm.y(), 0, 0, 0.001),
                                           equipment("m", dir / "pole_m.osgt", m.x(), m.y())})));
  const Mesh poleMm = transformed(readBack(dir / "pole_mm.osgt"), instanceToLocal(0, 0, 0, 0.001, V3(-3, 5, 0)));
  const Mesh poleM = transformed(readBack(dir / "pole_m.osgt"), instanceToLocal(0, 0, 0, 1, V3(3, 5, 0)));
  const NestedVolume<double>& v = rig.scene().units[0].volume;
  Aabb<double> bounds;
  for (const V3& p : poleMm.vertices) {
    bounds.extend(p);
    EXPECT_TRUE(insideBox(v.inner, p, 1e-9)) << "inner OBB misses " << p.transpose();
  }
  EXPECT_LT((v.outer.min - bounds.min).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((v.outer.max - bounds.max).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_TRUE((v.outer.min.array() <= bounds.min.array()).all() && (v.outer.max.array() >= bounds.max.array()).all());
  // The same pole in metres, 6 m east: the same box to the float rounding of the two files (1e-8 m).
  const NestedVolume<double>& vm = rig.scene().units[1].volume;
  EXPECT_LT((vm.outer.min - V3(6, 0, 0) - v.outer.min).cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_LT((vm.outer.max - V3(6, 0, 0) - v.outer.max).cwiseAbs().maxCoeff(), 1e-8);

  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-1, 1);
  int contacts = 0;
  for (int k = 0; k < 300; ++k) {
    const Obb<double> box{V3(-3 + 0.4 * U(rng), 5 + 0.4 * U(rng), 1.5 + 2.0 * U(rng)),
                          Eigen::AngleAxisd(std::numbers::pi * U(rng), V3(U(rng), U(rng), U(rng)).normalized()).toRotationMatrix(),
                          V3(0.05 + 0.2 * std::abs(U(rng)), 0.05 + 0.2 * std::abs(U(rng)), 0.05 + 0.5 * std::abs(U(rng)))};
    MeshQueryCounters c;
    const double ref = fclBoxMeshDistance(box, poleMm);
    EXPECT_NEAR(rig.meshes().distance(0, box, c), ref, 1e-9) << "box " << k;
    if (ref > 1e-9) {
      EXPECT_FALSE(rig.meshes().overlaps(0, box, c)) << "box " << k;
    }
    if (ref == 0) {
      EXPECT_TRUE(rig.meshes().overlaps(0, box, c)) << "box " << k;
    }
    contacts += ref == 0;
  }
  EXPECT_GT(contacts, 20);
  for (VolumeMethod method : {VolumeMethod::NestedMesh, VolumeMethod::Kdop18})
    for (double speed : {1.4, 50.0}) {
      Walker& w = rig.walker(method);
      const Eigen::Vector2d start = site.map(-3.1, -2);
      ASSERT_EQ(w.place({start.x(), start.y(), 0}, false, 0, false, 2.0), "");
      walkToward(w, site.map(-3.1, 12), speed, 0);
      expectStoppedWithinAMillimetre(w, poleMm, 0, std::string(nameOf(method)) + " into the millimetre pole");
    }
}

// ------------------------------------------------------------------------------------------------
// Situation: a model whose up axis is Y. A slab authored Y-up (x in [-0.1, 0.1], height y in [0, 3],
// z in [-0.5, 0.5]) stood up two ways: by the instance (pitch 90: the model's +y turns to +z, its +z
// to -y) and by a transform in the file (OSG rotation of 90 degrees about x). Either way the slab in
// the local frame is x in [-0.1, 0.1] + tx, y in [-0.5, 0.5] + ty, z in [0, 3] (closed form). Exact
// answers: the outer AABB is that box (to the float rounding of 0.1, 2e-9 m); the engine's triangle
// distances equal FCL's on the transformed triangles; the walker coming from the south stops with
// its front face (feet y + 0.25) within 1 mm short of y = ty - 0.5 for every method (the slab is its
// own OBB).
TEST(HardCase, YUpModel_Pitch90AndModelTransform) {
  ScratchFolder dir;
  const FlatSite site{{0.0, 64.0}};
  const Mesh slab = boxMesh(V3(-0.1, 0, -0.5), V3(0.1, 3, 0.5));
  writeModel(*toGeode(slab), dir / "yup.osgt");
  osg::ref_ptr<osg::MatrixTransform> up = new osg::MatrixTransform(osg::Matrixd::rotate(std::numbers::pi / 2, osg::Vec3d(1, 0, 0)));
  up->addChild(toGeode(slab));
  writeModel(*up, dir / "yup_transform.osgt");
  const Eigen::Vector2d a = site.map(-4, 5), b = site.map(4, 5);
  SceneRig rig(writeSceneFile(dir.path(), site.writeTerrain(dir.path()), site.origin(),
                              Json::array({equipment("pitched", dir / "yup.osgt", a.x(), a.y(), 0, 90),
                                           equipment("transformed", dir / "yup_transform.osgt", b.x(), b.y())})));
  const Mesh slabs[2] = {transformed(readBack(dir / "yup.osgt"), instanceToLocal(0, 90, 0, 1, V3(-4, 5, 0))),
                         transformed(readBack(dir / "yup_transform.osgt"), instanceToLocal(0, 0, 0, 1, V3(4, 5, 0)))};
  const double tx[2] = {-4, 4};
  for (int u = 0; u < 2; ++u) {
    const Aabb<double>& outer = rig.scene().units[std::size_t(u)].volume.outer;
    EXPECT_LT((outer.min - V3(tx[u] - 0.1, 4.5, 0)).cwiseAbs().maxCoeff(), 1e-8) << "unit " << u << " min " << outer.min.transpose();
    EXPECT_LT((outer.max - V3(tx[u] + 0.1, 5.5, 3)).cwiseAbs().maxCoeff(), 1e-8) << "unit " << u << " max " << outer.max.transpose();
    for (const V3& p : slabs[u].vertices) {
      EXPECT_TRUE(insideBox(rig.scene().units[std::size_t(u)].volume.inner, p, 1e-9));
    }
    std::mt19937 rng(11 + u);
    std::uniform_real_distribution<double> U(-1, 1);
    for (int k = 0; k < 100; ++k) {
      const Obb<double> box{V3(tx[u] + 0.6 * U(rng), 5 + 1.0 * U(rng), 1.5 + 2.0 * U(rng)),
                            Eigen::AngleAxisd(std::numbers::pi * U(rng), V3(U(rng), U(rng), U(rng)).normalized()).toRotationMatrix(),
                            V3(0.11 + 0.2 * std::abs(U(rng)), 0.11 + 0.2 * std::abs(U(rng)), 0.11 + 0.3 * std::abs(U(rng)))};
      // (Half extents above the slab's 0.1 m half thickness: no box fits inside the slab, where
      // the surface distance FCL measures would not be the solids'.)
      MeshQueryCounters c;
      const double ref = fclBoxMeshDistance(box, slabs[u]);
      EXPECT_NEAR(rig.meshes().distance(std::uint32_t(u), box, c), ref, 1e-9) << "unit " << u << " box " << k;
    }
    for (VolumeMethod method : {VolumeMethod::Nested, VolumeMethod::NestedMesh, VolumeMethod::Kdop18}) {
      Walker& w = rig.walker(method);
      const Eigen::Vector2d start = site.map(tx[u] + 0.05, 0);
      ASSERT_EQ(w.place({start.x(), start.y(), 0}, false, 0, false, 2.0), "");
      walkToward(w, site.map(tx[u] + 0.05, 10), 5.0, 0);
      const std::string what = std::string(nameOf(method)) + (u == 0 ? " (pitch 90)" : " (file transform)");
      expectStoppedWithinAMillimetre(w, slabs[u], u, what);
      const double front = w.state().feet.y() - site.origin().y() + 0.25;
      EXPECT_LT(front, 4.5) << what;
      EXPECT_GE(front, 4.5 - 1e-3) << what;
    }
  }
}

// ------------------------------------------------------------------------------------------------
// Situation: UTM magnitudes vs the origin, with the exact methods. The pole and the L above on a
// site whose corner is at (550000, 4650064), loaded as it is and moved to the map's origin
// (SceneLoadOptions::mapShift). The same walks in both frames must stop at the same place (map
// positions equal after the shift, to 1e-6 m: the UTM feet round to 1e-9 m per step) and within
// 1 mm of the triangles (FCL, local frame).
TEST(HardCase, UtmVsOrigin_MeshWalker) {
  ScratchFolder dir;
  const FlatSite site{{550000.0, 4650064.0}};
  writeModel(*toGeode(cylinderMesh(0.025, 3.0, 24)), dir / "pole.osgt");
  Mesh l = boxMesh(V3(0, 0, 0), V3(4, 0.2, 2));
  l.append(boxMesh(V3(0, 0, 0), V3(0.2, 4, 2)));
  writeModel(*toGeode(l), dir / "ell.osgt");
  const Eigen::Vector2d p = site.map(0, 5), e = site.map(-10, -10);
  const fs::path file = writeSceneFile(dir.path(), site.writeTerrain(dir.path()), site.origin(),
                                       Json::array({equipment("pole", dir / "pole.osgt", p.x(), p.y()),
                                                    equipment("ell", dir / "ell.osgt", e.x(), e.y(), 30)}));
  const V3 shift(-550000.0, -4650000.0, 0.0);
  SceneLoadOptions moved;
  moved.mapShift = shift;
  SceneRig utm(file), origin(file, moved);
  ASSERT_EQ(utm.scene().origin + shift, origin.scene().origin);
  const Mesh pole = transformed(readBack(dir / "pole.osgt"), instanceToLocal(0, 0, 0, 1, V3(0, 5, 0)));
  const Mesh ell = transformed(readBack(dir / "ell.osgt"), instanceToLocal(30, 0, 0, 1, V3(-10, -10, 0)));
  struct Walk {
    Eigen::Vector2d from, to;  // local
    double heading, speed;
    const Mesh* target;
    int unit;
  };
  const Walk walks[] = {{{0.1, -3}, {0.1, 12}, 0, 27.0, &pole, 0}, {{-4, -4}, {-12, -12}, 225, 1.4, &ell, 1}};
  for (VolumeMethod method : {VolumeMethod::NestedMesh, VolumeMethod::Kdop18})
    for (const Walk& k : walks) {
      Walker& a = utm.walker(method);
      Walker& b = origin.walker(method);
      const Eigen::Vector2d fa = site.map(k.from.x(), k.from.y()), ta = site.map(k.to.x(), k.to.y());
      const Eigen::Vector2d fb = fa + shift.head<2>(), tb = ta + shift.head<2>();
      ASSERT_EQ(a.place({fa.x(), fa.y(), 0}, false, k.heading, false, 2.0), "");
      ASSERT_EQ(b.place({fb.x(), fb.y(), 0}, false, k.heading, false, 2.0), "");
      walkToward(a, ta, k.speed, k.heading);
      walkToward(b, tb, k.speed, k.heading);
      const std::string what = std::string(nameOf(method)) + " toward unit " + std::to_string(k.unit);
      EXPECT_LE((a.state().feet + shift - b.state().feet).norm(), 1e-6) << what;
      expectStoppedWithinAMillimetre(a, *k.target, k.unit, what + " at UTM");
      expectStoppedWithinAMillimetre(b, *k.target, k.unit, what + " at the origin");
    }
}

}  // namespace
}  // namespace nestwalk
