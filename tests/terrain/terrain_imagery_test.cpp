// terrain/terrain_imagery: imagery read onto terrain grids. GDAL's own warp (GDALWarp, gdalwarp's
// library form, -r bilinear onto the same grid) is the oracle of reprojected reads, and PROJ through
// OSR with the imagery's analytic colour pattern a second one, independent of GDAL's warper; pixel
// values written into the test rasters are the oracle of same-frame reads at pixel centres. Also:
// grey, grey and alpha, RGB, RGBA, nodata, 16-bit scaling, overviews used by coarse reads, the
// imagery's edges, warnings, and bad files refused with their names.
#include "nestwalk/core/input_error.h"
#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/terrain/imagery_import.h"
#include "nestwalk/terrain/terrain_imagery.h"
#include "tests/common/input_error_of.h"
#include "tests/common/temp_folder.h"

#include <gdal.h>
#include <cpl_conv.h>
#include <gdal_utils.h>
#include <ogr_srs_api.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace nestwalk::test {
namespace {

namespace fs = std::filesystem;
using terrain::TerrainImagery;

/// 8-bit levels: GDAL's warp and a read of the same grid run the same warper; they may differ by the
/// final rounding of a bilinear value (working in floating point against working in bytes).
constexpr int kWarpAgreementLevels = 1;
/// 8-bit levels: a reprojected read against the analytic pattern at the exact (PROJ) position:
/// bilinear interpolation of the pattern's samples (at most 1/8 of the pixel size squared times its
/// curvature, 0.2 level here), the warper's approximate transformer (1/8 pixel times the pattern's
/// gradient, 1.4 levels), the samples' and the result's rounding (0.5 each).
constexpr double kAnalyticLevels = 3.0;
/// 8-bit levels: same-frame reads between pixel centres against GDAL's warp (both bilinear between the
/// same centres; rounding only).
constexpr int kSameFrameAgreementLevels = 1;

// The site: UTM zone 33N around 62.1 N, 16.2 E (60 km east of the zone's central meridian, so grid
// north and true north differ by about a degree and the warp is not a plain scaling).
constexpr double kSiteLon = 16.2, kSiteLat = 62.1;

std::string wktOf(int epsg) {
  OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
  EXPECT_EQ(OSRImportFromEPSG(srs, epsg), OGRERR_NONE);
  char* wkt = nullptr;
  OSRExportToWkt(srs, &wkt);
  std::string out = wkt ? wkt : "";
  CPLFree(wkt);
  OSRDestroySpatialReference(srs);
  return out;
}

/// Transforms points between two EPSG CRSs through PROJ (OSR), in GIS order (longitude first).
std::array<double, 2> transformPoint(int fromEpsg, int toEpsg, double x, double y) {
  OGRSpatialReferenceH a = OSRNewSpatialReference(nullptr), b = OSRNewSpatialReference(nullptr);
  OSRImportFromEPSG(a, fromEpsg);
  OSRImportFromEPSG(b, toEpsg);
  OSRSetAxisMappingStrategy(a, OAMS_TRADITIONAL_GIS_ORDER);
  OSRSetAxisMappingStrategy(b, OAMS_TRADITIONAL_GIS_ORDER);
  OGRCoordinateTransformationH t = OCTNewCoordinateTransformation(a, b);
  EXPECT_NE(t, nullptr);
  double z = 0;
  EXPECT_TRUE(OCTTransform(t, 1, &x, &y, &z));
  OCTDestroyCoordinateTransformation(t);
  OSRDestroySpatialReference(a);
  OSRDestroySpatialReference(b);
  return {x, y};
}

struct RasterSpec {
  int cols = 0, rows = 0, bands = 3;
  GDALDataType type = GDT_Byte;
  std::array<double, 6> gt{0, 1, 0, 0, 0, -1};
  bool hasGeoTransform = true;
  std::string wkt;
  std::optional<double> noData;
  bool alphaLast = false;  // mark the last band as alpha
  std::vector<std::string> options;
};

/// Writes a GeoTIFF whose band b (1-based) holds value(c, r, b) at pixel (c, r).
void writeRaster(const fs::path& path, const RasterSpec& s, const std::function<double(int, int, int)>& value) {
  terrain::initGdal();
  std::vector<const char*> options;
  for (const auto& o : s.options) options.push_back(o.c_str());
  options.push_back(nullptr);
  GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), path.c_str(), s.cols, s.rows, s.bands, s.type,
                               const_cast<char**>(options.data()));
  ASSERT_NE(ds, nullptr) << path;
  if (s.hasGeoTransform) {
    double gt[6];
    std::copy(s.gt.begin(), s.gt.end(), gt);
    GDALSetGeoTransform(ds, gt);
  }
  if (!s.wkt.empty()) GDALSetProjection(ds, s.wkt.c_str());
  std::vector<double> line(std::size_t(s.cols) * std::size_t(s.rows));
  for (int b = 1; b <= s.bands; ++b) {
    GDALRasterBandH band = GDALGetRasterBand(ds, b);
    if (s.alphaLast && b == s.bands) GDALSetRasterColorInterpretation(band, GCI_AlphaBand);
    if (s.noData) GDALSetRasterNoDataValue(band, *s.noData);
    for (int r = 0; r < s.rows; ++r)
      for (int c = 0; c < s.cols; ++c) line[std::size_t(r) * std::size_t(s.cols) + std::size_t(c)] = value(c, r, b);
    ASSERT_EQ(GDALRasterIO(band, GF_Write, 0, 0, s.cols, s.rows, line.data(), s.cols, s.rows, GDT_Float64, 0, 0),
              CE_None);
  }
  GDALClose(ds);
}

/// A read's grid: pixel (i, j) at (x0 + i * dx, y0 - j * dy).
struct Grid {
  double x0 = 0, y0 = 0, dx = 1, dy = 1;
  int w = 1, h = 1;
};

