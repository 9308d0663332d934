// Texels per pixel (render/texel_density.h) against the analytic answer: over flat ground seen
// straight down every pixel covers the same ground, H * 2 tan(fovY / 2) / height metres on both
// axes (the ground plane is parallel to the image plane, so ground offsets are linear in the
// pixel), and the part under the eye is the nearest one, drawn with the finest texel of the frame.
// Real llvmpipe, a 1 m DEM at UTM magnitudes (zone 33N, 69 degrees north), a 25 cm orthophoto.
#include "nestwalk/render/texel_density.h"

#include "nestwalk/render/imagery_tiles.h"
#include "nestwalk/render/paged_terrain.h"
#include "nestwalk/render/view_graph.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/terrain/terrain_imagery.h"
#include "nestwalk/terrain/terrain_import.h"
#include "tests/scene/scene_test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <vector>

namespace nestwalk {
namespace {

constexpr double kWest = 500000.0, kNorth = 7650000.0;  // map x, y of the DEM's sample (0, 0)
constexpr int kDemSamples = 257;                           // 256 m at 1 m
constexpr double kGroundZ = 300.0;
constexpr double kOrthoPixelM = 0.25;
constexpr int kSide = 720;  // a square frame: the one sampled pixel (pixelStep = kSide) is its centre's

class TexelDensity : public test::TempFolderTest {
 protected:
  Scene makeScene(bool imagery) {
    const std::vector<float> heights(std::size_t(kDemSamples) * kDemSamples, float(kGroundZ));
    terrain::writeTerrainCog((dir() / "dem.tif").string(), kDemSamples, kDemSamples, heights, kWest, kNorth, 1.0, 1.0,
                             "EPSG:32633", false);
    nlohmann::json scene{{"terrain", "dem.tif"}};
    if (imagery) {
      const int pixels = int(std::lround((kDemSamples - 1) / kOrthoPixelM));
      std::vector<std::uint8_t> rgb(std::size_t(pixels) * std::size_t(pixels) * 3);
      for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = std::uint8_t((i * 37) % 251);
      terrain::writeImageryCog((dir() / "ortho.tif").string(), pixels, pixels, rgb, kWest + kOrthoPixelM / 2,
                               kNorth - kOrthoPixelM / 2, kOrthoPixelM, kOrthoPixelM, "EPSG:32633", false);
      scene["imagery"] = "ortho.tif";
    }
    std::ofstream((dir() / "scene.json").string()) << scene.dump();
    return loadScene((dir() / "scene.json").string());
  }

  static RenderOptions options() {
    RenderOptions o;
    o.width = o.height = kSide;
    o.terrainLoading = TerrainLoading::Complete;
    return o;
  }

  static ViewPose straightDown(double heightM) {
    ViewPose p;
    p.eye = Eigen::Vector3d(kWest + 128.3, kNorth - 127.6, kGroundZ + heightM);
    p.pitchDeg = -90;
    return p;
  }
};

TEST_F(TexelDensity, StraightDownOverFlatGroundIsTheAnalyticFootprintOverTheFinestTexelDrawn) {
  const Scene scene = makeScene(true);
  ViewRenderer renderer(scene, options());
  TexelsPerPixel all;
  // 10 m: the near band; 50 m: the middle; 150 m and 600 m: far, the last over a coarser texel than
  // the orthophoto's 25 cm.
  for (const double h : {10.0, 50.0, 150.0, 600.0}) {
    const RenderFrameStats& stats = renderer.render(straightDown(h));
    TexelsPerPixel one;
    sampleTexelsPerPixel(renderer, *scene.terrain, kSide, one);
    sampleTexelsPerPixel(renderer, *scene.terrain, kSide, all);
    const std::vector<double>& band = h < kTexelNearM ? one.near : h < kTexelFarM ? one.middle : one.far;
    ASSERT_EQ(one.near.size() + one.middle.size() + one.far.size(), 1u) << h << " m";
    ASSERT_EQ(band.size(), 1u) << h << " m";
    const double footprint = h * 2 * std::tan(0.5 * RenderOptions{}.fovYDegrees * M_PI / 180) / kSide;
    const ImageryTiles& tiles = *renderer.graph().pagedTerrain().imageryTiles();
    const double texel = tiles.texelSize(stats.terrain.finestTexelLevelDrawn);
    EXPECT_NEAR(band[0], footprint / texel, 1e-6 * footprint / texel) << h << " m: texel " << texel << " m";
    if (h > 500) {
      EXPECT_GT(texel, kOrthoPixelM);
    }
    std::printf("straight down from %.0f m: %.4f m a pixel, %.4f m texels, %.3f texels per pixel\n", h, footprint,
                texel, band[0]);
  }
  EXPECT_EQ(all.near.size(), 1u);
  EXPECT_EQ(all.middle.size(), 1u);
  EXPECT_EQ(all.far.size(), 2u);
}

TEST_F(TexelDensity, NothingIsSampledWithoutImageryAndAStepBelowOneIsRefused) {
  const Scene scene = makeScene(false);
  ViewRenderer renderer(scene, options());
  renderer.render(straightDown(10));
  TexelsPerPixel into;
  sampleTexelsPerPixel(renderer, *scene.terrain, 16, into);
  EXPECT_TRUE(into.near.empty() && into.middle.empty() && into.far.empty());
  EXPECT_THROW(sampleTexelsPerPixel(renderer, *scene.terrain, 0, into), std::invalid_argument);
}

}  // namespace
}  // namespace nestwalk
