// Imagery at its own resolution (render/imagery_tiles.h), rendered for real (llvmpipe, 1280 x 720)
// over a 1 m DEM at UTM magnitudes (zone 33N, 69 degrees north), with a checkerboard orthophoto of
// 5 cm squares (1.25 cm pixels) around the eye:
// - near the eye every pixel whose ground point (the exact ray cast through the pixel's centre,
//   Heightfield::intersectRay) lies clear of a square's edge shows that square's colour, in 99 % of
//   them; the drape at the DEM's resolution (one texel per metre) fails the same check;
// - the texel level drawn on each part is within one level of a GPU's mipmap choice at the part's
//   nearest visible point, measured from the frame's own rays (the ground distance between
//   neighbouring pixels' hits), not from the rule's boxes;
// - a far region of the frame changes little when the eye moves a little (no shimmer): each far
//   tile is filtered from the orthophoto's overviews, not point-sampled; nearer, a part's farther
//   pixels are kept from shimmering by the tile's mip levels.
#include "nestwalk/render/view_renderer.h"

#include "nestwalk/render/paged_terrain.h"
#include "nestwalk/render/view_graph.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/terrain/terrain_imagery.h"
#include "nestwalk/terrain/terrain_import.h"
#include "tests/scene/scene_test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <vector>

namespace nestwalk {
namespace {

constexpr double kWest = 500000.0, kNorth = 7650000.0;  // map x, y of the DEM's sample (0, 0)
constexpr int kDemSamples = 1025;                          // 1 km at 1 m
constexpr double kSquareM = 0.05;                          // the checkerboard's squares
constexpr double kOrthoPixelM = 0.0125;                    // 4 pixels a square, squares on pixel edges
constexpr double kOrthoSideM = 32.0;                       // the orthophoto: 32 m around the eye
constexpr double kEyeX = kWest + 500.0, kEyeY = kNorth - 500.0;
constexpr unsigned char kRed[3] = {210, 60, 40}, kBlue[3] = {40, 120, 220};

double demHeight(double x, double y) {  // map coordinates: gentle waves over a tilt
  const double u = x - kWest, v = kNorth - y;
  return 200.0 + 0.02 * u + 0.01 * v + 1.5 * std::sin(0.05 * u) * std::cos(0.04 * v);
}

/// Which colour a checkerboard of `square` metres has at map (x, y): true red.
bool redAt(double x, double y, double square = kSquareM) {
  const auto i = std::int64_t(std::floor((x - kEyeX) / square)), j = std::int64_t(std::floor((y - kEyeY) / square));
  return ((i + j) & 1) == 0;
}

/// The distance from map (x, y) to the nearest square edge, metres.
double edgeDistance(double x, double y) {
  auto along = [](double t) {
    const double f = t / kSquareM - std::floor(t / kSquareM);
    return std::min(f, 1 - f) * kSquareM;
  };
  return std::min(along(x - kEyeX), along(y - kEyeY));
}

class ImageryTilesRender : public test::TempFolderTest {
 protected:
  /// The DEM, the orthophoto (a checkerboard of `square` metres at `pixel` metres, `side` metres
  /// around the eye) and scene.json in the test's folder; the scene loaded.
  Scene makeScene(double square = kSquareM, double pixel = kOrthoPixelM, double side = kOrthoSideM) {
    std::vector<float> heights(std::size_t(kDemSamples) * kDemSamples);
    for (int r = 0; r < kDemSamples; ++r)
      for (int c = 0; c < kDemSamples; ++c) heights[std::size_t(r) * kDemSamples + std::size_t(c)] = float(demHeight(kWest + c, kNorth - r));
    terrain::writeTerrainCog((dir() / "dem.tif").string(), kDemSamples, kDemSamples, heights, kWest, kNorth, 1.0, 1.0,
                             "EPSG:32633", false);
    const int pixels = int(std::lround(side / pixel));
    const double x0 = kEyeX - side / 2, y0 = kEyeY + side / 2;  // north-west corner
    std::vector<std::uint8_t> rgb(std::size_t(pixels) * std::size_t(pixels) * 3);
    for (int j = 0; j < pixels; ++j)
      for (int i = 0; i < pixels; ++i) {
        const bool red = redAt(x0 + (i + 0.5) * pixel, y0 - (j + 0.5) * pixel, square);
        std::copy_n(red ? kRed : kBlue, 3, &rgb[3 * (std::size_t(j) * std::size_t(pixels) + std::size_t(i))]);
      }
    terrain::writeImageryCog((dir() / "ortho.tif").string(), pixels, pixels, rgb, x0 + pixel / 2, y0 - pixel / 2, pixel,
                             pixel, "EPSG:32633", false);
    std::ofstream((dir() / "scene.json").string())
        << nlohmann::json{{"terrain", "dem.tif"}, {"imagery", "ortho.tif"}}.dump();
    return loadScene((dir() / "scene.json").string());
  }