/// GDAL's own warp of `src` onto `grid` in `dstWkt`: bilinear, with a destination alpha, no
/// overviews: RGBA bytes like TerrainImagery::read (grey expanded to R = G = B; no alpha: 255).
std::vector<std::uint8_t> gdalWarpOracle(const fs::path& src, const std::string& dstWkt, const Grid& g) {
  GDALDatasetH in = GDALOpen(src.c_str(), GA_ReadOnly);
  EXPECT_NE(in, nullptr);
  char buf[6][64];
  std::snprintf(buf[0], 64, "%.10f", g.x0 - 0.5 * g.dx);
  std::snprintf(buf[1], 64, "%.10f", g.y0 - (g.h - 0.5) * g.dy);
  std::snprintf(buf[2], 64, "%.10f", g.x0 + (g.w - 0.5) * g.dx);
  std::snprintf(buf[3], 64, "%.10f", g.y0 + 0.5 * g.dy);
  std::snprintf(buf[4], 64, "%d", g.w);
  std::snprintf(buf[5], 64, "%d", g.h);
  const char* args[] = {"-of", "MEM", "-t_srs", dstWkt.c_str(), "-te", buf[0], buf[1], buf[2], buf[3],
                        "-ts", buf[4], buf[5], "-r", "bilinear", "-dstalpha", "-ovr", "NONE", nullptr};
  GDALWarpAppOptions* options = GDALWarpAppOptionsNew(const_cast<char**>(args), nullptr);
  int usageError = 0;
  GDALDatasetH out = GDALWarp("", nullptr, 1, &in, options, &usageError);
  GDALWarpAppOptionsFree(options);
  EXPECT_NE(out, nullptr) << CPLGetLastErrorMsg();
  std::vector<std::uint8_t> rgba(std::size_t(g.w) * std::size_t(g.h) * 4u, 0);
  if (out) {
    const int bands = GDALGetRasterCount(out);  // colour bands + the alpha
    std::vector<std::uint8_t> band(std::size_t(g.w) * std::size_t(g.h));
    for (int b = 1; b <= bands; ++b) {
      EXPECT_EQ(GDALRasterIO(GDALGetRasterBand(out, b), GF_Read, 0, 0, g.w, g.h, band.data(), g.w, g.h, GDT_Byte, 0, 0),
                CE_None);
      const bool alpha = b == bands;
      for (std::size_t p = 0; p < band.size(); ++p) {
        if (alpha) rgba[p * 4 + 3] = band[p];
        else if (bands == 2) rgba[p * 4] = rgba[p * 4 + 1] = rgba[p * 4 + 2] = band[p];
        else rgba[p * 4 + std::size_t(b - 1)] = band[p];
      }
    }
    GDALClose(out);
  }
  GDALClose(in);
  return rgba;
}

std::vector<std::uint8_t> readGrid(TerrainImagery& imagery, const Grid& g) {
  return imagery.read(g.x0, g.y0, g.dx, g.dy, g.w, g.h);
}

std::array<int, 4> pixelAt(const std::vector<std::uint8_t>& rgba, const Grid& g, int i, int j) {
  const std::size_t p = (std::size_t(j) * std::size_t(g.w) + std::size_t(i)) * 4u;
  return {rgba[p], rgba[p + 1], rgba[p + 2], rgba[p + 3]};
}

// ---- The geographic imagery over the UTM site -------------------------------------------------

// EPSG:4326 pixels of 2e-5 degrees of longitude (1.04 m at 62.1 N) by 1e-5 of latitude (1.11 m),
// 600 x 600 pixels around the site.
constexpr int kGeoCols = 600, kGeoRows = 600;
constexpr double kGeoDLon = 2e-5, kGeoDLat = 1e-5;
constexpr double kGeoWest = kSiteLon - 0.5 * kGeoCols * kGeoDLon, kGeoNorth = kSiteLat + 0.5 * kGeoRows * kGeoDLat;

/// The smooth pattern at continuous pixel coordinates (u, v) (pixel c's centre is u = c + 0.5).
std::array<double, 3> smoothColour(double u, double v) {
  const double tau = 2 * std::numbers::pi;
  return {128 + 90 * std::sin(tau * u / 53.0) * std::cos(tau * v / 41.0), 128 + 80 * std::cos(tau * (u + v) / 67.0),
          120 + 60 * std::sin(tau * v / 29.0)};
}
/// Sharp features: a red and a blue square and a one-pixel white line (pixel ranges, inclusive).
bool inRed(int c, int r) { return c >= 200 && c < 240 && r >= 300 && r < 340; }
bool inBlue(int c, int r) { return c >= 400 && c < 430 && r >= 200 && r < 240; }
bool onLine(int c, int) { return c == 100; }
bool nearSharp(double u, double v, double margin) {
  auto near = [&](double c0, double c1, double r0, double r1) {
    return u > c0 - margin && u < c1 + margin && v > r0 - margin && v < r1 + margin;
  };
  return near(200, 240, 300, 340) || near(400, 430, 200, 240) || (u > 100 - margin && u < 101 + margin);
}
double geoPixel(int c, int r, int b) {
  if (inRed(c, r)) return std::array<double, 3>{250, 10, 10}[std::size_t(b - 1)];
  if (inBlue(c, r)) return std::array<double, 3>{10, 20, 240}[std::size_t(b - 1)];
  if (onLine(c, r)) return 255;
  return std::round(smoothColour(c + 0.5, r + 0.5)[std::size_t(b - 1)]);
}

RasterSpec geoSpec() {
  RasterSpec s;
  s.cols = kGeoCols;
  s.rows = kGeoRows;
  s.gt = {kGeoWest, kGeoDLon, 0, kGeoNorth, 0, -kGeoDLat};
  s.wkt = wktOf(4326);
  return s;
}

/// The UTM grid read in the tests: 2 m pixels, 200 x 150, centred on the site (whole metres).
Grid siteGrid() {
  const auto utm = transformPoint(4326, 32633, kSiteLon, kSiteLat);
  Grid g;
  g.dx = g.dy = 2.0;
  g.w = 200;
  g.h = 150;
  g.x0 = std::round(utm[0]) - 0.5 * (g.w - 1) * g.dx;
  g.y0 = std::round(utm[1]) + 0.5 * (g.h - 1) * g.dy;
  return g;
}

TEST(TerrainImagery, ReprojectedReadIsGdalsWarpOfTheSameGrid) {
  const TempFolder folder;
  const fs::path file = folder / "ortho_4326.tif";
  writeRaster(file, geoSpec(), geoPixel);
  const std::string utm = wktOf(32633);
  TerrainImagery imagery(file.string(), utm);
  EXPECT_TRUE(imagery.reprojected());
  EXPECT_TRUE(imagery.warnings().empty());
  EXPECT_EQ(imagery.colourBands(), 3);
  EXPECT_FALSE(imagery.hasAlpha());
  EXPECT_NEAR(imagery.pixelSize(), 1.0, 0.2);  // about a metre a pixel at the site

  const Grid g = siteGrid();
  const auto ours = readGrid(imagery, g);
  const auto oracle = gdalWarpOracle(file, utm, g);
  int compared = 0, worst = 0;
  for (int j = 0; j < g.h; ++j)
    for (int i = 0; i < g.w; ++i) {
      const auto a = pixelAt(ours, g, i, j), b = pixelAt(oracle, g, i, j);
      ASSERT_EQ(b[3], 255) << "the grid lies inside the imagery";
      EXPECT_EQ(a[3], 255) << i << ", " << j;
      for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(a[std::size_t(k)] - b[std::size_t(k)]));
      ++compared;
    }
  std::printf("[ imagery  ] %d pixels against GDALWarp: largest difference %d levels\n", compared, worst);
  EXPECT_LE(worst, kWarpAgreementLevels);
}

