// The walk session (engine/session/walk_session.h) without a window, on the bundled mining-dump
// scene: the start is the first free place of the search order (checked by placing a separate
// walker at every candidate in turn), a start inside equipment is refused by name, a recorded walk
// is a script that a plain flythrough plays back to the same place, and a played script's blocks
// and expectations are said once each as the shown frame reaches them.
#include "nestwalk/session/walk_session.h"

#include "nestwalk/core/angles.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/walker/script_file.h"
#include "tests/common/input_error_of.h"
#include "tests/common/temp_folder.h"
#include "tests/common/test_data.h"

#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_api.h>

#include <filesystem>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;

class WalkSessionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(test::bundledSceneFile()))
      GTEST_SKIP() << test::bundledSceneFile() << " is absent: build the bundled_scene target";
  }
  WalkSessionOptions options() const {
    WalkSessionOptions o;
    o.scene = test::bundledSceneFile().string();
    o.say = [this](const std::string& line) { said.push_back(line); };
    return o;
  }
  mutable std::vector<std::string> said;
};

TEST_F(WalkSessionTest, StartsAtTheFirstFreePlaceOfTheSearch) {
  WalkSession session(options());
  // The candidates in the search's order, each tried on a walker of our own.
  const Scene& scene = session.scene();
  const CollisionWorld world = CollisionWorld::fromScene(scene, session.method());
  WalkerOptions wo;
  wo.viewer = scene.spec.viewer;
  Walker probe(*scene.terrain, world, scene.origin, wo);
  const terrain::Heightfield& hf = *scene.terrain;
  const Eigen::Vector3d centre(hf.origin().x() + 0.5 * (hf.cols() - 1) * hf.dx(),
                               hf.origin().y() - 0.5 * (hf.rows() - 1) * hf.dy(), 0);
  std::vector<Eigen::Vector3d> candidates = {centre};
  for (double r = 5; r <= 0.5 * std::max(hf.cols() * hf.dx(), hf.rows() * hf.dy()); r += 5)
    for (int k = 0; k < 16; ++k) {
      const auto [s, c] = sinCosDegrees(22.5 * k);
      candidates.push_back(centre + r * Eigen::Vector3d(s, c, 0));
    }
  std::optional<Eigen::Vector3d> first;
  for (const Eigen::Vector3d& c : candidates)
    if (probe.place(c, false, 0, false, 0).empty()) {
      first = c;
      break;
    }
  ASSERT_TRUE(first.has_value());
  const Eigen::Vector3d& feet = session.walker().state().feet;
  EXPECT_EQ(feet.x(), first->x());
  EXPECT_EQ(feet.y(), first->y());
}

TEST_F(WalkSessionTest, RefusesAStartInsideEquipment) {
  const Scene scene = loadScene(test::bundledSceneFile().string());
  const CollisionWorld world = CollisionWorld::fromScene(scene, scene.spec.method);
  WalkerOptions wo;
  wo.viewer = scene.spec.viewer;
  Walker probe(*scene.terrain, world, scene.origin, wo);
  // The middle of a unit's inner box (local frame + origin) that a walker of our own refuses.
  std::string why;
  Eigen::Vector3d inside;
  for (std::size_t u = 0; u < world.size() && why.empty(); ++u) {
    inside = world.unit(u).inner.center + scene.origin;
    why = probe.place(inside, false, 0, false, 0);
  }
  ASSERT_FALSE(why.empty()) << "no unit of the bundled scene refuses a start at its middle";
  WalkSessionOptions o = options();
  o.start = {inside.x(), inside.y()};
  const std::string message = test::inputError([&] { WalkSession session(o); });
  EXPECT_EQ(message.rfind("--start ", 0), 0u) << message;
  EXPECT_NE(message.find(why), std::string::npos) << message;
}