  static RenderOptions options(double finestTexelM = 0) {
    RenderOptions o;
    o.terrainLoading = TerrainLoading::Complete;
    o.imageryFinestTexelM = finestTexelM;
    return o;
  }

  static ViewPose pose(double pitchDeg, double dx = 0) {
    ViewPose p;
    p.eye = Eigen::Vector3d(kEyeX + dx, kEyeY, demHeight(kEyeX + dx, kEyeY) + 1.7);
    p.headingDeg = 30;
    p.pitchDeg = pitchDeg;
    return p;
  }
};

/// The share of near-field pixels (ground within kNearM of the eye, clear of a square's edge by
/// kEdgeMarginM) whose colour is the checkerboard's there (red or blue by which channel is larger).
struct CheckerMatch {
  std::size_t pixels = 0, matching = 0;
  double share() const { return pixels ? double(matching) / double(pixels) : 0; }
};

/// Metres: the near field the target speaks of.
constexpr double kNearM = 8.0;
/// Metres from a square's edge: the drawn colour there blends the two squares over a texel and an
/// orthophoto pixel (1.56 cm and 1.25 cm, bilinear both): at 1 cm at least four fifths of it is the
/// square's own.
constexpr double kEdgeMarginM = 0.01;

CheckerMatch matchChecker(const Scene& scene, ViewRenderer& renderer) {
  const osg::Image& image = renderer.image();
  CheckerMatch m;
  for (int y = 0; y < image.t(); y += 2)
    for (int x = 0; x < image.s(); x += 2) {
      const auto [origin, dir] = renderer.pixelRay(x + 0.5, y + 0.5);
      const auto hit = scene.terrain->intersectRay(origin, dir);
      if (!hit || hit->t > kNearM) continue;
      const Eigen::Vector3d p = origin + hit->t * dir;
      if (std::abs(p.x() - kEyeX) > kOrthoSideM / 2 - 0.5 || std::abs(p.y() - kEyeY) > kOrthoSideM / 2 - 0.5) continue;
      if (edgeDistance(p.x(), p.y()) < kEdgeMarginM) continue;
      const unsigned char* c = image.data(x, image.t() - 1 - y);
      ++m.pixels;
      m.matching += (c[0] > c[2]) == redAt(p.x(), p.y());
    }
  return m;
}

TEST_F(ImageryTilesRender, CheckerboardNearTheEyeShowsTheOrthophotosColours) {
  const Scene scene = makeScene();
  const terrain::TerrainImagery ortho((dir() / "ortho.tif").string(), scene.terrain->crsWkt());
  ViewRenderer renderer(scene, options());
  renderer.render(pose(-45));
  const CheckerMatch tiled = matchChecker(scene, renderer);
  ASSERT_GT(tiled.pixels, 20000u);
  EXPECT_GE(tiled.share(), 0.99) << tiled.matching << " of " << tiled.pixels;
  // The drawn texels near the eye are the finest level (1.5625 cm: the 1.25 cm pixels with the slack).
  const PagedTerrainStats& stats = renderer.lastStats().terrain;
  EXPECT_EQ(stats.finestTexelLevelDrawn, -4);
  EXPECT_GT(stats.imageryBytes, 0u);
  EXPECT_LE(stats.residentBytes, defaultTerrainBudgetBytes());

  // The drape at the DEM's resolution: a texel a metre, the squares averaged away.
  ViewRenderer coarse(scene, options(1.0));
  coarse.render(pose(-45));
  const CheckerMatch dem = matchChecker(scene, coarse);
  ASSERT_GT(dem.pixels, 20000u);
  EXPECT_LT(dem.share(), 0.75) << dem.matching << " of " << dem.pixels;
  std::printf("checkerboard near the eye: tiles %zu of %zu pixels (%.2f %%), DEM-resolution drape %zu of %zu (%.2f %%)\n",
              tiled.matching, tiled.pixels, 100 * tiled.share(), dem.matching, dem.pixels, 100 * dem.share());
}

TEST_F(ImageryTilesRender, TexelLevelIsWithinOneOfTheGpusMipmapChoice) {
  const Scene scene = makeScene();
  ViewRenderer renderer(scene, options());
  std::size_t parts = 0, within = 0;
  double finest = 0, coarsest = 0;  // the tile's level minus the GPU's, over the parts
  std::map<int, int> offByLevel;
  for (const auto& [heading, pitch] : {std::pair(30.0, -8.0), std::pair(120.0, -20.0), std::pair(250.0, -3.0)}) {
    ViewPose view = pose(pitch);
    view.headingDeg = heading;
    renderer.render(view);
    const PagedTerrain& terrain = renderer.graph().pagedTerrain();
    const ImageryTiles& tiles = *terrain.imageryTiles();
    const osg::Image& image = renderer.image();
    const int w = image.s(), h = image.t();
    // Every pixel's ground point (mesh frame: metres from the DEM's sample (0, 0)).
    std::vector<std::optional<Eigen::Vector3d>> ground(std::size_t(w) * std::size_t(h));
    const Eigen::Vector3d origin0(kWest, kNorth, 0);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const auto [origin, dir] = renderer.pixelRay(x + 0.5, y + 0.5);
        if (const auto hit = scene.terrain->intersectRay(origin, dir))
          ground[std::size_t(y) * std::size_t(w) + std::size_t(x)] = origin + hit->t * dir - origin0;
      }
    const Eigen::Vector3d eye = view.eye - origin0;
    auto at = [&](int i, int j) -> const std::optional<Eigen::Vector3d>& {
      return ground[std::size_t(std::clamp(j, 0, h - 1)) * std::size_t(w) + std::size_t(std::clamp(i, 0, w - 1))];
    };
    // A pixel's footprint along the screen's coarser axis: the larger of the horizontal ground steps
    // (the texture's coordinates are the map's x and y, chunk_node.h) to its neighbours across and down (on each axis the smaller of the two sides' steps, so that a step
    // over a silhouette does not count), as a GPU's derivatives measure it.
    auto footprint = [&](int x, int y) -> std::optional<double> {
      const auto& p = at(x, y);
      double axis[2];
      for (int a = 0; a < 2; ++a) {
        double best = std::numeric_limits<double>::infinity();
        for (int s : {-1, 1}) {
          const auto& q = a == 0 ? at(x + s, y) : at(x, y + s);
          if (q) best = std::min(best, (*q - *p).head<2>().norm());  // texture coordinates are map x, y
        }
        if (!std::isfinite(best)) return std::nullopt;
        axis[a] = best;
      }
      return std::max(axis[0], axis[1]);
    };
    // Each drawn part's nearest visible point: the pixel whose ground point, inside the part's
    // area, is nearest the eye.
    const terrain::ChunkLayout& layout = terrain.layout();
    for (const DrawnPart& part : terrain.drawnParts()) {
      const double span = layout.chunkCells() * std::ldexp(1.0, part.key.level - 1);  // 1 m samples
      const double ax = (2 * part.key.x + (part.quadrant & 1)) * span, ay = (2 * part.key.y + (part.quadrant >> 1)) * span;
      double nearest = std::numeric_limits<double>::infinity();
      int nx = -1, ny = -1;
      for (int y = 1; y + 1 < h; ++y)
        for (int x = 1; x + 1 < w; ++x) {
          const auto& p = ground[std::size_t(y) * std::size_t(w) + std::size_t(x)];
          if (!p || p->x() < ax || p->x() > ax + span || -p->y() < ay || -p->y() > ay + span) continue;
          const double d = (*p - eye).norm();
          if (d < nearest) nearest = d, nx = x, ny = y;
        }
      if (nx < 0) continue;  // not visible
      const std::optional<double> f = footprint(nx, ny);
      if (!f) continue;
      // The GPU's level, continuous: log2 of the footprint in the finest texels, within the levels.
      const double gpu = std::clamp(tiles.finestTexelLevel() + std::log2(*f / tiles.texelSize(tiles.finestTexelLevel())),
                                    double(tiles.finestTexelLevel()), double(tiles.topTexelLevel()));
      const int tile = part.imageryDrawn.texelLevel;
      ++parts;
      within += std::abs(tile - gpu) <= 1.0;
      finest = std::min(finest, tile - gpu);
      coarsest = std::max(coarsest, tile - gpu);
      ++offByLevel[int(std::floor(tile - gpu))];
      if (std::getenv("NESTWALK_DEBUG_TEXELS"))
        std::printf("part %d/%d/%d q%d wanted %d drawn %d gpu %.2f nearest %.1f m footprint %.3f m at (%d, %d)\n",
                    part.key.level, part.key.x, part.key.y, part.quadrant, part.imageryTexelLevel, tile, gpu, nearest,
                    *f, nx, ny);
    }
  }
  std::string histogram;
  for (const auto& [off, count] : offByLevel) histogram += " " + std::to_string(off) + ":" + std::to_string(count);
  ASSERT_GT(parts, 30u);
  // The rule measures at a block's nearest point in view with the block's mean normal; the GPU at
  // the nearest pixel the part shows, on the surface there. Where the two differ (a wave tilting
  // away from a grazing view, a crest hiding the block the rule measured) the tile is finer than
  // the GPU wants there: measured 47 of 49 tiles within one level, the other 2 up to 1.84 levels
  // finer, none more than 0.65 of a level coarser. With the tiles' mip levels the GL samples its
  // own level wherever the tile is at least that fine (OpenGL's mip selection, seen in the pixels by
  // MipLevelsKeepAPartsFartherPixelsFromShimmering), so a tile finer than the GPU's choice costs
  // memory, not sharpness; one coarser would blur, and none is by more than one level.
  EXPECT_GE(double(within) / double(parts), 0.9) << within << " of " << parts << "; tile minus GPU level (floor):" << histogram;
  EXPECT_GE(finest, -2.0) << histogram;
  EXPECT_LE(coarsest, 1.0) << histogram;
  std::printf("texel levels: %zu of %zu parts' tiles within one level of the GPU's choice; tile minus GPU from %.2f to %.2f\n",
              within, parts, finest, coarsest);
}

/// A band of the frame over a checkerboard of 0.25 m squares when the eye moves 5 cm: how much the
/// drawn colours of the pixels whose ground lies between `fromM` and `toM` of the eye change
/// (levels, mean over the channels), how far they lie from the squares' average, and how much a
/// point sample of the checkerboard at each frame's ground point changes.
struct ShimmerBand {
  std::size_t pixels = 0;
  double drawnChange = 0, fromAverage = 0, pointChange = 0;
};
constexpr double kShimmerSquareM = 0.25;

ShimmerBand shimmer(const Scene& scene, const RenderOptions& options, const ViewPose& before, double fromM, double toM) {
  ViewRenderer renderer(scene, options);
  ViewPose after = before;
  after.eye += Eigen::Vector3d(0.03, 0.04, 0);  // 5 cm
  // Each frame and the ground each sampled pixel shows (every second pixel each way).
  struct Frame {
    osg::ref_ptr<osg::Image> image;
    std::vector<std::optional<Eigen::Vector3d>> ground;
  };
  std::vector<Frame> frames;
  for (const ViewPose& p : {before, after}) {
    renderer.render(p);
    Frame f{new osg::Image(renderer.image(), osg::CopyOp::DEEP_COPY_ALL), {}};
    for (int y = 0; y < f.image->t(); y += 2)
      for (int x = 0; x < f.image->s(); x += 2) {
        const auto [origin, dir] = renderer.pixelRay(x + 0.5, y + 0.5);
        const auto hit = scene.terrain->intersectRay(origin, dir);
        f.ground.push_back(hit ? std::optional<Eigen::Vector3d>(origin + hit->t * dir) : std::nullopt);
      }
    frames.push_back(std::move(f));
  }
  ShimmerBand band;
  std::size_t k = 0;
  const Eigen::Vector3d eye = before.eye;
  for (int y = 0; y < frames[0].image->t(); y += 2)
    for (int x = 0; x < frames[0].image->s(); x += 2, ++k) {
      const auto& g0 = frames[0].ground[k];
      const auto& g1 = frames[1].ground[k];
      if (!g0 || !g1 || (*g0 - eye).norm() < fromM || (*g0 - eye).norm() >= toM) continue;
      if (std::abs(g0->x() - kEyeX) > 195 || std::abs(g0->y() - kEyeY) > 195) continue;  // on the orthophoto
      ++band.pixels;
      const unsigned char* c0 = frames[0].image->data(x, frames[0].image->t() - 1 - y);
      const unsigned char* c1 = frames[1].image->data(x, frames[1].image->t() - 1 - y);
      const unsigned char* p0 = redAt(g0->x(), g0->y(), kShimmerSquareM) ? kRed : kBlue;
      const unsigned char* p1 = redAt(g1->x(), g1->y(), kShimmerSquareM) ? kRed : kBlue;
      for (int c = 0; c < 3; ++c) {
        band.drawnChange += std::abs(int(c0[c]) - int(c1[c])) / 3.0;
        band.pointChange += std::abs(int(p0[c]) - int(p1[c])) / 3.0;
        band.fromAverage += std::abs(c0[c] - 0.5 * (kRed[c] + kBlue[c])) / 3.0;
      }
    }
  if (band.pixels) {
    band.drawnChange /= double(band.pixels);
    band.pointChange /= double(band.pixels);
    band.fromAverage /= double(band.pixels);
  }
  return band;
}

TEST_F(ImageryTilesRender, FarTerrainDoesNotShimmerWhenTheEyeMovesALittle) {
  // A checkerboard of 0.25 m squares over 400 m: far away a pixel covers many squares. Point-sampled
  // (what a texture at the imagery's resolution without mipmaps shows) such a region flips between
  // the two colours as the eye moves a few centimetres; the tiles show the average there, read from
  // the orthophoto's overviews, and stay put.
  constexpr double kFarM = 100.0;
  const Scene scene = makeScene(kShimmerSquareM, 0.125, 400.0);
  const ShimmerBand far = shimmer(scene, options(), pose(-4), kFarM, 1e9);
  std::printf("far terrain (%zu pixels beyond %.0f m), eye moved 5 cm: drawn colours change by %.2f levels on average "
              "(%.2f from the squares' average colour), point samples of the orthophoto by %.1f\n",
              far.pixels, kFarM, far.drawnChange, far.fromAverage, far.pointChange);
  ASSERT_GT(far.pixels, 1000u);
  // The bound: 2 levels on average (each far texel is about a pixel of the squares' average, so a
  // 5 cm move shifts each pixel's bilinear sample within a texel of a nearly even image), and the
  // colour drawn is that average; point samples change by 29 levels (two in five flip).
  EXPECT_LT(far.drawnChange, 2.0);
  EXPECT_LT(far.fromAverage, 6.0) << "far texels are not the squares' average";
  EXPECT_GT(far.pointChange, 20.0) << "the region is not one that would shimmer";
}

TEST_F(ImageryTilesRender, MipLevelsKeepAPartsFartherPixelsFromShimmering) {
  // Between 30 and 100 m a part's tile is chosen for its nearest point, so its farther pixels cover
  // several of its texels: sampled at the tile's own texels they alias (and shimmer as the eye
  // moves); with the tile's mip levels each pixel samples its own footprint's level.
  const Scene scene = makeScene(kShimmerSquareM, 0.125, 400.0);
  RenderOptions plain = options();
  plain.imageryMipmaps = false;
  const ShimmerBand mip = shimmer(scene, options(), pose(-4), 30, 100);
  const ShimmerBand own = shimmer(scene, plain, pose(-4), 30, 100);
  std::printf("30 to 100 m (%zu pixels), eye moved 5 cm: drawn colours change by %.2f levels with mip levels, %.2f "
              "without (%.2f and %.2f from the squares' average), point samples by %.1f\n",
              mip.pixels, mip.drawnChange, own.drawnChange, mip.fromAverage, own.fromAverage, mip.pointChange);
  ASSERT_GT(mip.pixels, 1000u);
  EXPECT_EQ(mip.pixels, own.pixels);
  EXPECT_LT(mip.drawnChange, 0.5 * own.drawnChange);
  EXPECT_LT(mip.fromAverage, 0.5 * own.fromAverage);
}

TEST_F(ImageryTilesRender, ImageryElsewhereIsRefusedNamingTheFileBeforeAFrame) {
  Scene scene = makeScene();
  // The same orthophoto 10 km east: it drapes nothing.
  const std::string elsewhere = (dir() / "elsewhere.tif").string();
  terrain::writeImageryCog(elsewhere, 64, 64, std::vector<std::uint8_t>(64 * 64 * 3, 128), kEyeX + 10000, kEyeY, 0.5,
                           0.5, "EPSG:32633", false);
  scene.drapedImagery = elsewhere;
  try {
    ViewRenderer renderer(scene, options());
    FAIL() << "an orthophoto beside the terrain was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(elsewhere + ": does not overlap the terrain"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nestwalk