TEST(TerrainImagery, ReprojectedReadPutsThePatternWhereProjPutsIt) {
  const TempFolder folder;
  const fs::path file = folder / "ortho_4326.tif";
  writeRaster(file, geoSpec(), geoPixel);
  TerrainImagery imagery(file.string(), wktOf(32633));
  const Grid g = siteGrid();
  const auto ours = readGrid(imagery, g);
  // The smooth pattern at every 7th pixel, away from the sharp features: the map point taken back to
  // longitude and latitude through PROJ, the pattern evaluated there.
  int checked = 0;
  double worst = 0;
  for (int j = 3; j < g.h; j += 7)
    for (int i = 2; i < g.w; i += 7) {
      const auto ll = transformPoint(32633, 4326, g.x0 + i * g.dx, g.y0 - j * g.dy);
      const double u = (ll[0] - kGeoWest) / kGeoDLon, v = (kGeoNorth - ll[1]) / kGeoDLat;
      if (nearSharp(u, v, 2.0)) continue;
      const auto want = smoothColour(u, v);
      const auto got = pixelAt(ours, g, i, j);
      for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(got[std::size_t(k)] - want[std::size_t(k)]));
      ++checked;
    }
  std::printf("[ imagery  ] %d pixels against the analytic pattern through PROJ: largest difference %.2f levels\n",
              checked, worst);
  EXPECT_GT(checked, 500);
  EXPECT_LE(worst, kAnalyticLevels);
  // The sharp features where PROJ puts them: the middle of each square has its colour exactly, and
  // the white line runs where its pixel's centre line maps.
  auto pixelOf = [&](double c, double r) {
    const auto utmPoint = transformPoint(4326, 32633, kGeoWest + c * kGeoDLon, kGeoNorth - r * kGeoDLat);
    return std::array<int, 2>{int(std::lround((utmPoint[0] - g.x0) / g.dx)), int(std::lround((g.y0 - utmPoint[1]) / g.dy))};
  };
  const auto red = pixelOf(220, 320), blue = pixelOf(415, 220);
  ASSERT_TRUE(red[0] >= 0 && red[0] < g.w && red[1] >= 0 && red[1] < g.h);
  ASSERT_TRUE(blue[0] >= 0 && blue[0] < g.w && blue[1] >= 0 && blue[1] < g.h);
  EXPECT_EQ(pixelAt(ours, g, red[0], red[1]), (std::array<int, 4>{250, 10, 10, 255}));
  EXPECT_EQ(pixelAt(ours, g, blue[0], blue[1]), (std::array<int, 4>{10, 20, 240, 255}));
  // The line is one imagery pixel (about 1 m) wide, so a read on a 0.25 m grid across it at its
  // centre line's position is white there and the pattern a pixel and a half away.
  const auto onLineUtm = transformPoint(4326, 32633, kGeoWest + 100.5 * kGeoDLon, kGeoNorth - 250.5 * kGeoDLat);
  const auto line = imagery.read(onLineUtm[0], onLineUtm[1], 0.25, 0.25, 1, 1);
  EXPECT_EQ(line[0], 255);
  EXPECT_EQ(line[1], 255);
  EXPECT_EQ(line[2], 255);
}

TEST(TerrainImagery, ReprojectedAlphaAndOutsideAreNoData) {
  const TempFolder folder;
  const fs::path file = folder / "ortho_rgba.tif";
  RasterSpec s = geoSpec();
  s.bands = 4;
  s.alphaLast = true;
  // Alpha 0 over the western third of the imagery.
  writeRaster(file, s, [](int c, int r, int b) { return b == 4 ? (c < 200 ? 0.0 : 255.0) : geoPixel(c, r, b); });
  const std::string utm = wktOf(32633);
  TerrainImagery imagery(file.string(), utm);
  EXPECT_TRUE(imagery.hasAlpha());
  Grid g = siteGrid();
  g.w = 320;  // 640 m: beyond the imagery's 626 m east-west
  g.x0 -= 120;
  const auto ours = readGrid(imagery, g);
  const auto oracle = gdalWarpOracle(file, utm, g);
  int transparent = 0, opaque = 0, outside = 0, worst = 0;
  for (int j = 0; j < g.h; ++j)
    for (int i = 0; i < g.w; ++i) {
      const auto a = pixelAt(ours, g, i, j), b = pixelAt(oracle, g, i, j);
      EXPECT_EQ(a[3], b[3]) << i << ", " << j;
      if (a[3] == 0) {
        EXPECT_EQ(a, (std::array<int, 4>{0, 0, 0, 0})) << "no data is (0, 0, 0, 0)";
        const auto ll = transformPoint(32633, 4326, g.x0 + i * g.dx, g.y0 - j * g.dy);
        const double u = (ll[0] - kGeoWest) / kGeoDLon;
        if (u < 0 || u > kGeoCols) ++outside;
        else ++transparent;
        continue;
      }
      ++opaque;
      if (b[3] == 255)
        for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(a[std::size_t(k)] - b[std::size_t(k)]));
    }
  std::printf("[ imagery  ] RGBA: %d transparent, %d outside, %d opaque; largest difference %d levels\n", transparent,
              outside, opaque, worst);
  EXPECT_GT(transparent, 1000);
  EXPECT_GT(outside, 100);
  EXPECT_GT(opaque, 10000);
  EXPECT_LE(worst, kWarpAgreementLevels);
}

// ---- Same frame ---------------------------------------------------------------------------------

/// A UTM raster at the site: `cols` x `rows` pixels of `cell` metres, its north-west corner at whole
/// metres.
RasterSpec utmSpec(int cols, int rows, double cell, int bands, GDALDataType type = GDT_Byte) {
  const auto utm = transformPoint(4326, 32633, kSiteLon, kSiteLat);
  RasterSpec s;
  s.cols = cols;
  s.rows = rows;
  s.bands = bands;
  s.type = type;
  s.gt = {std::round(utm[0]) - 0.5 * cols * cell, cell, 0, std::round(utm[1]) + 0.5 * rows * cell, 0, -cell};
  s.wkt = wktOf(32633);
  return s;
}

