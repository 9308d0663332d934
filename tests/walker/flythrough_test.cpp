// Flythroughs on the bundled mining-dump scene at the engine level: the scene at its real UTM
// position and moved near the map origin (terrain, equipment and script shifted together) gives
// the same contacts and heights, and every step's eye stands eye_height above the terrain query.
#include "tests/common/build_paths.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/terrain/height_tiles.h"
#include "nestwalk/walker/flythrough.h"
#include "nestwalk/walker/script_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;
const fs::path kDir(nestwalk::test::build::bundledSceneDir());

Script shifted(Script s, const Eigen::Vector3d& shift) {
  for (ScriptCommand& c : s.commands)
    if (c.op == ScriptOp::Start || c.op == ScriptOp::Goto || c.op == ScriptOp::ExpectPosition) {
      c.v.x() += shift.x();
      c.v.y() += shift.y();
      if (c.hasZ) c.v.z() += shift.z();
    }
  return s;
}

/// The bundled script `name`.
Script bundledScript(const char* name) { return readScript((kDir / "scripts" / name).string()); }

/// `script` played on `scene` with its viewer (no part timing), each record to `onRecord`.
FlythroughResult playOn(const Scene& scene, const Script& script,
                        const std::function<void(const FrameRecord&)>& onRecord = {}) {
  WalkerOptions opts;
  opts.viewer = scene.spec.viewer;
  opts.timeParts = false;
  const CollisionWorld world = CollisionWorld::fromScene(scene, scene.spec.method);
  return runFlythrough(scene, world, script, opts, onRecord);
}

class BundledFlythrough : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override {
    if (!fs::exists(kDir / "scene.json")) GTEST_SKIP() << kDir << " is absent: build the bundled_scene target";
  }
};

TEST_P(BundledFlythrough, UtmAndOriginGiveTheSameContactsAndHeights) {
  const Scene utm = loadScene((kDir / "scene.json").string());
  SceneLoadOptions moved;
  moved.mapShift = Eigen::Vector3d(-550000.0, -4650000.0, 0.0);
  const Scene origin = loadScene((kDir / "scene.json").string(), moved);
  const Script script = bundledScript(GetParam());
  const FlythroughResult a = playOn(utm, script);
  const FlythroughResult b = playOn(origin, shifted(script, moved.mapShift));
  ASSERT_EQ(a.records.size(), b.records.size());
  std::size_t blocked = 0;
  for (std::size_t i = 0; i < a.records.size(); ++i) {
    const FrameRecord &ra = a.records[i], &rb = b.records[i];
    ASSERT_EQ(ra.blocked, rb.blocked) << "frame " << i;
    ASSERT_EQ(ra.blockedBy, rb.blockedBy) << "frame " << i;
    // Positions are accumulated step by step in map coordinates, where a UTM northing rounds to
    // 1e-9 m per addition: after thousands of steps the two runs drift apart by micrometres.
    ASSERT_NEAR(ra.eye.x() + moved.mapShift.x(), rb.eye.x(), 2e-5) << "frame " << i;
    ASSERT_NEAR(ra.eye.y() + moved.mapShift.y(), rb.eye.y(), 2e-5) << "frame " << i;
    ASSERT_NEAR(ra.eye.z(), rb.eye.z(), 2e-5) << "frame " << i;
    ASSERT_NEAR(ra.ground, rb.ground, 2e-5) << "frame " << i;
    blocked += ra.blocked;
  }
  EXPECT_TRUE(a.expectationsMet());
  EXPECT_TRUE(b.expectationsMet());
  RecordProperty("frames_blocked", std::to_string(blocked));
}

TEST_P(BundledFlythrough, WalkingEyeIsEyeHeightAboveTheTerrainQuery) {
  const Scene scene = loadScene((kDir / "scene.json").string());
  const FlythroughResult r = playOn(scene, bundledScript(GetParam()));
  const double eyeHeight = scene.spec.viewer.eyeHeight;
  ASSERT_FALSE(r.records.empty());
  double worst = 0;
  for (const FrameRecord& f : r.records) {
    const std::optional<double> g = scene.terrain->groundHeight(f.eye.x(), f.eye.y());
    ASSERT_TRUE(g.has_value()) << "frame " << f.frame;
    if (f.flying) {
      EXPECT_GE(f.eye.z() - eyeHeight - *g, 0.0) << "frame " << f.frame;
    } else {
      worst = std::max(worst, std::abs(f.eye.z() - eyeHeight - *g));
    }
  }
  EXPECT_LE(worst, 1e-9);
}

TEST_P(BundledFlythrough, OnThePagedTerrainEveryStepIsTheResidentOnesAndNoneWaits) {
  SceneLoadOptions held, paged;
  held.terrainStorage = SceneLoadOptions::TerrainStorage::resident;
  paged.terrainStorage = SceneLoadOptions::TerrainStorage::paged;
  paged.terrainTileBudget = std::size_t(16) * 270'000;  // 16 tiles of 257 x 257 samples
  const Scene a = loadScene((kDir / "scene.json").string(), held);
  const Scene b = loadScene((kDir / "scene.json").string(), paged);
  ASSERT_TRUE(b.terrain->paged());
  const Script script = bundledScript(GetParam());
  const FlythroughResult ra = playOn(a, script);
  // Each step lets the tiles the walker asked for be read first, as playing at the real pace does
  // (the walker asks kPrefetchSeconds of motion ahead; a tile takes milliseconds): what is tested is
  // that it asks for the ground it then reaches. The first step waits for none either: placing
  // the walker read the ground around it.
  std::uint64_t waits = 0;
  const FlythroughResult rb = playOn(b, script, [&](const FrameRecord& r) {
    waits += r.groundWaits;
    b.terrain->tiles()->waitForPrefetch();
  });
  ASSERT_EQ(ra.records.size(), rb.records.size());
  for (std::size_t i = 0; i < ra.records.size(); ++i) {
    ASSERT_EQ(ra.records[i].eye, rb.records[i].eye) << "frame " << i;
    ASSERT_EQ(ra.records[i].ground, rb.records[i].ground) << "frame " << i;
    ASSERT_EQ(ra.records[i].blockedBy, rb.records[i].blockedBy) << "frame " << i;
    EXPECT_EQ(ra.records[i].groundWaits, 0u);
  }
  EXPECT_EQ(waits, 0u);
  EXPECT_LE(b.terrain->tiles()->stats().peakBytesHeld, paged.terrainTileBudget);
  RecordProperty("tiles_read", std::to_string(b.terrain->tiles()->stats().reads));
}

INSTANTIATE_TEST_SUITE_P(Scripts, BundledFlythrough,
                         ::testing::Values("bench_patrol.txt", "ramp_descent.txt", "low_flight.txt",
                                           "equipment_walk.txt", "equipment_fly.txt"),
                         [](const auto& info) { return fs::path(info.param).stem().string(); });

}  // namespace
}  // namespace nestwalk
