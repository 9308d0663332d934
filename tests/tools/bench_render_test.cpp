// `nestwalk bench render --quick --json`: a smoke run of the rendering benchmark a user runs,
// offscreen without a display. Times are not asserted; what it checks is measured: both
// configurations rendered every sampled frame, the terrain error stays within its LOD budget, the
// nested view culling never kept more instances than OSG's bounding spheres on the same frames, and
// the frame-rate target is the default configuration's median frame rate.
#include "tests/common/run_command.h"
#include "tests/common/test_data.h"

#include <nlohmann/json.hpp>

#include <filesystem>

namespace nestwalk::test {
namespace {

TEST(BenchRender, QuickJsonRunComparesCullingAndLod) {
  if (!std::filesystem::exists(test::bundledSceneFile()))
    GTEST_SKIP() << "the bundled scene is absent: build the bundled_scene target";
  const CommandResult r = runNestwalk("bench render --quick --json");
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["route"], "egl-surfaceless");
  ASSERT_EQ(j["flythroughs"].size(), 5u);  // the bundled ones
  ASSERT_EQ(j["configs"].size(), 2u);
  const long frames = 8 * 5;                // --quick: 8 sampled frames per flythrough
  for (const auto& c : j["configs"]) {
    EXPECT_EQ(c["frames"].get<long>(), frames);
    EXPECT_DOUBLE_EQ(c["fps_p50"].get<double>(), 1000.0 / c["ms_p50"].get<double>());
    EXPECT_LE(c["ms_p50"].get<double>(), c["ms_p95"].get<double>());
    EXPECT_GT(c["mean_triangles"].get<double>(), 1000.0);
    EXPECT_LE(c["max_terrain_error_px"].get<double>(), c["lod_max_px"].get<double>() * (1 + 1e-9));
  }
  const auto& cull = j["view_culling"];
  EXPECT_EQ(cull["frames"].get<long>(), frames);
  EXPECT_EQ(cull["frames_nested_kept_more"].get<long>(), 0);
  EXPECT_LE(cull["nested_kept_mean"].get<double>(), cull["osg_spheres_kept_mean"].get<double>());
  ASSERT_EQ(j["targets"].size(), 1u);
  EXPECT_DOUBLE_EQ(j["targets"][0]["value"].get<double>(), j["configs"][0]["fps_p50"].get<double>());
}

}  // namespace
}  // namespace nestwalk::test