/// A deterministic byte pattern with no structure (every pixel differs from its neighbours).
double hashed(int c, int r, int b) { return double((c * 73 + r * 151 + b * 197 + c * r * 7) % 256); }

TEST(TerrainImagery, SameFrameAtPixelCentresIsThePixelsExactly) {
  const TempFolder folder;
  const RasterSpec s = utmSpec(97, 83, 0.5, 3);
  writeRaster(folder / "rgb.tif", s, hashed);
  // The same pixels stored south-up (row 0 south): read the same.
  RasterSpec south = s;
  south.gt = {s.gt[0], s.gt[1], 0, s.gt[3] - s.rows * s.gt[1], 0, s.gt[1]};
  writeRaster(folder / "rgb_south_up.tif", south, [&](int c, int r, int b) { return hashed(c, s.rows - 1 - r, b); });
  for (const char* name : {"rgb.tif", "rgb_south_up.tif"}) {
    TerrainImagery imagery((folder / name).string(), s.wkt);
    EXPECT_FALSE(imagery.reprojected());
    const double cell = s.gt[1];
    // All of it, then a part starting at pixel (5, 7).
    for (const auto& [c0, r0, w, h] : {std::array<int, 4>{0, 0, s.cols, s.rows}, std::array<int, 4>{5, 7, 31, 19}}) {
      const Grid g{s.gt[0] + (c0 + 0.5) * cell, s.gt[3] - (r0 + 0.5) * cell, cell, cell, w, h};
      const auto got = readGrid(imagery, g);
      int wrong = 0;
      for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
          const auto p = pixelAt(got, g, i, j);
          const std::array<int, 4> want{int(hashed(c0 + i, r0 + j, 1)), int(hashed(c0 + i, r0 + j, 2)),
                                        int(hashed(c0 + i, r0 + j, 3)), 255};
          wrong += p != want;
        }
      EXPECT_EQ(wrong, 0) << name << " from " << c0 << ", " << r0;
    }
  }
}

TEST(TerrainImagery, SameFrameBetweenCentresIsGdalsBilinear) {
  const TempFolder folder;
  const RasterSpec s = utmSpec(120, 90, 1.0, 3);
  const fs::path file = folder / "rgb.tif";
  writeRaster(file, s, [](int c, int r, int b) { return std::round(smoothColour(c * 3.1 + 0.5, r * 2.3 + 0.5)[std::size_t(b - 1)]); });
  TerrainImagery imagery(file.string(), s.wkt);
  // Off the centres by (0.3, 0.7) pixel at 0.8 pixel spacing, reaching past the imagery's edges.
  Grid g{s.gt[0] - 3.3, s.gt[3] + 2.7, 0.8, 0.8, 160, 120};
  const auto ours = readGrid(imagery, g);
  const auto oracle = gdalWarpOracle(file, s.wkt, g);
  int compared = 0, worst = 0, outside = 0;
  for (int j = 0; j < g.h; ++j)
    for (int i = 0; i < g.w; ++i) {
      const double x = g.x0 + i * g.dx, y = g.y0 - j * g.dy;
      const double u = (x - s.gt[0]) / s.gt[1], v = (s.gt[3] - y) / s.gt[1];
      const auto a = pixelAt(ours, g, i, j), b = pixelAt(oracle, g, i, j);
      if (u < 0 || v < 0 || u > s.cols || v > s.rows) {
        EXPECT_EQ(a, (std::array<int, 4>{0, 0, 0, 0})) << "beyond the outer edge: " << i << ", " << j;
        ++outside;
        continue;
      }
      EXPECT_EQ(a[3], 255) << i << ", " << j;
      if (b[3] != 255) continue;
      for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(a[std::size_t(k)] - b[std::size_t(k)]));
      ++compared;
    }
  std::printf("[ imagery  ] same frame: %d pixels against GDALWarp, largest difference %d levels; %d outside\n",
              compared, worst, outside);
  EXPECT_GT(compared, 10000);
  EXPECT_GT(outside, 1000);
  EXPECT_LE(worst, kSameFrameAgreementLevels);
}

