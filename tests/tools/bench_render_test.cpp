// `nestwalk bench render --quick --json`: a smoke run of the rendering benchmark a user runs,
// offscreen without a display. Times are not asserted; what it checks is measured: both
// configurations rendered every sampled frame, the terrain error stays within its LOD budget, the
// nested view culling never kept more instances than OSG's bounding spheres on the same frames, and
// the frame-rate target is the default configuration's median frame rate.
#include "tests/common/run_command.h"
#include "tests/common/temp_folder.h"
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

TEST(BenchRender, ImageryRowsDrapeAFinerOrthophotoBesideTheDemResolution) {
  if (!std::filesystem::exists(test::bundledSceneFile()))
    GTEST_SKIP() << "the bundled scene is absent: build the bundled_scene target";
  // The bundled dump's orthophoto at 25 cm (the bundled scene is make-terrain's default dump).
  const TempFolder folder;
  const auto made = runNestwalk("make-terrain " + quoted(folder.path() / "dump.tif") + " --ortho " +
                                quoted(folder.path() / "ortho25.tif") + " --ortho-pixel 0.25");
  ASSERT_EQ(made.exitCode, 0) << made.err;
  const CommandResult r = runNestwalk("bench render --quick --json --imagery " + quoted(folder.path() / "ortho25.tif"));
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["configs"].size(), 4u);  // the two default rows, the DEM's resolution, the orthophoto
  const auto& dem = j["configs"][2];
  const auto& fine = j["configs"][3];
  EXPECT_EQ(dem["config"], "imagery at the DEM's resolution, settled");
  EXPECT_EQ(fine["config"], "imagery ortho25.tif, settled");
  EXPECT_DOUBLE_EQ(dem["finest_texel_cm"].get<double>(), 100.0);  // 1 m cells: the DEM's spacing
  EXPECT_DOUBLE_EQ(fine["finest_texel_cm"].get<double>(), 25.0);  // the 25 cm pixels: 64 m over 256 texels
  EXPECT_GT(fine["imagery_mib"].get<double>(), dem["imagery_mib"].get<double>());
  // Texels per pixel near the eye (render/texel_density.h): the same pixels of the same poses, each
  // drawn at its finest texel there (a pixel within 20 m covers less than 25 cm), so the 25 cm
  // orthophoto shows 4 times the DEM drape's texels per pixel.
  EXPECT_NEAR(fine["texels_per_px_near"].get<double>() / dem["texels_per_px_near"].get<double>(), 4.0, 0.2);
  for (const auto* row : {&dem, &fine}) {
    EXPECT_EQ((*row)["poses_unsettled"].get<long>(), 0);
    EXPECT_LE((*row)["imagery_mib"].get<double>(), (*row)["terrain_resident_mib"].get<double>());
    EXPECT_LE((*row)["max_terrain_error_px"].get<double>(), 1.0 + 1e-9);
  }
}

}  // namespace
}  // namespace nestwalk::test
