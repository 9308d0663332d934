// terrain/mining_dump_ortho and the generator's surfaces (terrain/mining_dump.h): each sample's
// surface agrees with the heights the generator produced, measured independently (slopes from the
// grid, levels from the layout: tops and berms flat at their levels, faces at 35 degrees, the ramp at
// its grade, the ditch a trough), and the orthophoto's colour at a sample is its surface's material
// (the nearest base colour of a 3 x 3 average), deterministic from the seed; a drone's finer
// orthophoto (writeFineMiningDumpOrtho), read back through GDAL, is on the area's edges at its
// pixel, shows the materials the generator finds at its pixels and carries texture.
#include "nestwalk/terrain/mining_dump.h"
#include "nestwalk/terrain/mining_dump_ortho.h"
#include "tests/scene/scene_test_util.h"

#include <gdal.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>

namespace nestwalk::test {
namespace {

using terrain::DumpSurface;

/// Metres: heights of a flat surface against its level (the generator's roughness is 5 cm).
constexpr double kLevelTolerance = 0.15;
/// Degrees: the steepest slope of a flat surface over one cell (5 cm of roughness over 2 m).
constexpr double kFlatSlopeDeg = 3.0;
/// Degrees: a face's slope over two cells against its 35 degrees (roughness over 2 m).
constexpr double kFaceSlopeToleranceDeg = 3.0;
/// Share of the samples that must pass each check (a few sit where the roughness peaks).
constexpr double kRequiredShare = 0.99;

const terrain::MiningDump& dump() {
  static const terrain::MiningDump d = terrain::generateMiningDump(terrain::MiningDumpParams{});
  return d;
}

struct Probe {
  const terrain::MiningDump& d;
  double h(int c, int r) const { return d.heights[std::size_t(r) * std::size_t(d.cols) + std::size_t(c)]; }
  DumpSurface s(int c, int r) const { return d.surfaces[std::size_t(r) * std::size_t(d.cols) + std::size_t(c)]; }
  /// Slope in degrees from central differences over two cells.
  double slopeDeg(int c, int r) const {
    const double gx = (h(c + 1, r) - h(c - 1, r)) / (2 * d.cell), gy = (h(c, r - 1) - h(c, r + 1)) / (2 * d.cell);
    return std::atan(std::hypot(gx, gy)) * 180.0 / std::numbers::pi;
  }
  /// Metres: the mean height of the samples of other surfaces within 3 cells, less this sample's
  /// (NaN when there are none): how far it lies below what surrounds its surface.
  double relief(int c, int r) const {
    double sum = 0;
    int n = 0;
    for (int dr = -3; dr <= 3; ++dr)
      for (int dc = -3; dc <= 3; ++dc)
        if (s(c + dc, r + dr) != s(c, r)) sum += h(c + dc, r + dr), ++n;
    return n ? sum / n - h(c, r) : std::nan("");
  }
  /// Whether the samples within `k` cells all have this one's surface.
  bool uniform(int c, int r, int k) const {
    for (int dr = -k; dr <= k; ++dr)
      for (int dc = -k; dc <= k; ++dc)
        if (s(c + dc, r + dr) != s(c, r)) return false;
    return true;
  }
};

TEST(MiningDumpSurfaces, AgreeWithTheGeneratedHeights) {
  const terrain::MiningDump& d = dump();
  const Probe p{d};
  ASSERT_EQ(d.surfaces.size(), d.heights.size());
  const auto& L = d.layout;
  const int benches = int(std::lround((L.topHeight - L.baseHeight) / 10.0));
  std::map<DumpSurface, std::array<int, 2>> tally;  // surface -> {checked, passed}
  double ditchRelief = 0;
  int ditchSamples = 0;
  for (int r = 3; r < d.rows - 3; ++r)
    for (int c = 3; c < d.cols - 3; ++c) {
      const DumpSurface s = p.s(c, r);
      // Away from where surfaces meet (but all of the ditch, which is only 4 m wide).
      if (s != DumpSurface::Ditch && !p.uniform(c, r, 1)) continue;
      const double h = p.h(c, r), slope = p.slopeDeg(c, r);
      bool ok = true;
      switch (s) {
        case DumpSurface::Top:
          ok = std::abs(h - L.topHeight) < kLevelTolerance && slope < kFlatSlopeDeg;
          break;
        case DumpSurface::Berm: {
          const double k = std::round((h - L.baseHeight) / 10.0);
          ok = k >= 1 && k < benches && std::abs(h - (L.baseHeight + 10.0 * k)) < kLevelTolerance && slope < kFlatSlopeDeg;
          break;
        }
        case DumpSurface::Face:
        case DumpSurface::RampSide:
          ok = std::abs(slope - 35.0) < kFaceSlopeToleranceDeg;
          break;
        case DumpSurface::Ramp:
          ok = slope > 3.0 && slope < 9.0;  // a 10 % grade: 5.7 degrees
          break;
        case DumpSurface::Ditch: {
          // Never above what surrounds it (its edges are only centimetres deep, within the roughness),
          // and 1.5 m deep at its axis: on average well below.
          const double relief = p.relief(c, r);
          ok = !(relief < -kLevelTolerance);
          if (!std::isnan(relief)) ditchRelief += relief, ++ditchSamples;
          break;
        }
        case DumpSurface::Pit:
          ok = slope > 20.0 || h < p.h(c + 2, r) + 0.5;  // walls, or a floor below its rim
          break;
        case DumpSurface::Ground:
          ok = slope < 6.0;  // gentle natural ground
          break;
      }
      ++tally[s][0];
      tally[s][1] += ok;
    }
  for (int k = 0; k < terrain::kDumpSurfaceCount; ++k) {
    const auto s = DumpSurface(k);
    const auto [checked, passed] = tally[s];
    std::printf("[ surfaces ] %-9s %7d samples, %7d as the heights say\n", terrain::dumpSurfaceName(s), checked, passed);
    EXPECT_GT(checked, 50) << terrain::dumpSurfaceName(s) << ": every surface is there";
    EXPECT_GE(passed, kRequiredShare * checked) << terrain::dumpSurfaceName(s);
  }
  ASSERT_GT(ditchSamples, 0);
  std::printf("[ surfaces ] the ditch lies %.3f m below its surroundings on average\n", ditchRelief / ditchSamples);
  EXPECT_GT(ditchRelief / ditchSamples, 0.4);
}

TEST(MiningDumpOrtho, ColoursAreTheSurfacesMaterials) {
  const terrain::MiningDump& d = dump();
  const Probe p{d};
  const std::vector<std::uint8_t> rgb = terrain::miningDumpOrtho(d, 7);
  ASSERT_EQ(rgb.size(), d.heights.size() * 3u);
  std::array<int, terrain::kDumpSurfaceCount> checked{}, right{};
  for (int r = 1; r < d.rows - 1; ++r)
    for (int c = 1; c < d.cols - 1; ++c) {
      if (!p.uniform(c, r, 1)) continue;
      double mean[3] = {0, 0, 0};
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc)
          for (int k = 0; k < 3; ++k)
            mean[k] += rgb[(std::size_t(r + dr) * std::size_t(d.cols) + std::size_t(c + dc)) * 3u + std::size_t(k)] / 9.0;
      int nearest = 0;
      double best = 1e9;
      for (int m = 0; m < terrain::kDumpSurfaceCount; ++m) {
        const auto& base = terrain::kDumpSurfaceColours[std::size_t(m)];
        const double dist = std::hypot(mean[0] - base[0], mean[1] - base[1], mean[2] - base[2]);
        if (dist < best) best = dist, nearest = m;
      }
      const int s = int(p.s(c, r));
      ++checked[std::size_t(s)];
      right[std::size_t(s)] += nearest == s;
    }
  for (int s = 0; s < terrain::kDumpSurfaceCount; ++s) {
    EXPECT_GT(checked[std::size_t(s)], 0) << terrain::dumpSurfaceName(DumpSurface(s));
    EXPECT_EQ(right[std::size_t(s)], checked[std::size_t(s)]) << terrain::dumpSurfaceName(DumpSurface(s));
  }
  // The top is lighter than the faces (the tops light grey-brown, the faces a darker ochre).
  const auto& top = terrain::kDumpSurfaceColours[std::size_t(DumpSurface::Top)];
  const auto& face = terrain::kDumpSurfaceColours[std::size_t(DumpSurface::Face)];
  EXPECT_GT(top[0] + top[1] + top[2], face[0] + face[1] + face[2] + 100);
}

TEST(MiningDumpOrtho, SameSeedSameBytes) {
  const terrain::MiningDump& d = dump();
  EXPECT_EQ(terrain::miningDumpOrtho(d, 7), terrain::miningDumpOrtho(d, 7));
  EXPECT_NE(terrain::miningDumpOrtho(d, 7), terrain::miningDumpOrtho(d, 8));
  terrain::MiningDump broken = d;
  broken.surfaces.pop_back();
  EXPECT_THROW(terrain::miningDumpOrtho(broken, 7), std::invalid_argument);
}

/// Tyre tracks on the ramp (mining_dump_ortho.h) in an orthophoto read back: from the layout's ramp,
/// the pixels surely inside a wheel path (within its half width less the wander and the fading edge
/// of its nominal centre) against those surely between them (on a lane's centre line or the ramp's
/// axis); in a track, the light of the tread's lugs against the gaps between them (by the pixel
/// centre's distance along the ramp).
struct TrackLight {
  double darkening = 0, tread = 0;  // track / between; lugs / gaps
  int trackPixels = 0, betweenPixels = 0;
};
TrackLight trackLight(const std::vector<std::uint8_t>& rgb, int n, double pixel, const terrain::MiningDumpGenerator& generator) {
  std::vector<float> heights(std::size_t(n) * std::size_t(n));
  std::vector<DumpSurface> surfaces(heights.size());
  generator.generateRows(0, n, heights.data(), surfaces.data());
  const terrain::MiningDumpLayout& L = generator.layout();
  const double az = L.azimuthDeg * std::numbers::pi / 180.0;
  const double sure = 0.5 * terrain::kOrthoTrackWidthM - terrain::kOrthoTrackWanderM - terrain::kOrthoTrackEdgeM;
  double light[4] = {0, 0, 0, 0};  // track, between, lug, gap
  int count[4] = {0, 0, 0, 0};
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const std::size_t at = std::size_t(y) * std::size_t(n) + std::size_t(x);
      if (surfaces[at] != DumpSurface::Ramp) continue;
      const double de = generator.originX() + x * pixel - L.centreE, dn = generator.originY() - y * pixel - L.centreN;
      const double u = de * std::sin(az) + dn * std::cos(az), across = de * std::cos(az) - dn * std::sin(az) - L.rampV;
      const double l = (rgb[3 * at] + rgb[3 * at + 1] + rgb[3 * at + 2]) / 3.0;
      const double wheel = std::min(std::abs(std::abs(across) - (terrain::kOrthoLaneOffsetM - 0.5 * terrain::kOrthoWheelGaugeM)),
                                    std::abs(std::abs(across) - (terrain::kOrthoLaneOffsetM + 0.5 * terrain::kOrthoWheelGaugeM)));
      const double between = std::min(std::abs(across), std::abs(std::abs(across) - terrain::kOrthoLaneOffsetM));
      if (wheel < sure) {
        light[0] += l, ++count[0];
        const int k = std::sin(2 * std::numbers::pi * u / terrain::kOrthoTreadPitchM) > 0 ? 2 : 3;
        light[k] += l, ++count[k];
      } else if (between < 0.5) {
        light[1] += l, ++count[1];
      }
    }
  for (int k = 0; k < 4; ++k) EXPECT_GT(count[k], 500) << k;
  TrackLight t;
  t.darkening = (light[0] / std::max(count[0], 1)) / (light[1] / std::max(count[1], 1));
  t.tread = (light[2] / std::max(count[2], 1)) / (light[3] / std::max(count[3], 1));
  t.trackPixels = count[0];
  t.betweenPixels = count[1];
  return t;
}

