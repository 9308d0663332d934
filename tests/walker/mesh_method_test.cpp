// The exact walker methods on the bundled scene: nested+mesh (nested volumes, then a k-DOP-18 tree
// over the real triangles), kdop18 (the same tree right after the broad phase) and auto (the mesh
// stage only where a unit's inner OBB is not tight). Wherever the bench patrol and the equipment
// walk and flight are blocked, the body stops within a millimetre of the real triangles and never
// touches them (distance by FCL between the body box and the instances' triangles, independent of
// the project's trees); the exact methods block on the same frames by the same units; the nested
// volumes stop the walker earlier, never later, than the real geometry would. Every sweep of every
// method is also compared with the reference that finds contacts by conservative advancement on
// exact distances instead of swept tests (mesh_world.h): the exact methods and auto never miss,
// never stop early, never block falsely.
#include "tests/common/build_paths.h"
#include "nestwalk/report/reference_comparison.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/walker/flythrough.h"
#include "nestwalk/walker/mesh_world.h"
#include "nestwalk/walker/script_file.h"
#include "nestwalk/walker/script_player.h"
#include "nestwalk/walker/walker.h"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/narrowphase/distance.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>

namespace nestwalk {
namespace {

const std::filesystem::path kScene = std::filesystem::path(nestwalk::test::build::bundledSceneDir()) / "scene.json";
const std::filesystem::path kScripts = std::filesystem::path(nestwalk::test::build::bundledSceneDir()) / "scripts";
const char* const kBlockingScripts[] = {"bench_patrol.txt", "equipment_walk.txt", "equipment_fly.txt"};

/// FCL's view of one unit: its instances' triangles in the local frame, one BVH.
std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> fclUnit(const Scene& scene, std::size_t unit) {
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  model->beginModel();
  for (std::uint32_t i : scene.units[unit].instances) {
    const SceneInstance& inst = scene.instances[i];
    const TriangleMesh& mesh = scene.models[inst.model].mesh;
    for (const auto& t : mesh.triangles) {
      fcl::Vector3d p[3];
      for (int k = 0; k < 3; ++k)
        p[k] = inst.toLocal.scale * (inst.toLocal.rotation * mesh.vertices[t[std::size_t(k)]]) + inst.toLocal.translation;
      model->addTriangle(p[0], p[1], p[2]);
    }
  }
  model->endModel();
  return model;
}

double fclDistance(const fcl::BVHModel<fcl::OBBRSSd>& mesh, const Obb<double>& body) {
  const fcl::Boxd box(2 * body.halfExtents.x(), 2 * body.halfExtents.y(), 2 * body.halfExtents.z());
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.linear() = body.axes;
  tf.translation() = body.center;
  fcl::DistanceRequestd request;
  request.enable_nearest_points = false;
  fcl::DistanceResultd result;
  return fcl::distance(&mesh, fcl::Transform3d::Identity(), &box, tf, request, result);
}

struct BlockedStep {
  std::uint64_t frame;
  std::int32_t unit;
  Obb<double> body;
};

std::vector<BlockedStep> blockedSteps(const Scene& scene, const CollisionWorld& world, const Script& script) {
  WalkerOptions options;
  options.viewer = scene.spec.viewer;
  options.timeParts = false;
  Walker walker(*scene.terrain, world, scene.origin, options);
  ScriptPlayer player(script, walker);
  std::vector<BlockedStep> out;
  player.run([&](const Walker& w, const StepReport&) {
    const WalkerState& s = w.state();
    if (s.blocked && s.reason == BlockReason::Equipment)
      out.push_back({s.frame, s.blockedUnit, w.bodyVolume(s.feet, s.bodyYawDeg).inner});
  });
  return out;
}

class MeshMethods : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (std::filesystem::exists(kScene)) {
      scene_ = std::make_unique<Scene>(loadScene(kScene.string()));
      meshes_ = MeshWorld::fromScene(*scene_);
    }
  }
  static void TearDownTestSuite() {
    scene_.reset();
    meshes_.reset();
  }
  void SetUp() override {
    if (!scene_) GTEST_SKIP() << kScene << " is absent: build the bundled_scene target";
  }
  static CollisionWorld world(VolumeMethod m) {
    MethodSpec spec = scene_->spec.method;
    spec.volumes = m;
    return CollisionWorld::fromScene(*scene_, spec, meshes_);
  }
  static std::unique_ptr<Scene> scene_;
  static std::shared_ptr<const MeshWorld> meshes_;
};
std::unique_ptr<Scene> MeshMethods::scene_;
std::shared_ptr<const MeshWorld> MeshMethods::meshes_;