TEST(TerrainImagery, GreyGreyAlphaRgbaAndNodata) {
  const TempFolder folder;
  const double cell = 1.0;
  auto centres = [&](const RasterSpec& s) { return Grid{s.gt[0] + 0.5 * cell, s.gt[3] - 0.5 * cell, cell, cell, s.cols, s.rows}; };
  {  // grey: R = G = B
    const RasterSpec s = utmSpec(40, 30, cell, 1);
    writeRaster(folder / "grey.tif", s, hashed);
    TerrainImagery imagery((folder / "grey.tif").string(), s.wkt);
    EXPECT_EQ(imagery.colourBands(), 1);
    const Grid g = centres(s);
    const auto got = readGrid(imagery, g);
    for (int j = 0; j < g.h; ++j)
      for (int i = 0; i < g.w; ++i) {
        const int v = int(hashed(i, j, 1));
        ASSERT_EQ(pixelAt(got, g, i, j), (std::array<int, 4>{v, v, v, 255})) << i << ", " << j;
      }
  }
  {  // grey and alpha: alpha as written, no colour where it is 0
    RasterSpec s = utmSpec(40, 30, cell, 2);
    s.alphaLast = true;
    auto alpha = [](int c, int r) { return (c + r) % 5 == 0 ? 0.0 : (c % 3 == 0 ? 128.0 : 255.0); };
    writeRaster(folder / "grey_alpha.tif", s, [&](int c, int r, int b) { return b == 2 ? alpha(c, r) : hashed(c, r, 1); });
    TerrainImagery imagery((folder / "grey_alpha.tif").string(), s.wkt);
    EXPECT_EQ(imagery.colourBands(), 1);
    EXPECT_TRUE(imagery.hasAlpha());
    const Grid g = centres(s);
    const auto got = readGrid(imagery, g);
    for (int j = 0; j < g.h; ++j)
      for (int i = 0; i < g.w; ++i) {
        const int v = int(hashed(i, j, 1)), a = int(alpha(i, j));
        const std::array<int, 4> want = a == 0 ? std::array<int, 4>{0, 0, 0, 0} : std::array<int, 4>{v, v, v, a};
        ASSERT_EQ(pixelAt(got, g, i, j), want) << i << ", " << j;
      }
  }
  {  // RGBA: alpha 0 areas have no data
    RasterSpec s = utmSpec(40, 30, cell, 4);
    s.alphaLast = true;
    auto alpha = [](int c, int r) { return c >= 10 && c < 20 && r >= 5 && r < 25 ? 0.0 : 255.0; };
    writeRaster(folder / "rgba.tif", s, [&](int c, int r, int b) { return b == 4 ? alpha(c, r) : hashed(c, r, b); });
    TerrainImagery imagery((folder / "rgba.tif").string(), s.wkt);
    EXPECT_EQ(imagery.colourBands(), 3);
    EXPECT_TRUE(imagery.hasAlpha());
    const Grid g = centres(s);
    const auto got = readGrid(imagery, g);
    for (int j = 0; j < g.h; ++j)
      for (int i = 0; i < g.w; ++i) {
        const std::array<int, 4> want = alpha(i, j) == 0 ? std::array<int, 4>{0, 0, 0, 0}
                                                         : std::array<int, 4>{int(hashed(i, j, 1)), int(hashed(i, j, 2)),
                                                                              int(hashed(i, j, 3)), 255};
        ASSERT_EQ(pixelAt(got, g, i, j), want) << i << ", " << j;
      }
    // Between the centres inside the transparent block (a pixel from its edge): still no data.
    const auto mid = imagery.read(s.gt[0] + 14.9, s.gt[3] - 12.2, 0.5, 0.5, 4, 4);
    for (std::size_t p = 0; p < mid.size(); ++p) EXPECT_EQ(mid[p], 0) << p;
  }
  {  // grey with a nodata value: those pixels have no data
    RasterSpec s = utmSpec(40, 30, cell, 1);
    s.noData = 7;
    auto value = [](int c, int r) { return (c * r) % 11 == 3 ? 7.0 : 100.0 + (c + 2 * r) % 100; };
    writeRaster(folder / "grey_nodata.tif", s, [&](int c, int r, int) { return value(c, r); });
    TerrainImagery imagery((folder / "grey_nodata.tif").string(), s.wkt);
    const Grid g = centres(s);
    const auto got = readGrid(imagery, g);
    int holes = 0;
    for (int j = 0; j < g.h; ++j)
      for (int i = 0; i < g.w; ++i) {
        const int v = int(value(i, j));
        const std::array<int, 4> want = v == 7 ? std::array<int, 4>{0, 0, 0, 0} : std::array<int, 4>{v, v, v, 255};
        holes += v == 7;
        ASSERT_EQ(pixelAt(got, g, i, j), want) << i << ", " << j;
      }
    EXPECT_GT(holes, 50);
  }
}

TEST(TerrainImagery, SixteenBitGreyIsScaledFromItsRange) {
  const TempFolder folder;
  const RasterSpec s = utmSpec(50, 40, 1.0, 1, GDT_UInt16);
  // 1000 .. 5000: v' = 255 (v - 1000) / 4000, rounded.
  auto value = [](int c, int r) { return 1000.0 + double((c * 37 + r * 101) % 4001); };
  double lo = 1e9, hi = -1e9;
  for (int r = 0; r < s.rows; ++r)
    for (int c = 0; c < s.cols; ++c) lo = std::min(lo, value(c, r)), hi = std::max(hi, value(c, r));
  writeRaster(folder / "grey16.tif", s, [&](int c, int r, int) { return value(c, r); });
  TerrainImagery imagery((folder / "grey16.tif").string(), s.wkt);
  const Grid g{s.gt[0] + 0.5, s.gt[3] - 0.5, 1.0, 1.0, s.cols, s.rows};
  const auto got = readGrid(imagery, g);
  for (int j = 0; j < g.h; ++j)
    for (int i = 0; i < g.w; ++i) {
      const int want = int(std::lround(255.0 * (value(i, j) - lo) / (hi - lo)));
      const auto p = pixelAt(got, g, i, j);
      ASSERT_EQ(p, (std::array<int, 4>{want, want, want, 255})) << i << ", " << j << " value " << value(i, j);
    }
}

// ---- Overviews, edges, warnings, guards ---------------------------------------------------------

/// Adds overviews 2, 4, 8 to `file` and fills every overview with `marker`: a read that takes a value
/// of `marker` read an overview.
void addMarkedOverviews(const fs::path& file, double marker) {
  GDALDatasetH ds = GDALOpen(file.c_str(), GA_Update);
  ASSERT_NE(ds, nullptr);
  int levels[] = {2, 4, 8};
  ASSERT_EQ(GDALBuildOverviews(ds, "AVERAGE", 3, levels, 0, nullptr, nullptr, nullptr), CE_None);
  for (int b = 1; b <= GDALGetRasterCount(ds); ++b) {
    GDALRasterBandH band = GDALGetRasterBand(ds, b);
    for (int k = 0; k < GDALGetOverviewCount(band); ++k) {
      GDALRasterBandH ovr = GDALGetOverview(band, k);
      const int w = GDALGetRasterBandXSize(ovr), h = GDALGetRasterBandYSize(ovr);
      std::vector<double> fill(std::size_t(w) * std::size_t(h), marker);
      ASSERT_EQ(GDALRasterIO(ovr, GF_Write, 0, 0, w, h, fill.data(), w, h, GDT_Float64, 0, 0), CE_None);
    }
  }
  GDALClose(ds);
}

TEST(TerrainImagery, CoarseReadsUseTheOverviews) {
  const TempFolder folder;
  {  // same frame: GDAL's RasterIO picks the overview
    const RasterSpec s = utmSpec(512, 512, 1.0, 1);
    const fs::path file = folder / "grey.tif";
    writeRaster(file, s, [](int, int, int) { return 100.0; });
    addMarkedOverviews(file, 200.0);
    TerrainImagery imagery(file.string(), s.wkt);
    const double cx = s.gt[0] + 256, cy = s.gt[3] - 256;
    EXPECT_EQ(imagery.read(cx - 40, cy + 40, 1.0, 1.0, 80, 80)[0], 100) << "a full-resolution read";
    EXPECT_EQ(imagery.read(cx - 200, cy + 200, 8.0, 8.0, 50, 50)[0], 200) << "a read at 8 pixels a sample";
  }
  {  // reprojected: the warper reads the overview gdalwarp -ovr AUTO would
    RasterSpec s = geoSpec();
    s.bands = 1;
    const fs::path file = folder / "grey_4326.tif";
    writeRaster(file, s, [](int, int, int) { return 100.0; });
    addMarkedOverviews(file, 200.0);
    TerrainImagery imagery(file.string(), wktOf(32633));
    const Grid g = siteGrid();
    const auto cx = g.x0 + 0.5 * (g.w - 1) * g.dx, cy = g.y0 - 0.5 * (g.h - 1) * g.dy;
    EXPECT_EQ(imagery.read(cx - 50, cy + 50, 1.0, 1.0, 100, 100)[0], 100) << "a full-resolution read";
    EXPECT_EQ(imagery.read(cx - 200, cy + 200, 10.0, 10.0, 40, 40)[0], 200) << "a read at about 9 pixels a sample";
  }
}

