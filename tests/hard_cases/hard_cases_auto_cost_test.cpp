// Auto on cost (walker/exact_stage_cost.h): a unit whose inner OBB is not tight gets the exact
// mesh stage only where its sample sweeps stay within kMaxExactStageTests tests.
// Situations, on a level site: an L of two plain walls (24 triangles) and the same L with each
// wall tessellated into 1 cm squares with 2 mm of relief (78,024 triangles, a scanned surface's
// density). Both Ls have the same loose inner OBB (the L's corner leaves a quarter of the box
// empty: checked, the gap verdict is not tight).
// Asserted: both Ls are sampled by the same sweeps, and both get the exact stage: the dense L's
// sample sweeps stay far within the limit. A step pressing on the dense wall reaches ten thousand
// triangles at nearly the same time (counted by brute force over every triangle); the tree tests
// a hundred at most (its nodes' normal slabs are tight on the relief's patches, and contacts
// within mesh_tree.h's tie are one). Walking into the dense L's empty quarter, auto and
// nested+mesh both stop at the real wall, within 1 mm. (Until 2026-11-28 the tree tested every
// triangle under a pressed face, 10,206 here, and auto left the dense L to the nested test.)
#include "tests/hard_cases/hard_case_util.h"

#include "nestwalk/geometry/triangle_sweep.h"
#include "nestwalk/walker/exact_stage_cost.h"

#include <cstdio>