TEST_F(WalkSessionTest, ARecordedWalkPlaysBackToTheSamePlace) {
  const test::TempFolder folder;
  WalkSessionOptions o = options();
  o.recordFolder = (folder.path() / "walks").string();
  WalkSession session(o);
  for (int k = 0; k < 30; ++k) {  // the window runs a while before R is pressed
    StepInput still;
    still.headingDeg = session.walker().state().headingDeg;
    session.walker().step(still);
  }
  session.toggleRecording();
  ASSERT_TRUE(session.recording()) << session.status();
  Walker& walker = session.walker();
  StepInput in;
  in.headingDeg = 30;
  in.move = Eigen::Vector3d(0.5, 0.866, 0) * 1.4 * walker.options().dt;  // 1.4 m/s, heading 30
  for (int k = 0; k < 240; ++k) {
    session.recordStep(in, walker.step(in));
  }
  const Eigen::Vector3d end = walker.state().feet;
  session.toggleRecording();
  EXPECT_FALSE(session.recording());
  const fs::path script = folder.path() / "walks" / "walk_001.txt";
  ASSERT_TRUE(fs::exists(script)) << session.status();
  EXPECT_TRUE(fs::exists(folder.path() / "walks" / "walk_001.path"));
  EXPECT_TRUE(fs::exists(folder.path() / "walks" / "walk_001.geojson"));
  {  // The walk's layers: its path holds every recorded step, ending where the walker stood.
    GDALAllRegister();
    GDALDatasetH ds = GDALOpenEx((folder.path() / "walks" / "walk_001.gpkg").c_str(), GDAL_OF_VECTOR, nullptr, nullptr, nullptr);
    ASSERT_NE(ds, nullptr);
    OGRLayerH l = GDALDatasetGetLayerByName(ds, "path");
    ASSERT_NE(l, nullptr);
    OGRFeatureH f = OGR_L_GetNextFeature(l);
    ASSERT_NE(f, nullptr);
    OGRGeometryH g = OGR_F_GetGeometryRef(f);
    ASSERT_EQ(OGR_G_GetPointCount(g), 240);
    // Times from the recording's start, not the window's (30 steps before it).
    EXPECT_NEAR(OGR_G_GetM(g, 0), walker.options().dt, 1e-9);
    EXPECT_NEAR(OGR_G_GetM(g, 239), 240 * walker.options().dt, 1e-9);
    const Eigen::Vector3d last = walker.eye();
    EXPECT_EQ(Eigen::Vector3d(OGR_G_GetX(g, 239), OGR_G_GetY(g, 239), OGR_G_GetZ(g, 239)), last);
    OGR_F_Destroy(f);
    GDALClose(ds);
  }
  EXPECT_NE(session.status().find("walk_001.txt"), std::string::npos);

  const Scene& scene = session.scene();
  const CollisionWorld world = CollisionWorld::fromScene(scene, session.method());
  WalkerOptions wo;
  wo.viewer = scene.spec.viewer;
  const FlythroughResult replay = runFlythrough(scene, world, readScript(script.string()), wo);
  ASSERT_FALSE(replay.records.empty());
  EXPECT_LT((replay.records.back().eye.head<2>() - end.head<2>()).norm(), 1e-3);  // 1 mm
}

TEST_F(WalkSessionTest, SaysEachBlockAndExpectationOnceAsTheShownFrameReachesThem) {
  WalkSessionOptions o = options();
  o.script = test::bundledScript("bench_patrol.txt").string();
  WalkSession session(o);
  const FlythroughResult& played = session.played();
  ASSERT_FALSE(played.records.empty());
  std::size_t blocks = 0;
  bool was = false;
  for (const FrameRecord& r : played.records) {
    WalkFrame f;
    f.pose = {r.eye, r.headingDeg, r.pitchDeg, r.blocked, r.blockedBy};
    f.shown = &r;
    const HudState h = session.frame(f);
    EXPECT_EQ(h.eye, r.eye);
    const std::optional<double> ground = session.scene().terrain->groundHeight(r.eye.x(), r.eye.y());
    EXPECT_EQ(h.hasGround, ground.has_value());
    blocks += r.blocked && !was;
    was = r.blocked;
  }
  std::size_t blockLines = 0, expectationLines = 0;
  for (const std::string& line : said) {
    blockLines += line.rfind("blocked by ", 0) == 0;
    expectationLines += line.rfind("line ", 0) == 0;
  }
  EXPECT_GT(blocks, 0u);
  EXPECT_EQ(blockLines, blocks);
  EXPECT_EQ(expectationLines, played.expectations.size());
  EXPECT_TRUE(session.expectationsMet());
}

}  // namespace
}  // namespace nestwalk