TEST(TerrainImagery, EdgesOfTheImagery) {
  const TempFolder folder;
  const RasterSpec s = utmSpec(10, 8, 1.0, 1);
  writeRaster(folder / "small.tif", s, [](int c, int r, int) { return 10.0 * c + r; });
  TerrainImagery imagery((folder / "small.tif").string(), s.wkt);
  const auto e = imagery.extent();
  EXPECT_DOUBLE_EQ(e.minX, s.gt[0]);
  EXPECT_DOUBLE_EQ(e.maxX, s.gt[0] + 10);
  EXPECT_DOUBLE_EQ(e.maxY, s.gt[3]);
  EXPECT_DOUBLE_EQ(e.minY, s.gt[3] - 8);
  EXPECT_DOUBLE_EQ(imagery.pixelSize(), 1.0);
  // A row along pixel row 3's centre from 1.5 m west of the imagery to 1.5 m east of it, every 0.25 m.
  const double y = s.gt[3] - 3.5;
  const auto row = imagery.read(s.gt[0] - 1.5, y, 0.25, 0.25, 53, 1);
  for (int i = 0; i < 53; ++i) {
    const double u = -1.5 + 0.25 * i;  // pixel units from the west edge
    const int value = row[std::size_t(i) * 4], alpha = row[std::size_t(i) * 4 + 3];
    if (u < 0 || u > 10) {
      EXPECT_EQ(alpha, 0) << u;
      EXPECT_EQ(value, 0) << u;
      continue;
    }
    EXPECT_EQ(alpha, 255) << u;
    // Between the outer edge and the outermost centres: the edge pixel's value; between centres the
    // linear interpolation 10 * (u - 0.5) + 3.
    const double want = 10.0 * std::clamp(u - 0.5, 0.0, 9.0) + 3.0;
    EXPECT_NEAR(value, want, 0.5) << u;
  }
  // Ten samples 0.9 pixel apart from u = 0.85: their footprints span the row from 0.4 to 9.4 of its
  // 10 pixels, as many pixels as samples: GDAL copies pixels instead of resampling when its integer
  // window is as large as the buffer, which the reader must not let happen.
  const auto spread = imagery.read(s.gt[0] + 0.85, y, 0.9, 1.0, 10, 1);
  for (int i = 0; i < 10; ++i) EXPECT_NEAR(spread[std::size_t(i) * 4], 10.0 * (0.85 + 0.9 * i - 0.5) + 3.0, 0.5) << i;
  // Coarse, 2 pixels a sample on every second pixel centre: GDAL's bilinear kernel widens to a
  // triangle two pixels in radius, which keeps a linear ramp as it is.
  const auto coarse = imagery.read(s.gt[0] + 1.5, y, 2.0, 2.0, 4, 1);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(coarse[std::size_t(i) * 4], 10.0 * (1.5 + 2.0 * i - 0.5) + 3.0, 0.5) << i;
  // Wholly outside: no data, and no GDAL read at all.
  const auto away = imagery.read(s.gt[0] + 1000, s.gt[3], 1, 1, 4, 4);
  for (auto v : away) EXPECT_EQ(v, 0);
}

TEST(TerrainImagery, MissingCrsIsTakenAsTheOtherOnesWithAWarning) {
  const TempFolder folder;
  RasterSpec s = utmSpec(20, 20, 1.0, 1);
  const std::string utm = s.wkt;
  s.wkt.clear();
  writeRaster(folder / "no_crs.tif", s, hashed);
  {
    TerrainImagery imagery((folder / "no_crs.tif").string(), utm);
    EXPECT_FALSE(imagery.reprojected());
    ASSERT_EQ(imagery.warnings().size(), 1u);
    EXPECT_NE(imagery.warnings()[0].find((folder / "no_crs.tif").string() + ": no CRS"), std::string::npos)
        << imagery.warnings()[0];
    const auto p = imagery.read(s.gt[0] + 3.5, s.gt[3] - 4.5, 1, 1, 1, 1);
    EXPECT_EQ(int(p[0]), int(hashed(3, 4, 1)));
  }
  {
    writeRaster(folder / "geo.tif", geoSpec(), geoPixel);
    TerrainImagery imagery((folder / "geo.tif").string(), "");
    EXPECT_FALSE(imagery.reprojected());
    ASSERT_EQ(imagery.warnings().size(), 1u);
    EXPECT_NE(imagery.warnings()[0].find("the terrain has no CRS"), std::string::npos) << imagery.warnings()[0];
    // Read in the imagery's own frame: degrees.
    const auto p = imagery.read(kGeoWest + 220.5 * kGeoDLon, kGeoNorth - 320.5 * kGeoDLat, kGeoDLon, kGeoDLat, 1, 1);
    EXPECT_EQ(p[0], 250);
  }
}

TEST(TerrainImagery, BadRequestsAreRefused) {
  const TempFolder folder;
  const RasterSpec s = utmSpec(8, 8, 1.0, 1);
  writeRaster(folder / "grey.tif", s, hashed);
  TerrainImagery imagery((folder / "grey.tif").string(), s.wkt);
  const double x = s.gt[0], y = s.gt[3];
  EXPECT_THROW(imagery.read(x, y, 1, 1, 0, 4), std::invalid_argument);
  EXPECT_THROW(imagery.read(x, y, 1, 1, 4, -1), std::invalid_argument);
  EXPECT_THROW(imagery.read(x, y, 1, 1, 4097, 4097), std::invalid_argument);
  EXPECT_THROW(imagery.read(std::nan(""), y, 1, 1, 4, 4), std::invalid_argument);
  EXPECT_THROW(imagery.read(x, INFINITY, 1, 1, 4, 4), std::invalid_argument);
  EXPECT_THROW(imagery.read(x, y, 0, 1, 4, 4), std::invalid_argument);
  EXPECT_THROW(imagery.read(x, y, 1, -1, 4, 4), std::invalid_argument);
  EXPECT_THROW(imagery.read(x, y, 1, std::nan(""), 4, 4), std::invalid_argument);
}