/// The n x n RGB pixels of an orthophoto through GDAL (empty when they cannot be read).
std::vector<std::uint8_t> readRgb(GDALDatasetH ds, int n) {
  std::vector<std::uint8_t> rgb(std::size_t(n) * std::size_t(n) * 3u);
  int bands[3] = {1, 2, 3};
  if (GDALDatasetRasterIO(ds, GF_Read, 0, 0, n, n, rgb.data(), n, n, GDT_Byte, 3, bands, 3, 3 * n, 1) != CE_None) rgb.clear();
  return rgb;
}

class FineMiningDumpOrtho : public TempFolderTest {};

TEST_F(FineMiningDumpOrtho, ShowsTheGeneratorsMaterialsAtItsPixelsWithTexture) {
  terrain::MiningDumpParams params;
  params.size = 400;
  constexpr double kPixel = 0.25;
  const std::string path = (dir() / "ortho.tif").string();
  terrain::writeFineMiningDumpOrtho(path, params, kPixel, terrain::kMiningDumpCrs, false);
  EXPECT_THROW(terrain::writeFineMiningDumpOrtho(path, params, kPixel, terrain::kMiningDumpCrs, false), InputError);

  GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
  ASSERT_NE(ds, nullptr);
  const int n = GDALGetRasterXSize(ds);
  ASSERT_EQ(n, 1600);
  ASSERT_EQ(GDALGetRasterYSize(ds), n);
  double gt[6];
  ASSERT_EQ(GDALGetGeoTransform(ds, gt), CE_None);
  EXPECT_DOUBLE_EQ(gt[0], params.centreE - 200);  // the area's west and north edges
  EXPECT_DOUBLE_EQ(gt[3], params.centreN + 200);
  EXPECT_DOUBLE_EQ(gt[1], kPixel);
  EXPECT_DOUBLE_EQ(gt[5], -kPixel);
  EXPECT_GT(GDALGetOverviewCount(GDALGetRasterBand(ds, 1)), 0);
  const std::vector<std::uint8_t> rgb = readRgb(ds, n);
  GDALClose(ds);
  ASSERT_FALSE(rgb.empty());

  // The generator's own materials at the pixels' centres.
  terrain::MiningDumpParams fine = params;
  fine.cell = kPixel;
  const terrain::MiningDumpGenerator generator(fine);
  std::vector<float> heights(rgb.size() / 3);
  std::vector<DumpSurface> surfaces(heights.size());
  generator.generateRows(0, n, heights.data(), surfaces.data());
  // 1 m blocks of one material (4 x 4 pixels and a pixel around them): the nearest base colour (or
  // the vegetation's, on the ground and the top) of their mean is their material; the spread of
  // their light within them is the texture (the per-pixel grain alone is 3 levels).
  std::array<int, terrain::kDumpSurfaceCount> checked{}, right{};
  double spread = 0;
  int spreadBlocks = 0;
  for (int by = 1; by + 5 < n; by += 4)
    for (int bx = 1; bx + 5 < n; bx += 4) {
      const DumpSurface s = surfaces[std::size_t(by) * std::size_t(n) + std::size_t(bx)];
      bool uniform = true;
      for (int y = by - 1; y < by + 5 && uniform; ++y)
        for (int x = bx - 1; x < bx + 5; ++x) uniform = uniform && surfaces[std::size_t(y) * std::size_t(n) + std::size_t(x)] == s;
      if (!uniform) continue;
      double mean[3] = {0, 0, 0}, light = 0, light2 = 0;
      for (int y = by; y < by + 4; ++y)
        for (int x = bx; x < bx + 4; ++x) {
          const std::uint8_t* p = &rgb[(std::size_t(y) * std::size_t(n) + std::size_t(x)) * 3u];
          for (int k = 0; k < 3; ++k) mean[k] += p[k] / 16.0;
          const double l = (p[0] + p[1] + p[2]) / 3.0;
          light += l / 16.0;
          light2 += l * l / 16.0;
        }
      auto distance = [&](const std::array<std::uint8_t, 3>& c) { return std::hypot(mean[0] - c[0], mean[1] - c[1], mean[2] - c[2]); };
      int nearest = 0;
      for (int m = 1; m < terrain::kDumpSurfaceCount; ++m)
        if (distance(terrain::kDumpSurfaceColours[std::size_t(m)]) < distance(terrain::kDumpSurfaceColours[std::size_t(nearest)]))
          nearest = m;
      // Vegetation blends the ground and the top towards its green: their mean lies nearer the
      // segment from their base colour to the green than any other material's colour.
      bool vegetated = false;
      if (s == DumpSurface::Ground || s == DumpSurface::Top) {
        const auto& a = terrain::kDumpSurfaceColours[std::size_t(s)];
        const auto& g = terrain::kOrthoVegetationColour;
        double t = 0, len2 = 0;
        for (int k = 0; k < 3; ++k) {
          t += (mean[k] - a[std::size_t(k)]) * (g[std::size_t(k)] - a[std::size_t(k)]);
          len2 += double(g[std::size_t(k)] - a[std::size_t(k)]) * (g[std::size_t(k)] - a[std::size_t(k)]);
        }
        t = std::clamp(t / len2, 0.0, 1.0);
        double toSegment = 0;
        for (int k = 0; k < 3; ++k) {
          const double d = mean[k] - (a[std::size_t(k)] + t * (g[std::size_t(k)] - a[std::size_t(k)]));
          toSegment += d * d;
        }
        vegetated = true;
        for (int m = 0; m < terrain::kDumpSurfaceCount; ++m)
          if (m != int(s) && distance(terrain::kDumpSurfaceColours[std::size_t(m)]) < std::sqrt(toSegment)) vegetated = false;
      }
      ++checked[std::size_t(s)];
      right[std::size_t(s)] += nearest == int(s) || vegetated;
      if (s == DumpSurface::Face) {
        spread += std::sqrt(std::max(0.0, light2 - light * light));
        ++spreadBlocks;
      }
    }
  for (DumpSurface s : {DumpSurface::Ground, DumpSurface::Face, DumpSurface::Berm, DumpSurface::Top}) {
    ASSERT_GT(checked[std::size_t(s)], 100) << terrain::dumpSurfaceName(s);
    std::printf("%s: %d of %d one-metre blocks\n", terrain::dumpSurfaceName(s), right[std::size_t(s)], checked[std::size_t(s)]);
    // Stones (a tenth of the area, 0.65 or 1.3 times the colour) pull a block's mean off its
    // material where they gather.
    EXPECT_GE(double(right[std::size_t(s)]) / checked[std::size_t(s)], 0.9) << terrain::dumpSurfaceName(s);
  }
  ASSERT_GT(spreadBlocks, 100);
  EXPECT_GT(spread / spreadBlocks, 6.0) << "the faces show no texture within a metre";
  std::printf("light spread within a metre of face: %.1f levels\n", spread / spreadBlocks);

  const TrackLight tracks = trackLight(rgb, n, kPixel, generator);
  std::printf("tyre tracks at %.2f m: %.3f of the light between them, lugs %.3f of the gaps (%d and %d pixels)\n", kPixel,
              tracks.darkening, tracks.tread, tracks.trackPixels, tracks.betweenPixels);
  EXPECT_NEAR(tracks.darkening, terrain::kOrthoTrackDarkening, 0.05);
  EXPECT_NEAR(tracks.tread, 1.0, 0.02) << "a tread at 25 cm pixels, which would beat instead of showing lugs";
}

