// CoherentSweep (coherent_sweep.h): a mover's steps answered from a remembered free path must be
// MeshTree::sweep's answers to the bit, and MeshTree::sweep's are the brute-force loop's (every
// triangle tested, bruteForceSweep), which this test checks on every step answered from memory.
// Walks: straight approaches that end in contact, walks that turn a little every step or
// teleport, steps that start inside the step (tStart > 0), a box that changes size, on the tree
// tests' meshes (test_meshes.h: UTM magnitudes, a thin pole, degenerate triangles, an empty mesh).
#include "nestwalk/geometry/coherent_sweep.h"

#include "tests/geometry/test_meshes.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <utility>
#include <string>

namespace nestwalk {
namespace {

using V3 = Vec3<double>;
using namespace testmeshes;

void expectSameHit(const MeshSweepHit& got, const MeshSweepHit& want, const std::string& where) {
  ASSERT_EQ(got.contact, want.contact) << where;
  EXPECT_EQ(got.t, want.t) << where;
  EXPECT_EQ(got.normal, want.normal) << where;
}

struct WalkSummary {
  int steps = 0, contacts = 0;
  std::uint64_t remembered = 0;  // steps answered from a free path
};

/// Walks `walks` movers through the mesh, each step swept both ways; returns the steps and contacts.
WalkSummary walk(const NamedMesh& m, unsigned seed, int walks, double turnPerStep, bool teleports) {
  const KdopTree tree(m.mesh);
  BoxMaker maker = boxesAround(m.mesh, seed);
  std::uniform_real_distribution<double> u(0, 1);
  const Aabb<double> bounds = boundsOf(m.mesh);
  CoherentSweep mover;
  WalkSummary summary;
  for (int w = 0; w < walks; ++w) {
    Obb<double> box = maker.random();
    const V3 target = bounds.isEmpty() ? V3::Zero()
                                       : V3(bounds.min + (bounds.max - bounds.min).cwiseProduct(
                                                             V3(u(maker.rng), u(maker.rng), u(maker.rng))));
    V3 d = (target - box.center) / 40.0;  // about 40 steps to the target
    if (d.isZero()) d = V3(1e-3, 0, 0);
    for (int step = 0; step < 80; ++step) {
      const double tStart = step % 7 == 3 ? 0.5 * u(maker.rng) : 0.0;
      const MeshSweepHit want = tree.sweep(box, d, tStart);
      const std::uint64_t rememberedBefore = mover.counters().remembered;
      const MeshSweepHit got = mover.sweep(tree, box, d, tStart);
      const std::string where = std::string(m.name) + " walk " + std::to_string(w) + " step " + std::to_string(step);
      expectSameHit(got, want, where);
      if (mover.counters().remembered > rememberedBefore)  // answered from memory: the brute force agrees
        expectSameHit(got, bruteForceSweep(m.mesh, box, d, tStart), where + " (brute force)");
      ++summary.steps;
      if (want.contact) {
        ++summary.contacts;
        // Held at the contact, turned away a little: the next steps start there.
        box.center += want.t * d;
        d = Eigen::AngleAxisd(0.3, V3::UnitZ()) * d;
        continue;
      }
      box.center += d;
      if (turnPerStep != 0) {
        const Mat3<double> turn = Eigen::AngleAxisd(turnPerStep, V3::UnitZ()).toRotationMatrix();
        d = turn * d;
        box.axes = turn * box.axes;
      }
      if (teleports && step % 13 == 12) box.center += 3 * d.norm() * V3(u(maker.rng), u(maker.rng), u(maker.rng));
      if (step == 50) box.halfExtents *= 0.9;  // a new body: the free path is not its
    }
  }
  summary.remembered = mover.counters().remembered;
  return summary;
}

TEST(CoherentSweep, StraightWalksGiveTheTreesAnswers) {
  unsigned seed = 70;
  for (const NamedMesh& m : testMeshes()) {
    const WalkSummary s = walk(m, ++seed, 30, 0.0, false);
    if (!m.mesh.triangles.empty() && std::string(m.name) != "exponential") {
      EXPECT_GT(s.contacts, 0) << m.name;
    }
  }
}

TEST(CoherentSweep, TurningAndTeleportingWalksGiveTheTreesAnswers) {
  unsigned seed = 90;
  for (const NamedMesh& m : testMeshes()) {
    walk(m, ++seed, 20, 0.02, true);
    // Turning by a hair: the free path still holds most steps.
    const WalkSummary hair = walk(m, ++seed, 20, 1e-9, false);
    EXPECT_GT(hair.remembered, 0u) << m.name << ": no step answered from memory while turning by 1e-9 rad";
  }
}

TEST(CoherentSweep, StepsInFreeSpaceAreAnsweredFromMemory) {
  // A box walking straight at an icosphere from 4 radii away, 1 cm steps: all but the last few
  // steps before the contact lie in free paths.
  const TriangleMesh sphere = icosphere(3, 1.0);
  const KdopTree tree(sphere);
  CoherentSweep mover;
  Obb<double> box{V3(-5, 0.1, 0.2), Mat3<double>::Identity(), V3(0.25, 0.25, 0.9)};
  const V3 d(0.01, 0, 0);
  int steps = 0;
  for (; steps < 1000; ++steps) {
    const MeshSweepHit hit = mover.sweep(tree, box, d);
    ASSERT_EQ(hit.contact, tree.sweep(box, d).contact);
    if (hit.contact) break;
    box.center += d;
  }
  // The box's face reaches the sphere after (5 - 1 - 0.25) / 0.01 = 375 steps.
  EXPECT_NEAR(steps, 375, 2);
  const CoherentSweepCounters& c = mover.counters();
  EXPECT_GT(c.remembered, std::uint64_t(0.9 * steps)) << c.lookAheads << " look-aheads, " << c.exact << " exact";
  // Every step not remembered was swept: a look-ahead, an exact sweep or both.
  EXPECT_GE(c.lookAheads + c.exact, std::uint64_t(steps + 1) - c.remembered);
}

TEST(CoherentSweep, ADifferentTreeForgetsTheFreePath) {
  // A far sphere leaves the box a free path (the first step's look-ahead: 4 steps from its end);
  // a wall (two triangles in the plane x = -4.715) stands across the third step after it, which
  // the far tree's free path covers.
  const TriangleMesh far = icosphere(1, 1.0);
  const TriangleMesh wall{{V3(-4.715, -1, -1), V3(-4.715, 1, -1), V3(-4.715, 1, 1), V3(-4.715, -1, 1)},
                          {{0, 1, 2}, {0, 2, 3}}};
  const KdopTree farTree(far), wallTree(wall);
  CoherentSweep mover;
  Obb<double> box{V3(-5, 0, 0), Mat3<double>::Identity(), V3(0.25, 0.25, 0.25)};
  const V3 d(0.01, 0, 0);
  for (int i = 0; i < 3; ++i, box.center += d) EXPECT_FALSE(mover.sweep(farTree, box, d).contact);
  // The box's face is at x = -4.72: the next step takes it to -4.71, through the wall.
  ASSERT_TRUE(mover.covers(box, d, 0.0)) << "the next step should lie in the far tree's free path";
  ASSERT_FALSE(farTree.sweep(box, d).contact);
  const MeshSweepHit want = wallTree.sweep(box, d);
  ASSERT_TRUE(want.contact);
  const std::uint64_t rememberedBefore = mover.counters().remembered;
  expectSameHit(mover.sweep(wallTree, box, d), want, "the wall's step");
  EXPECT_EQ(mover.counters().remembered, rememberedBefore) << "answered from the far tree's free path";
  EXPECT_FALSE(mover.covers(box, d, 0.0)) << "the wall's contact left no free path";
}

TEST(CoherentSweep, NonFiniteStepsGoToTheTree) {
  const TriangleMesh sphere = icosphere(2, 1.0);
  const KdopTree tree(sphere);
  CoherentSweep mover;
  Obb<double> box{V3(-5, 0, 0), Mat3<double>::Identity(), V3(0.25, 0.25, 0.25)};
  const V3 d(0.01, 0, 0);
  for (int i = 0; i < 10; ++i, box.center += d) mover.sweep(tree, box, d);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const V3& odd : {V3(nan, 0, 0), V3(inf, 0, 0), V3(0, -inf, 0)}) {
    EXPECT_FALSE(mover.covers(box, odd, 0.0));
    Obb<double> oddBox = box;
    oddBox.center += odd;
    EXPECT_FALSE(mover.covers(oddBox, d, 0.0));
    // The tree's own answer (or its error) either way.
    for (const auto& [b, step] : {std::pair{box, odd}, std::pair{oddBox, d}}) {
      bool treeThrew = false, moverThrew = false;
      MeshSweepHit want, got;
      try { want = tree.sweep(b, step); } catch (const std::exception&) { treeThrew = true; }
      try { got = mover.sweep(tree, b, step); } catch (const std::exception&) { moverThrew = true; }
      ASSERT_EQ(moverThrew, treeThrew);
      if (!treeThrew) {
        EXPECT_EQ(got.contact, want.contact);
        if (!std::isnan(want.t)) {
          EXPECT_EQ(got.t, want.t);
        }
      }
    }
  }
  // The next finite step is answered as the tree answers it, with no free path left over.
  EXPECT_FALSE(mover.covers(box, d, 0.0));
  expectSameHit(mover.sweep(tree, box, d), tree.sweep(box, d), "after the odd steps");
}

}  // namespace
}  // namespace nestwalk