TEST_F(MeshMethods, ExactMethodsStopWithinAMillimetreOfTheRealTriangles) {
  std::map<std::int32_t, std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>>> fclUnits;
  auto gapOf = [&](const BlockedStep& b) {
    auto& model = fclUnits[b.unit];
    if (!model) model = fclUnit(*scene_, std::size_t(b.unit));
    return fclDistance(*model, b.body);
  };
  const VolumeMethod methods[] = {VolumeMethod::NestedMesh, VolumeMethod::Kdop18, VolumeMethod::Auto,
                                  VolumeMethod::Nested};
  for (const char* name : kBlockingScripts) {
    SCOPED_TRACE(name);
    const Script script = readScript((kScripts / name).string());
    std::vector<std::vector<BlockedStep>> runs;
    for (VolumeMethod m : methods) {
      const CollisionWorld w = world(m);
      runs.push_back(blockedSteps(*scene_, w, script));
      ASSERT_FALSE(runs.back().empty()) << volumeMethodName(m) << ": never blocked by equipment";
    }
    for (int k = 0; k < 3; ++k) {
      double worst = 0;
      for (const BlockedStep& b : runs[std::size_t(k)]) {
        const double gap = gapOf(b);
        EXPECT_GT(gap, 0.0) << "frame " << b.frame << ": the body touches the real triangles";
        EXPECT_LE(gap, 1e-3) << "frame " << b.frame << ": stopped " << gap * 1000 << " mm from the real triangles";
        worst = std::max(worst, gap);
      }
      std::printf("%s, %s: %zu blocked frames, largest gap to the real triangles %.3f mm\n", name,
                  volumeMethodName(methods[k]), runs[std::size_t(k)].size(), worst * 1000);
    }
    // The exact methods block on the same frames, by the same units.
    for (int k = 1; k < 3; ++k) {
      ASSERT_EQ(runs[0].size(), runs[std::size_t(k)].size()) << volumeMethodName(methods[k]);
      for (std::size_t i = 0; i < runs[0].size(); ++i) {
        EXPECT_EQ(runs[0][i].frame, runs[std::size_t(k)][i].frame);
        EXPECT_EQ(runs[0][i].unit, runs[std::size_t(k)][i].unit);
        EXPECT_NEAR((runs[0][i].body.center - runs[std::size_t(k)][i].body.center).norm(), 0.0, 1e-3);
      }
    }
    // The nested volumes stop earlier, never in the real triangles (where a unit's inner OBB is its
    // surface, as on a container's face, as close as the exact methods).
    double nestedMin = std::numeric_limits<double>::infinity();
    for (const BlockedStep& b : runs[3]) nestedMin = std::min(nestedMin, gapOf(b));
    std::printf("%s, nested: %zu blocked frames, smallest gap to the real triangles %.1f mm\n", name, runs[3].size(),
                nestedMin * 1000);
    EXPECT_GT(nestedMin, 0.0);
  }
}

