// The recorded run (engine/session/recorded_run.h) on the bundled mining-dump scene: its steps are
// the ones a plain flythrough on the same walker takes (runFlythrough, played here beside it), its
// files hold them (rows, summary, camera path), an existing output is refused before anything is
// written, a rendered run draws every N-th step into as many PNGs, and a frame's render statistics
// reach the run's record field for field.
#include "nestwalk/session/recorded_run.h"

#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/walker/script_file.h"
#include "tests/common/input_error_of.h"
#include "tests/common/temp_folder.h"
#include "tests/common/test_data.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <sstream>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;

// The shortest bundled flythrough that meets contacts: the bench patrol.
const char* const kScript = "bench_patrol.txt";

std::size_t lineCount(const std::string& text) {
  std::size_t n = 0;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) n += !line.empty();
  return n;
}

class RecordedRunTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(test::bundledSceneFile()))
      GTEST_SKIP() << test::bundledSceneFile() << " is absent: build the bundled_scene target";
  }
  RecordedRunOptions options(const fs::path& out) const {
    RecordedRunOptions o;
    o.scene = test::bundledSceneFile().string();
    o.script = test::bundledScript(kScript).string();
    o.out = out.string();
    return o;
  }
};

TEST_F(RecordedRunTest, TakesAPlainFlythroughsStepsAndWritesThem) {
  const test::TempFolder folder;
  const RecordedRun run = recordRun(options(folder.path()));

  // The same script on the same walker, played directly.
  const Scene scene = loadScene(test::bundledSceneFile().string());
  const CollisionWorld world = CollisionWorld::fromScene(scene, scene.spec.method);
  WalkerOptions walker;
  walker.viewer = scene.spec.viewer;
  walker.dt = 1.0 / 60.0;
  const FlythroughResult plain = runFlythrough(scene, world, readScript(test::bundledScript(kScript).string()), walker);

  const auto& records = run.flythrough.records;
  ASSERT_EQ(records.size(), plain.records.size());
  ASSERT_GT(records.size(), 10u);
  std::size_t blocked = 0;
  for (std::size_t i = 0; i < records.size(); ++i) {
    EXPECT_EQ(records[i].eye, plain.records[i].eye) << "frame " << records[i].frame;
    EXPECT_EQ(records[i].blockedBy, plain.records[i].blockedBy) << "frame " << records[i].frame;
    blocked += plain.records[i].blocked;
  }
  EXPECT_EQ(run.blockedSteps, blocked);
  EXPECT_GT(blocked, 0u);
  std::size_t met = 0;
  for (const ExpectationResult& e : plain.expectations) met += e.met;
  EXPECT_EQ(run.expectationsMet, met);
  EXPECT_EQ(run.expectationsMet, run.flythrough.expectations.size());
  EXPECT_EQ(run.units, world.size());
  EXPECT_TRUE(run.renders.empty());
  EXPECT_LE(run.stepP50Us, run.stepP99Us);
  EXPECT_LE(run.stepP99Us, run.stepMaxUs);

  const fs::path out = folder.path();
  EXPECT_EQ(lineCount(test::readText(out / "frames.csv")), records.size() + 1);  // the header, a row a step
  const auto summary = nlohmann::json::parse(test::readText(out / "summary.json"));
  EXPECT_EQ(summary["frames"].get<std::size_t>(), records.size());
  EXPECT_EQ(summary["units"].get<std::size_t>(), world.size());
  EXPECT_EQ(lineCount(test::readText(out / "camera.path")), plain.camera.size());
  for (const char* f : {"frame_times.png", "top_down.png"}) EXPECT_GT(fs::file_size(out / f), 1000u) << f;
  EXPECT_FALSE(fs::exists(out / "frames"));
}

TEST_F(RecordedRunTest, RefusesAnExistingOutputBeforeWritingAnything) {
  const test::TempFolder folder;
  const fs::path kept = folder.path() / "summary.json";
  test::writeText(kept, "an earlier run's summary");
  const std::string message = test::inputError([&] { recordRun(options(folder.path())); });
  EXPECT_NE(message.find(kept.string()), std::string::npos) << message;
  EXPECT_NE(message.find("--overwrite"), std::string::npos) << message;
  EXPECT_EQ(test::readText(kept), "an earlier run's summary");
  EXPECT_FALSE(fs::exists(folder.path() / "frames.csv"));

  RecordedRunOptions o = options(folder.path());
  o.overwrite = true;
  recordRun(o);
  EXPECT_NE(test::readText(kept), "an earlier run's summary");
}

TEST_F(RecordedRunTest, RendersEveryNthStepIntoAsManyFrames) {
  const test::TempFolder folder;
  RecordedRunOptions o = options(folder.path());
  RunRendering rendering;
  rendering.view.width = 96;
  rendering.view.height = 64;
  rendering.every = 40;
  rendering.video = false;
  o.rendering = rendering;
  std::size_t steps = 0;
  o.onStep = [&](const FrameRecord&, double) { ++steps; };
  const RecordedRun run = recordRun(o);

  const std::size_t n = run.flythrough.records.size();
  EXPECT_EQ(steps, n);
  ASSERT_EQ(run.renders.size(), n);
  const std::size_t expected = (n + 39) / 40;  // steps 1, 41, 81, ...
  EXPECT_EQ(run.framesRendered, expected);
  EXPECT_EQ(run.pngFrames, expected);
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(folder.path() / "frames")) files += entry.path().extension() == ".png";
  EXPECT_EQ(files, expected);
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(run.renders[i].rendered, i % 40 == 0) << i;
    if (run.renders[i].rendered) {
      EXPECT_GT(run.renders[i].triangles, 0u) << i;
    }
  }
  EXPECT_FALSE(run.route.empty());
  EXPECT_GT(run.renderP50Ms[RenderPart::Total], 0.0);
  const auto summary = nlohmann::json::parse(test::readText(folder.path() / "summary.json"));
  EXPECT_EQ(summary["render"]["frames"].get<std::size_t>(), expected);
}

TEST(RenderRecordOf, CopiesEveryFigureAndCountsEveryInstanceWhenNestedCullingIsOff) {
  RenderFrameStats s;
  s.cullMs = 1.5, s.drawMs = 2.25, s.readbackMs = 0.5, s.totalMs = 4.75;
  s.triangles = 123456;
  s.terrainErrorPx = 0.75;
  s.cull.instances = 40, s.cull.aabbOutside = 25, s.cull.obbOutside = 3, s.cull.visible = 12;
  const RenderRecord r = renderRecordOf(s, 40);
  EXPECT_TRUE(r.rendered);
  EXPECT_EQ(r.triangles, 123456u);
  EXPECT_EQ(r.instancesDrawn, 12u);
  EXPECT_EQ(r.culledByAabb, 25u);
  EXPECT_EQ(r.culledByObb, 3u);
  EXPECT_EQ(r.terrainErrorPx, 0.75);
  EXPECT_EQ(r.micros[RenderPart::Cull], 1500.0);
  EXPECT_EQ(r.micros[RenderPart::Draw], 2250.0);
  EXPECT_EQ(r.micros[RenderPart::Readback], 500.0);
  EXPECT_EQ(r.micros[RenderPart::Total], 4750.0);

  RenderFrameStats osgCulling;  // nested culling off: no instance tested, every one drawn by OSG's culling
  EXPECT_EQ(renderRecordOf(osgCulling, 40).instancesDrawn, 40u);
}

}  // namespace
}  // namespace nestwalk