TEST_F(FineMiningDumpOrtho, TyreTracksShowTheirTreadAtTenCentimetres) {
  terrain::MiningDumpParams params;
  params.size = 250;
  constexpr double kPixel = 0.1;
  const std::string path = (dir() / "ortho.tif").string();
  terrain::writeFineMiningDumpOrtho(path, params, kPixel, terrain::kMiningDumpCrs, false);
  GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
  ASSERT_NE(ds, nullptr);
  const int n = GDALGetRasterXSize(ds);
  ASSERT_EQ(n, 2500);
  const std::vector<std::uint8_t> rgb = readRgb(ds, n);
  GDALClose(ds);
  ASSERT_FALSE(rgb.empty());
  terrain::MiningDumpParams fine = params;
  fine.cell = kPixel;
  const TrackLight tracks = trackLight(rgb, n, kPixel, terrain::MiningDumpGenerator(fine));
  std::printf("tyre tracks at %.2f m: %.3f of the light between them, lugs %.3f of the gaps (%d and %d pixels)\n", kPixel,
              tracks.darkening, tracks.tread, tracks.trackPixels, tracks.betweenPixels);
  EXPECT_NEAR(tracks.darkening, terrain::kOrthoTrackDarkening, 0.05);
  EXPECT_NEAR(tracks.tread, (1 + terrain::kOrthoTreadAmplitude) / (1 - terrain::kOrthoTreadAmplitude), 0.05);
}

}  // namespace
}  // namespace nestwalk::test