TEST(TerrainImagery, BadFilesAreRefusedWithTheirNames) {
  const TempFolder folder;
  const std::string utm = wktOf(32633);
  auto errorOf = [&](const fs::path& p) { return inputError([&] { TerrainImagery(p.string(), utm); }); };
  auto expectNamed = [](const std::string& message, const fs::path& p, const std::string& problem) {
    EXPECT_EQ(message.rfind(p.string() + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(problem), std::string::npos) << message;
  };
  writeText(folder / "notes.txt", "not a raster\n");
  expectNamed(errorOf(folder / "notes.txt"), folder / "notes.txt", "not a raster GDAL can read");
  expectNamed(errorOf(folder / "gone.tif"), folder / "gone.tif", "no such file");

  const RasterSpec five = utmSpec(8, 8, 1.0, 5);
  writeRaster(folder / "five.tif", five, hashed);
  expectNamed(errorOf(folder / "five.tif"), folder / "five.tif", "5 bands; imagery needs 1 (grey), 2");

  RasterSpec rotated = utmSpec(8, 8, 1.0, 3);
  rotated.gt[2] = 0.2;
  rotated.gt[4] = 0.1;
  writeRaster(folder / "rotated.tif", rotated, hashed);
  expectNamed(errorOf(folder / "rotated.tif"), folder / "rotated.tif", "rotated or sheared geotransform");

  RasterSpec bare = utmSpec(8, 8, 1.0, 3);
  bare.hasGeoTransform = false;
  bare.wkt.clear();
  writeRaster(folder / "bare.tif", bare, hashed);
  expectNamed(errorOf(folder / "bare.tif"), folder / "bare.tif", "no geotransform");

  RasterSpec complexBand = utmSpec(8, 8, 1.0, 1, GDT_CFloat32);
  writeRaster(folder / "complex.tif", complexBand, hashed);
  expectNamed(errorOf(folder / "complex.tif"), folder / "complex.tif", "complex samples");

  // A terrain CRS GDAL cannot read: named with the imagery file.
  writeRaster(folder / "fine.tif", utmSpec(8, 8, 1.0, 3), hashed);
  const std::string message = inputError([&] { TerrainImagery((folder / "fine.tif").string(), "NOT A CRS"); });
  expectNamed(message, folder / "fine.tif", "the terrain's CRS is not one GDAL can read");
}

TEST(TerrainImagery, WrittenImageryIsACogGdalReadsBack) {
  const TempFolder folder;
  const int cols = 1100, rows = 700;
  std::vector<std::uint8_t> rgb(std::size_t(cols) * std::size_t(rows) * 3u);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      for (int b = 0; b < 3; ++b)
        rgb[(std::size_t(r) * std::size_t(cols) + std::size_t(c)) * 3u + std::size_t(b)] = std::uint8_t(hashed(c, r, b + 1));
  const fs::path out = folder / "ortho.tif";
  terrain::writeImageryCog(out.string(), cols, rows, rgb, 550000.5, 4650000.5, 1.0, 1.0, "EPSG:32651", false);
  EXPECT_EQ(folder.entries(), std::vector<std::string>{"ortho.tif"}) << "nothing left beside it";
  GDALDatasetH ds = GDALOpen(out.c_str(), GA_ReadOnly);
  ASSERT_NE(ds, nullptr);
  EXPECT_EQ(GDALGetRasterXSize(ds), cols);
  EXPECT_EQ(GDALGetRasterYSize(ds), rows);
  ASSERT_EQ(GDALGetRasterCount(ds), 3);
  double gt[6];
  ASSERT_EQ(GDALGetGeoTransform(ds, gt), CE_None);
  EXPECT_DOUBLE_EQ(gt[0], 550000.0);
  EXPECT_DOUBLE_EQ(gt[3], 4650001.0);
  EXPECT_DOUBLE_EQ(gt[1], 1.0);
  EXPECT_DOUBLE_EQ(gt[5], -1.0);
  EXPECT_NE(std::string(GDALGetProjectionRef(ds)).find("32651"), std::string::npos);
  const char* layout = GDALGetMetadataItem(ds, "LAYOUT", "IMAGE_STRUCTURE");
  EXPECT_STREQ(layout ? layout : "", "COG");
  GDALRasterBandH band = GDALGetRasterBand(ds, 2);
  EXPECT_EQ(GDALGetRasterDataType(band), GDT_Byte);
  EXPECT_GE(GDALGetOverviewCount(band), 1) << "overviews for coarse reads";
  std::vector<std::uint8_t> green(std::size_t(cols) * std::size_t(rows));
  ASSERT_EQ(GDALRasterIO(band, GF_Read, 0, 0, cols, rows, green.data(), cols, rows, GDT_Byte, 0, 0), CE_None);
  int wrong = 0;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) wrong += green[std::size_t(r) * std::size_t(cols) + std::size_t(c)] != hashed(c, r, 2);
  EXPECT_EQ(wrong, 0) << "lossless";
  GDALClose(ds);
  // An existing file is kept without overwrite.
  const std::string message = inputError([&] {
    terrain::writeImageryCog(out.string(), cols, rows, rgb, 0, 0, 1, 1, "EPSG:32651", false);
  });
  EXPECT_EQ(message, out.string() + ": already exists (use --overwrite to replace it)");
  EXPECT_NO_THROW(terrain::writeImageryCog(out.string(), cols, rows, rgb, 0, 0, 1, 1, "EPSG:32651", true));
}

// ---- The imagery import (terrain/imagery_import.h) ----------------------------------------------
// Its output read as a drape reads it, against the original read the same way (warped on the fly):
// the same colours within the JPEG's error, where PROJ puts the pattern.

/// 8-bit levels of the imported imagery against the pattern: JPEG at quality 90 stores colour as
/// YCbCr with the chroma at half resolution (4:2:0), and the test pattern's colour changes fast
/// (several levels a pixel); one bilinear resampling more than the on-the-fly read (the import's
/// warp, then the read's). Measured: mean 3.2, p99 10.9, largest 16.5. Uniform areas (the squares'
/// middles) keep their colour within kImportedFlatLevels.
constexpr double kImportedMeanLevels = 4.0, kImportedP99Levels = 12.0, kImportedLevels = 20.0;
constexpr double kImportedFlatLevels = 4.0;

std::string metadataItem(GDALDatasetH ds, const char* key, const char* domain) {
  const char* v = GDALGetMetadataItem(ds, key, domain);
  return v ? v : "";
}