namespace nestwalk {
namespace {

using namespace nestwalk::hardcase;

constexpr double kRelief = 2e-3;  // metres: the dense walls' relief (a scanned surface's)

/// A wall [x0, x1] x [y0, y1] x [0, h], its two large faces tessellated into `cell`-metre squares
/// (and its four narrow faces as two triangles each), each corner of the squares pushed into the
/// wall by up to `rough` metres (a fixed pseudo-random depth per corner, shared by the squares
/// that meet there): the relief of a scanned surface, whose triangles are no longer coplanar.
Mesh wall(const V3& lo, const V3& hi, double cell, double rough) {
  Mesh m = boxMesh(lo, hi);
  if (cell <= 0) return m;
  // The tessellated squares lie in the planes of the box's two largest faces, over its own two
  // triangles there: the surface is the same, only cut finer.
  const bool alongX = hi.x() - lo.x() >= hi.y() - lo.y();
  const double length = alongX ? hi.x() - lo.x() : hi.y() - lo.y();
  const int nu = int(std::lround(length / cell)), nv = int(std::lround((hi.z() - lo.z()) / cell));
  for (const double side : {alongX ? lo.y() : lo.x(), alongX ? hi.y() : hi.x()})
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) {
        auto at = [&](int a, int b) {
          const double u = (alongX ? lo.x() : lo.y()) + cell * a, z = lo.z() + cell * b;
          const double hash = std::sin(12.9898 * a + 78.233 * b) * 43758.5453;
          const double inward = (side == (alongX ? lo.y() : lo.x()) ? 1 : -1) * rough * (hash - std::floor(hash));
          return alongX ? V3(u, side + inward, z) : V3(side + inward, u, z);
        };
        const auto first = std::uint32_t(m.vertices.size());
        for (const auto& [a, b] : {std::pair{i, j}, std::pair{i + 1, j}, std::pair{i + 1, j + 1}, std::pair{i, j + 1}})
          m.vertices.push_back(at(a, b));
        m.triangles.push_back({first, first + 1, first + 2});
        m.triangles.push_back({first, first + 2, first + 3});
      }
  return m;
}

/// An L of two walls 1 m long, 5 cm thick, 1 m tall, meeting at the origin.
Mesh ell(double cell, double rough) {
  Mesh m = wall(V3(0, 0, 0), V3(1, 0.05, 1), cell, rough);
  m.append(wall(V3(0, 0.05, 0), V3(0.05, 1, 1), cell, rough));
  return m;
}

TEST(HardCase, AutoKeepsTheExactStageOnADenseWallWhoseSweepsStayCheap) {
  ScratchFolder dir;
  const FlatSite site{{0.0, 64.0}};
  writeModel(*toGeode(ell(0, 0)), dir / "plain.osgt");
  writeModel(*toGeode(ell(0.01, kRelief)), dir / "dense.osgt");
  const Eigen::Vector2d plainAt = site.map(-8, 0), denseAt = site.map(8, 0);
  SceneRig rig(writeSceneFile(dir.path(), site.writeTerrain(dir.path()), site.origin(),
                              Json::array({equipment("plain", dir / "plain.osgt", plainAt.x(), plainAt.y()),
                                           equipment("dense", dir / "dense.osgt", denseAt.x(), denseAt.y())})));
  ASSERT_EQ(rig.meshes().triangles(1), 24u + 2u * 2u * (100u + 95u) * 100u);  // walls 1 m and 0.95 m long

  MethodSpec spec = rig.scene().spec.method;
  spec.volumes = VolumeMethod::Auto;
  const CollisionWorld world = CollisionWorld::fromScene(rig.scene(), spec, MeshWorld::fromScene(rig.scene()));
  for (std::size_t u = 0; u < 2; ++u) {
    const GapVerdict& gap = world.contactChoices()[u];
    const ExactStageCost& cost = world.exactStageCosts()[u];
    std::printf("[auto cost] %-5s %zu triangles: OBB gap at least %.0f mm, %d sample sweeps, at most %llu tests\n",
                u == 0 ? "plain" : "dense", rig.meshes().triangles(u), 1000 * gap.lowerBound, cost.sweeps,
                (unsigned long long)cost.maxTests);
    EXPECT_FALSE(gap.tight) << "unit " << u << ": the L's corner leaves its box a quarter empty";
  }
  // The same L from the same sides: the same sample sweeps (two where an approach meets the L:
  // those aimed into its empty quarter pass its walls).
  EXPECT_EQ(world.exactStageCosts()[0].sweeps, world.exactStageCosts()[1].sweeps);
  EXPECT_GE(world.exactStageCosts()[0].sweeps, kCostSampleSides);
  EXPECT_TRUE(world.exactStage(0));
  EXPECT_LE(world.exactStageCosts()[0].maxTests, 200u);
  EXPECT_TRUE(world.exactStage(1));
  EXPECT_LE(world.exactStageCosts()[1].maxTests, 200u);

  // The body pressed flat against the outer face (y = 0) of the dense L's wall along x, from -y,
  // 0.5 mm off, stepping on turned 20 degrees: every triangle of the face under the body is
  // reached at the same time up to rounding (they are counted here by brute force over every
  // triangle). The tree finds one and passes over the flat patch's other nodes (the tie).
  const Scene& scene = rig.scene();
  const V3 body = scene.spec.viewer.bodyHalfExtents;
  const V3 origin = scene.units[1].volume.outer.min;  // the L's corner, local frame
  const Obb<double> pressed{V3(origin.x() + 0.5, origin.y() - body.y() - 0.5e-3, origin.z() + body.z()),
                            Mat3<double>::Identity(), body};
  const V3 step = V3(std::sin(0.35), std::cos(0.35), 0) * kCostSampleStep;
  const Mesh dense = transformed(readBack(dir / "dense.osgt"), instanceToLocal(0, 0, 0, 1, scene.instances[1].toLocal.translation));
  std::size_t reached = 0;
  for (std::size_t i = 0; i < dense.triangles.size(); ++i) {
    const auto c = dense.corners(i);
    const SweepResult r = sweepBoxTriangle(pressed, step, Triangle{c[0], c[1], c[2]}, 0.0, 1.0);
    reached += r.enter <= r.exit && r.enter <= 1.0 && r.exit >= 0.0;
  }
  MeshQueryCounters c;
  ASSERT_TRUE(rig.meshes().firstContact(1, pressed, step, 0.0, c).has_value());
  std::printf("[auto cost] pressing on the dense wall: %zu triangles reached in the step (brute force), %llu tests\n", reached,
              (unsigned long long)(c.nodeTests + c.triangleTests));
  EXPECT_GT(reached, kMaxExactStageTests);
  EXPECT_LE(c.nodeTests + c.triangleTests, 100u);

  // Walking south into the dense L's empty quarter: auto and nested+mesh both stop at the wall
  // along x (y = 0.05), not on the L's box.
  for (VolumeMethod method : {VolumeMethod::Auto, VolumeMethod::NestedMesh}) {
    Walker& w = rig.walker(method);
    const Eigen::Vector2d start = site.map(8.6, 4);
    ASSERT_EQ(w.place({start.x(), start.y(), 0}, false, 180, false, 2.0), "");
    walkToward(w, site.map(8.6, -1), 1.4, 180);
    EXPECT_TRUE(w.state().blocked) << volumeMethodName(method);
    const double gap = fclBoxMeshDistance(bodyBox(w), dense);
    std::printf("[auto cost] %-11s stops %.4f m from the dense L's triangles\n", volumeMethodName(method), gap);
    EXPECT_GT(gap, 0.0);
    EXPECT_LE(gap, 1e-3);
  }
}

}  // namespace
}  // namespace nestwalk