TEST_F(MeshMethods, EveryMethodAgainstTheAdvancementReference) {
  // Every sweep of every method compared with the exact method on the same step, found the other
  // way: conservative advancement on exact distances.
  CollisionWorld reference = world(VolumeMethod::NestedMesh);
  reference.setMeshContactSearch(MeshContactSearch::Advancement);
  for (VolumeMethod m : {VolumeMethod::Nested, VolumeMethod::Aabb, VolumeMethod::Obb, VolumeMethod::NestedMesh,
                         VolumeMethod::Kdop18, VolumeMethod::Auto}) {
    CollisionWorld w = world(m);
    ReferenceComparison comparison(reference);
    for (const char* name : kBlockingScripts) {
      // The outer boxes alone cannot land where the walk starts beside a diagonal fence: the
      // method's own verdict (the report shows that play as incomplete).
      if (m == VolumeMethod::Aabb && std::string(name) == "equipment_walk.txt") continue;
      const ObservedSweeps observed(w, comparison);
      WalkerOptions options;
      options.viewer = scene_->spec.viewer;
      options.timeParts = false;
      runFlythrough(*scene_, w, readScript((kScripts / name).string()), options);
    }
    const ReferenceTally& tally = comparison.tally();
    EXPECT_GT(tally.sweeps, 4000u);
    EXPECT_GT(tally.contacts, 0u);
    EXPECT_EQ(tally.missed, 0u) << volumeMethodName(m);
    // Without a miss every reference contact is the method's too; its other contacts are early
    // stops (before real geometry further on) or false blocks.
    EXPECT_GE(tally.contacts, tally.referenceContacts) << volumeMethodName(m);
    EXPECT_LE(tally.contacts, tally.referenceContacts + tally.earlyStops + tally.falseBlocks) << volumeMethodName(m);
    if (m == VolumeMethod::NestedMesh || m == VolumeMethod::Kdop18 || m == VolumeMethod::Auto) {
      EXPECT_EQ(tally.earlyStops + tally.falseBlocks, 0u) << volumeMethodName(m);
    }
    std::printf("%s: %llu sweeps, %llu contacts (exact %llu), %llu missed, %llu early stops, %llu false blocks\n",
                volumeMethodName(m), (unsigned long long)tally.sweeps, (unsigned long long)tally.contacts,
                (unsigned long long)tally.referenceContacts, (unsigned long long)tally.missed,
                (unsigned long long)tally.earlyStops, (unsigned long long)tally.falseBlocks);
  }
}

TEST_F(MeshMethods, SweepMemoryFindsTheSameContactsOnEveryUnit) {
  // The body box walked into every unit with triangles from 8 sides at walking steps (then held
  // at the contact, pressing on turned), each step's first contact found with one mover's
  // SweepMemory and without: the same contacts, times, normals and pressing verdicts.
  MeshWorld::SweepMemory memory = meshes_->sweepMemory();
  const Vec3<double> half = scene_->spec.viewer.bodyHalfExtents;
  std::uint64_t steps = 0;
  for (std::uint32_t u = 0; u < meshes_->units(); ++u) {
    if (meshes_->triangles(u) == 0) continue;
    const Aabb<double>& outer = scene_->units[u].volume.outer;
    const double reach = 0.5 * outer.size().head<2>().norm() + half.head<2>().norm() + 0.5;
    for (int side = 0; side < 8; ++side) {
      const double angle = 2 * std::numbers::pi * side / 8 + 0.2;
      const Vec3<double> toward(-std::cos(angle), -std::sin(angle), 0);
      Obb<double> body{outer.center() - reach * toward, Eigen::AngleAxisd(angle, Vec3<double>::UnitZ()).toRotationMatrix(),
                       half};
      Vec3<double> d = (1.4 / 60) * toward;
      for (int step = 0; step < 400; ++step) {
        MeshQueryCounters c;
        const auto with = meshes_->firstContact(u, body, d, 0.0, c, MeshContactSearch::Swept, &memory);
        const auto without = meshes_->firstContact(u, body, d, 0.0, c);
        ++steps;
        ASSERT_EQ(with.has_value(), without.has_value()) << "unit " << u << " side " << side << " step " << step;
        if (!with) {
          body.center += d;
          continue;
        }
        EXPECT_EQ(with->t, without->t);
        EXPECT_EQ(with->normal, without->normal);
        EXPECT_EQ(with->pressing, without->pressing);
        body.center += std::max(0.0, with->t - 0.02) * d;  // held short of the contact, turning
        d = Eigen::AngleAxisd(0.15, Vec3<double>::UnitZ()) * d;
        if (step > 300) break;
      }
    }
  }
  EXPECT_GT(memory.counters().remembered, steps / 4) << steps << " steps";
  // A memory is for the world that made it.
  const std::shared_ptr<const MeshWorld> other = MeshWorld::fromScene(*scene_);
  MeshQueryCounters c;
  EXPECT_THROW(other->firstContact(0, Obb<double>{}, Vec3<double>(1, 0, 0), 0.0, c, MeshContactSearch::Swept, &memory),
               std::logic_error);
}

