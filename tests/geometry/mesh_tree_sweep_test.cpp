// MeshTree::sweep (mesh_tree.h): the first contact of a translating box with a mesh, through the
// 18-DOP tree, against (1) the brute-force loop over every triangle with the same
// per-triangle test (the trees may only prune: the same contact verdict, and a t no later than
// brute force's and earlier by at most the tie, meshSweepTieDistance) and (2) an
// independent reference that knows only distances (triangle_box.h): conservative advancement on
// bruteForceDistance, which can never pass a contact, finds none where the sweep finds none; at
// the sweep's t the box touches the mesh, and a moment before it does not.
// Meshes: those of the tree tests (test_meshes.h), UTM magnitudes included; boxes rotated and
// axis-aligned; motions aimed at the mesh; starts inside the step (tStart > 0) too.
#include "nestwalk/geometry/mesh_tree.h"
#include "nestwalk/geometry/triangle_sweep.h"

#include "tests/geometry/test_meshes.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>

namespace nestwalk {
namespace {

using V3 = Vec3<double>;
using namespace testmeshes;

/// The tree's t against brute force's: never later, earlier by at most the tie (mesh_tree.h).
void expectWithinTie(const MeshSweepHit& hit, const MeshSweepHit& reference, double reach, const Obb<double>& box,
                     const V3& d, const std::string& where) {
  ASSERT_EQ(hit.contact, reference.contact) << where;
  EXPECT_LE(hit.t, reference.t) << where;
  EXPECT_GE(hit.t, reference.t - meshSweepTieDistance(box, d, reach) / d.norm()) << where;
}

/// Conservative advancement on exact distances from tStart: the first t where the distance falls
/// to `touch` (nullopt if the step ends first, NaN when it runs out of iterations: grazing).
std::optional<double> advance(const TriangleMesh& mesh, const Obb<double>& box, const V3& d, double tStart, double touch) {
  const double length = d.norm();
  double t = tStart;
  for (int i = 0; i < 20000; ++i) {
    Obb<double> b = box;
    b.center += t * d;
    const double dist = bruteForceDistance(mesh, b);
    if (dist <= touch) return t;
    if (length == 0.0) return std::nullopt;
    t += dist / length;
    if (t > 1.0) return std::nullopt;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

template <class Tree>
void checkSweeps(const char* treeName) {
  unsigned seed = 40;
  for (const NamedMesh& m : testMeshes()) {
    if (std::string(m.name) == "exponential") continue;  // coordinates up to 1e12 m: distances meaningless
    const Tree tree(m.mesh);
    BoxMaker maker = boxesAround(m.mesh, ++seed);
    std::uniform_real_distribution<double> u(0, 1);
    const Aabb<double> bounds = boundsOf(m.mesh);
    int contacts = 0, cases = 400;
    MeshQueryCounters counters;
    for (int n = 0; n < cases; ++n) {
      const Obb<double> box = maker.random();
      // Aim at a point of the mesh's bounds, overshooting by up to a half.
      const V3 target = bounds.isEmpty() ? V3::Zero()
                                         : V3(bounds.min + (bounds.max - bounds.min).cwiseProduct(
                                                               V3(u(maker.rng), u(maker.rng), u(maker.rng))));
      const V3 d = (target - box.center) * (1.0 + 0.5 * u(maker.rng));
      const double tStart = n % 4 == 0 ? 0.3 * u(maker.rng) : 0.0;
      const MeshSweepHit reference = bruteForceSweep(m.mesh, box, d, tStart);
      const MeshSweepHit hit = tree.sweep(box, d, tStart, &counters);
      ASSERT_EQ(hit.contact, reference.contact) << m.name << " case " << n;
      const double magnitude = box.center.cwiseAbs().maxCoeff() + d.cwiseAbs().maxCoeff() + 1.0;
      if (!hit.contact) {
        // Independent: advancement on distances, which never passes a contact, finds none either
        // (or runs out of iterations grazing the surface).
        const std::optional<double> stop = advance(m.mesh, box, d, tStart, 1e-12 * magnitude);
        EXPECT_TRUE(!stop || std::isnan(*stop)) << m.name << " case " << n << ": contact at t = " << *stop;
        if (tStart == 0.0) {
          EXPECT_EQ(tree.freeUntil(box, d), std::numeric_limits<double>::infinity()) << m.name << " case " << n;
        }
        continue;
      }
      ++contacts;
      expectWithinTie(hit, reference, tree.reach(), box, d, std::string(m.name) + " case " + std::to_string(n));
      if (tStart == 0.0) {  // freeUntil: never past the first contact
        EXPECT_LE(tree.freeUntil(box, d), reference.t) << m.name << " case " << n;
      }
      EXPECT_GE(hit.t, tStart);
      // Independent: at t the box touches the mesh (distance within the sweep's slack: not early)
      // and a moment before it does not (not late).
      Obb<double> at = box;
      at.center += hit.t * d;
      EXPECT_LE(bruteForceDistance(m.mesh, at), 1e-10 * magnitude + meshSweepTieDistance(box, d, tree.reach()))
          << m.name << " case " << n;
      const double before = hit.t - 1e-9;
      if (before > tStart) {
        at.center = box.center + before * d;
        EXPECT_GT(bruteForceDistance(m.mesh, at), 0.0) << m.name << " case " << n;
      }
    }
    std::printf("[%s] %-20s %d of %d sweeps touch, as brute force; %.1f BV and %.1f triangle tests per sweep "
                "(%zu triangles)\n",
                treeName, m.name, contacts, cases, double(counters.nodeTests) / cases,
                double(counters.triangleTests) / cases, m.mesh.triangles.size());
    if (!m.mesh.triangles.empty()) {
      EXPECT_GT(contacts, cases / 10) << m.name;
    }
  }
}

TEST(MeshTreeSweep, KdopTreeSweepsAsBruteForceAndDistances) { checkSweeps<KdopTree>("kdop18"); }

TEST(MeshTreeSweep, AThinPoleIsNeverJumpedOver) {
  // A 5 cm pole met by a 1 m box at 50 m/s in one 60 Hz step (0.83 m): the contact is found.
  const TriangleMesh mesh = pole();
  const KdopTree tree(mesh);
  Obb<double> box;
  box.halfExtents = V3(0.2, 0.2, 0.5);
  box.center = V3(-0.6, 0.0, 1.0);
  const V3 d(50.0 / 60.0 * 1.5, 0.0, 0.0);
  const MeshSweepHit hit = tree.sweep(box, d);
  ASSERT_TRUE(hit.contact);
  expectWithinTie(hit, bruteForceSweep(mesh, box, d), tree.reach(), box, d, "pole");
  EXPECT_LT(hit.normal.x(), 0.0);  // pushing back against the motion
}

TEST(MeshTreeSweep, AMotionThroughThousandsOfLooseNodesAnswersAsBruteForce) {
  // 20000 slivers 4.5 m long, each across the x axis's line of sight in its own direction in the
  // y-z plane, passing 5 cm from the axis at its own x (0 to 0.8 m) and shifted along itself by up
  // to 0.9 m: every sliver's 18-DOP holds the axis near its x, and so does a node's slab along its
  // slivers' mean normal (their directions differ), so a small box moving along the axis enters
  // every leaf without touching a triangle. The slivers' centres spread far more in y and z than
  // in x, so the leaves' entry times come in no order the tree knows: the best-first frontier
  // (kFrontierCapacity entries) overflows, and the nodes it cannot queue are searched depth
  // first. No contact, as brute force; then one more triangle across the axis is found at brute
  // force's t.
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> x(0, 0.8), shift(-0.9, 0.9), angle(0, 3.14159);
  TriangleMesh mesh;
  for (int i = 0; i < 20000; ++i) {
    const double phi = angle(rng);
    const V3 along(0, std::cos(phi), std::sin(phi)), across(0, -std::sin(phi), std::cos(phi));
    const V3 mid = V3(x(rng), 0, 0) + 0.05 * across + shift(rng) * along;
    const std::uint32_t first = std::uint32_t(mesh.vertices.size());
    mesh.vertices.push_back(mid - std::sqrt(5.0) * along);
    mesh.vertices.push_back(mid + std::sqrt(5.0) * along);
    mesh.vertices.push_back(mid + std::sqrt(5.0) * along + V3(1e-4, 0, 0));
    mesh.triangles.push_back({first, first + 1, first + 2});
  }
  const Obb<double> box{V3(-0.02, 0, 0), Mat3<double>::Identity(), V3::Constant(0.01)};
  const V3 d(0.84, 0, 0);
  {
    const KdopTree tree(mesh);
    MeshQueryCounters c;
    const MeshSweepHit hit = tree.sweep(box, d, 0.0, &c);
    EXPECT_FALSE(hit.contact);
    EXPECT_FALSE(bruteForceSweep(mesh, box, d).contact);
    EXPECT_GT(c.triangleTests, 10000u) << "the motion should open most leaves";
    std::printf("[loose nodes] %zu triangles: %llu node tests, %llu triangle tests, no contact\n", mesh.triangles.size(),
                (unsigned long long)c.nodeTests, (unsigned long long)c.triangleTests);
  }
  const std::uint32_t first = std::uint32_t(mesh.vertices.size());
  mesh.vertices.push_back(V3(0.6, -1, -1));
  mesh.vertices.push_back(V3(0.6, 1, -1));
  mesh.vertices.push_back(V3(0.6, 0, 1));
  mesh.triangles.push_back({first, first + 1, first + 2});
  const KdopTree tree(mesh);
  const MeshSweepHit hit = tree.sweep(box, d);
  const MeshSweepHit brute = bruteForceSweep(mesh, box, d);
  ASSERT_TRUE(hit.contact);
  expectWithinTie(hit, brute, tree.reach(), box, d, "the triangle across the axis");
  // Early by the slabs' slack (about 1e-12 of the magnitudes) and at most the tie (8 nm here).
  EXPECT_NEAR(hit.t, (0.6 + 0.01) / 0.84, 1e-10 + meshSweepTieDistance(box, d, tree.reach()) / d.norm());
}

TEST(MeshTreeSweep, ADenseFlatFaceIsOneContact) {
  // A 1 m x 1 m wall in the plane y = 0 cut into 1 cm squares (20,000 triangles), the body box
  // pressed on it 0.5 mm off and stepping on turned 20 degrees into it: every triangle under the
  // box's face is reached at the same time up to rounding. Brute force tests them all; the tree
  // keeps the first it finds and passes over every node of the flat patch entered no earlier
  // than that less the tie (its normal slab is tight on a flat patch).
  TriangleMesh mesh;
  const int n = 100;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) mesh.vertices.push_back(V3(0.01 * i, 0, 0.01 * j));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const auto at = [&](int a, int b) { return std::uint32_t(a * (n + 1) + b); };
      mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  const KdopTree tree(mesh);
  const Obb<double> box{V3(0.5, -0.25 - 0.5e-3, 0.5), Mat3<double>::Identity(), V3(0.25, 0.25, 0.4)};
  const V3 d = V3(std::sin(0.35), std::cos(0.35), 0) * (1.4 / 60);
  int reached = 0;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const SweepResult r = sweepBoxTriangle(box, d, mesh.triangle(i), 0.0, 1.0);
    reached += r.enter <= r.exit && r.enter <= 1.0 && r.exit >= 0.0;
  }
  MeshQueryCounters c;
  const MeshSweepHit hit = tree.sweep(box, d, 0.0, &c);
  expectWithinTie(hit, bruteForceSweep(mesh, box, d), tree.reach(), box, d, "dense wall");
  // It moves 0.5 mm toward the wall, less at most the tie (a few nm here).
  EXPECT_LE(hit.t * d.y(), 0.5e-3 + 1e-12);
  EXPECT_GE(hit.t * d.y(), 0.5e-3 - meshSweepTieDistance(box, d, tree.reach()));
  EXPECT_GT(reached, 4000) << "the box's face covers 50 x 80 squares";
  EXPECT_LE(c.triangleTests, 16u);
  EXPECT_LE(c.nodeTests, 64u);
  std::printf("[dense wall] %d triangles reached in the step; the tree tested %llu triangles and %llu nodes\n", reached,
              (unsigned long long)c.triangleTests, (unsigned long long)c.nodeTests);
}

}  // namespace
}  // namespace nestwalk