TEST(ImageryImport, AReprojectedOrthophotoBecomesAJpegCogInTheTerrainsCrs) {
  const TempFolder folder;
  const fs::path ortho = folder / "ortho_4326.tif", out = folder / "terrain_imagery.tif";
  writeRaster(ortho, geoSpec(), geoPixel);
  const terrain::ImageryImportSummary s = terrain::importImagery(ortho.string(), out.string(), wktOf(32633));
  EXPECT_TRUE(s.reprojected);
  EXPECT_TRUE(s.masked);  // the warped footprint's outside is a hole
  EXPECT_EQ(s.bands, 3);
  EXPECT_EQ(folder.entries(), (std::vector<std::string>{"ortho_4326.tif", "terrain_imagery.tif"}));

  GDALDatasetH ds = GDALOpen(out.c_str(), GA_ReadOnly);
  ASSERT_NE(ds, nullptr);
  EXPECT_EQ(metadataItem(ds, "LAYOUT", "IMAGE_STRUCTURE"), "COG");
  EXPECT_NE(metadataItem(ds, "COMPRESSION", "IMAGE_STRUCTURE").find("JPEG"), std::string::npos);
  int bx = 0, by = 0;
  GDALGetBlockSize(GDALGetRasterBand(ds, 1), &bx, &by);
  EXPECT_EQ(bx, terrain::kImageryTileSize);
  EXPECT_EQ(by, terrain::kImageryTileSize);
  EXPECT_EQ(GDALGetOverviewCount(GDALGetRasterBand(ds, 1)), s.overviews);
  EXPECT_GE(s.overviews, 1);  // 600 px of about 1 m: one overview below a 512-pixel tile
  OGRSpatialReferenceH written = OSRNewSpatialReference(GDALGetProjectionRef(ds)), utm = OSRNewSpatialReference(nullptr);
  OSRImportFromEPSG(utm, 32633);
  EXPECT_TRUE(OSRIsSame(written, utm));
  OSRDestroySpatialReference(written);
  OSRDestroySpatialReference(utm);
  GDALClose(ds);

  // Read back as a drape: no warping now, and the original's colours where PROJ puts them.
  TerrainImagery imported(out.string(), wktOf(32633)), original(ortho.string(), wktOf(32633));
  EXPECT_FALSE(imported.reprojected());
  const Grid g = siteGrid();
  const auto a = readGrid(imported, g), b = readGrid(original, g);
  int checked = 0;
  double worst = 0, sum = 0;
  std::vector<double> errors;
  for (int j = 3; j < g.h; j += 5)
    for (int i = 2; i < g.w; i += 5) {
      const auto ll = transformPoint(32633, 4326, g.x0 + i * g.dx, g.y0 - j * g.dy);
      const double u = (ll[0] - kGeoWest) / kGeoDLon, v = (kGeoNorth - ll[1]) / kGeoDLat;
      if (nearSharp(u, v, 3.0)) continue;
      const auto want = smoothColour(u, v);
      const auto got = pixelAt(a, g, i, j), before = pixelAt(b, g, i, j);
      ASSERT_EQ(got[3], 255) << i << ", " << j;
      ASSERT_EQ(before[3], 255) << i << ", " << j;
      for (int k = 0; k < 3; ++k) {
        const double e = std::abs(got[std::size_t(k)] - want[std::size_t(k)]);
        worst = std::max(worst, e);
        sum += e;
        errors.push_back(e);
      }
      ++checked;
    }
  std::sort(errors.begin(), errors.end());
  const double mean = sum / double(errors.size()), p99 = errors[errors.size() * 99 / 100];
  std::printf("[ import   ] %d pixels of the imported imagery against the pattern through PROJ: mean %.2f, p99 %.2f, "
              "largest %.1f levels\n", checked, mean, p99, worst);
  EXPECT_GT(checked, 800);
  EXPECT_LE(mean, kImportedMeanLevels);
  EXPECT_LE(p99, kImportedP99Levels);
  EXPECT_LE(worst, kImportedLevels);
  // The squares keep their colours in their middles.
  const auto red = transformPoint(4326, 32633, kGeoWest + 220 * kGeoDLon, kGeoNorth - 320 * kGeoDLat);
  const auto px = imported.read(red[0], red[1], 1.0, 1.0, 1, 1);
  EXPECT_NEAR(px[0], 250, kImportedFlatLevels);
  EXPECT_NEAR(px[1], 10, kImportedFlatLevels);
  EXPECT_NEAR(px[2], 10, kImportedFlatLevels);
}

TEST(ImageryImport, SixteenBitGreyIsScaledAndAnExistingOutputIsKept) {
  const TempFolder folder;
  const RasterSpec s = utmSpec(700, 600, 0.5, 1, GDT_UInt16);
  auto value = [](int c, int r) { return 1000.0 + 4000.0 * (0.5 + 0.5 * std::sin(c * 0.01) * std::cos(r * 0.013)); };
  writeRaster(folder / "grey16.tif", s, [&](int c, int r, int) { return std::round(value(c, r)); });
  const fs::path out = folder / "grey_imagery.tif";
  const terrain::ImageryImportSummary sum = terrain::importImagery((folder / "grey16.tif").string(), out.string(), s.wkt);
  EXPECT_FALSE(sum.reprojected);
  EXPECT_EQ(sum.bands, 1);
  EXPECT_EQ(sum.cols, 700);
  EXPECT_EQ(sum.rows, 600);
  // Scaled from the band's own range, as a drape scales it: the two reads agree within the JPEG's error.
  TerrainImagery imported(out.string(), s.wkt), original((folder / "grey16.tif").string(), s.wkt);
  const Grid g{s.gt[0] + 0.25, s.gt[3] - 0.25, 0.5, 0.5, s.cols, s.rows};
  const auto a = readGrid(imported, g), b = readGrid(original, g);
  double worst = 0;
  for (std::size_t k = 0; k < a.size(); k += 4) worst = std::max(worst, std::abs(double(a[k]) - double(b[k])));
  std::printf("[ import   ] 16-bit grey: largest difference from the on-the-fly read %.1f levels\n", worst);
  EXPECT_LE(worst, kImportedFlatLevels);  // grey: no chroma, a smooth pattern
  const auto before = fs::last_write_time(out);
  EXPECT_EQ(inputError([&] { terrain::importImagery((folder / "grey16.tif").string(), out.string(), s.wkt); }),
            out.string() + ": exists; pass --overwrite to replace it");
  EXPECT_EQ(fs::last_write_time(out), before);
}

}  // namespace
}  // namespace nestwalk::test