TEST_F(MeshMethods, APressedBodyStaysPutAndTestsNoTriangle) {
  // The body walked into every heavy unit (1,000 triangles or more: the drill rig) from 8 sides
  // with nested+mesh, then pressing on in the same direction for 30 frames, as a script's goto
  // does until it gives up: after the contact the body moves at most once more (0 or at least
  // kMinBlockedAdvance, never a creep by roundings), then stays where it is to the last bit,
  // blocked by the same unit, with no triangle tested from its second frame there, and its gap to
  // the real triangles (FCL) stays positive and within kMostStopGap.
  constexpr double kMostStopGap = 1e-3;  // metres: the exact methods stop within a millimetre
  const CollisionWorld w = world(VolumeMethod::NestedMesh);
  WalkerOptions options;
  options.viewer = scene_->spec.viewer;
  options.timeParts = false;
  const double stepLength = options.viewer.speed * options.dt;
  int pressedSides = 0;
  for (std::uint32_t u = 0; u < meshes_->units(); ++u) {
    if (meshes_->triangles(u) < 1000) continue;
    const auto fclModel = fclUnit(*scene_, u);
    const Aabb<double>& outer = scene_->units[u].volume.outer;
    const double reach = 0.5 * outer.size().head<2>().norm() + 1.0;
    for (int side = 0; side < 8; ++side) {
      SCOPED_TRACE("unit " + scene_->units[u].name + " side " + std::to_string(side));
      const double angle = 2 * std::numbers::pi * side / 8 + 0.2;
      const Eigen::Vector3d toward(-std::cos(angle), -std::sin(angle), 0);
      const Eigen::Vector3d start = scene_->toMap(outer.center() - reach * toward);
      const double heading = std::atan2(toward.x(), toward.y()) * 180 / std::numbers::pi;
      Walker walker(*scene_->terrain, w, scene_->origin, options);
      if (!walker.place(start, false, heading, false, 0.0).empty()) continue;  // off the ground or in a unit
      StepInput in;
      in.move = stepLength * toward;
      in.headingDeg = heading;
      int steps = 0;
      while (!walker.state().blocked && steps++ < 2000) walker.step(in);
      const WalkerState& s = walker.state();
      if (!s.blocked || s.reason != BlockReason::Equipment || s.blockedUnit != std::int32_t(u)) continue;
      ++pressedSides;
      Eigen::Vector3d held = s.feet;
      int moves = 0, still = 0;
      for (int frame = 1; frame <= 30; ++frame) {
        const StepReport report = walker.step(in);
        if (!s.blocked || s.blockedUnit != std::int32_t(u)) {
          ADD_FAILURE() << "pressed frame " << frame << ": no longer blocked by the unit";
          break;
        }
        const double moved = (s.feet - held).norm();
        if (moved != 0.0) {
          ++moves;
          EXPECT_GE(moved, kMinBlockedAdvance) << "pressed frame " << frame << ": a creep";
          held = s.feet;
          still = 0;
        } else if (++still >= 2) {  // the same sweep as the frame before: nothing to test again
          EXPECT_EQ(report.counters.primitiveTests, 0u) << "pressed frame " << frame;
        }
      }
      EXPECT_LE(moves, 1);
      const double gap = fclDistance(*fclModel, walker.bodyVolume(s.feet, s.bodyYawDeg).inner);
      EXPECT_GT(gap, 0.0);
      EXPECT_LE(gap, kMostStopGap);
    }
  }
  EXPECT_GE(pressedSides, 4);
}

}  // namespace
}  // namespace nestwalk
