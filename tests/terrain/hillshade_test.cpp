// The top-down map's hillshade (terrain/hillshade.h) against GDAL's DEM processing
// (GDALDEMProcessing "hillshade": Horn, azimuth 315°, altitude 45°, z factor 1), sample by sample:
// on a generated DEM at UTM magnitudes (steep and shadowed slopes included) and on a real one (the
// shared LANDFIRE grid of Storm Lake, Montana, 30 m, UTM 12N; skipped when the shared data is
// absent). GDAL writes 1 + 254 · shade rounded to a byte (0 is its nodata: the outermost samples
// and those next to a hole), so each sample whose 3 x 3 neighbourhood is valid must have
// |GDAL's byte - (1 + 254 · shade)| <= kByteRounding + kGdalArithmetic.
#include "nestwalk/terrain/hillshade.h"

#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/terrain/heightfield.h"
#include "tests/common/test_data.h"

#include <gdal.h>
#include <gdal_utils.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <numbers>
#include <vector>

namespace nestwalk {
namespace {

// GDAL rounds 1 + 254 · shade to the nearest byte: half a level.
constexpr double kByteRounding = 0.5;
// GDAL's window holds the heights as float32 and part of its arithmetic is single precision: about
// 1e-6 of the shade, 3e-4 of a level; a hundredth of a level is room to spare without hiding a
// wrong rule (a sun 1° off moves many samples by whole levels).
constexpr double kGdalArithmetic = 0.01;

/// GDAL's hillshade of band 1 of `src`, as bytes, row-major, row 0 north.
std::vector<std::uint8_t> gdalHillshade(GDALDatasetH src) {
  const char* argv[] = {"-alg", "Horn", "-az", "315", "-alt", "45", "-z", "1", "-s", "1", "-of", "MEM", nullptr};
  GDALDEMProcessingOptions* options = GDALDEMProcessingOptionsNew(const_cast<char**>(argv), nullptr);
  int usageError = 0;
  GDALDatasetH out = GDALDEMProcessing("", src, "hillshade", nullptr, options, &usageError);
  GDALDEMProcessingOptionsFree(options);
  if (!out) {
    ADD_FAILURE() << "GDALDEMProcessing failed: " << CPLGetLastErrorMsg();
    return {};
  }
  const int cols = GDALGetRasterXSize(out), rows = GDALGetRasterYSize(out);
  std::vector<std::uint8_t> bytes(std::size_t(cols) * std::size_t(rows));
  if (GDALRasterIO(GDALGetRasterBand(out, 1), GF_Read, 0, 0, cols, rows, bytes.data(), cols, rows, GDT_Byte, 0, 0) !=
      CE_None)
    ADD_FAILURE() << "cannot read GDAL's hillshade";
  GDALClose(out);
  return bytes;
}

struct Comparison {
  std::size_t compared = 0, shadowed = 0, bright = 0;
  double maxDiff = 0, sumDiff = 0;
};

/// The map's shade against GDAL's bytes at every sample whose 3 x 3 neighbourhood is valid.
Comparison compare(const terrain::Heightfield& hf, const std::vector<std::uint8_t>& gdal) {
  Comparison c;
  const Eigen::Vector3d sun = terrain::sunDirection(315, 45);
  for (int r = 1; r + 1 < hf.rows(); ++r)
    for (int col = 1; col + 1 < hf.cols(); ++col) {
      bool full = true;
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc) full = full && hf.valid(col + dc, r + dr);
      if (!full) continue;
      const std::uint8_t g = gdal[std::size_t(r) * std::size_t(hf.cols()) + std::size_t(col)];
      EXPECT_NE(g, 0) << "GDAL left sample " << col << ", " << r << " without a value";
      const double shade = terrain::hornShade(hf, col, r, sun);
      const double diff = std::abs(double(g) - (1 + 254 * shade));
      if (diff > c.maxDiff) c.maxDiff = diff;
      EXPECT_LE(diff, kByteRounding + kGdalArithmetic)
          << "sample " << col << ", " << r << ": GDAL " << int(g) << ", map " << 1 + 254 * shade;
      c.sumDiff += diff;
      ++c.compared;
      c.shadowed += g == 1;
      c.bright += g >= 230;
    }
  return c;
}

TEST(Hillshade, SunDirectionIsNorthWestAndUp) {
  const Eigen::Vector3d sun = terrain::sunDirection(315, 45);
  EXPECT_NEAR(sun.norm(), 1, 1e-15);
  EXPECT_NEAR(sun.x(), -0.5, 1e-15);  // west
  EXPECT_NEAR(sun.y(), 0.5, 1e-15);   // north
  EXPECT_NEAR(sun.z(), std::sqrt(0.5), 1e-15);
}

TEST(Hillshade, MatchesGdalOnAGeneratedDem) {
  // 90 x 70 samples 2 m apart at UTM magnitudes: rolling ground, a steep cone (a lit and a shadowed
  // flank) and a ridge; heights exact in float32, the values both sides read.
  constexpr int kCols = 90, kRows = 70;
  constexpr double kCell = 2, kOriginX = 550000.5, kOriginY = 4650100.5;  // centre of sample (0, 0)
  std::vector<float> heights;
  for (int r = 0; r < kRows; ++r)
    for (int c = 0; c < kCols; ++c) {
      const double rolling = 200 + 6 * std::sin(c / 7.0) * std::cos(r / 5.0) + 0.2 * c;
      const double d = std::hypot(c - 30.0, r - 35.0);
      const double cone = std::max(0.0, 40 - 3.5 * d);
      const double ridge = 12 * std::exp(-std::pow((c - 0.6 * r - 45) / 3.0, 2));
      heights.push_back(float(rolling + cone + ridge));
    }
  GDALAllRegister();
  GDALDatasetH src = GDALCreate(GDALGetDriverByName("MEM"), "", kCols, kRows, 1, GDT_Float32, nullptr);
  ASSERT_NE(src, nullptr);
  double geo[6] = {kOriginX - kCell / 2, kCell, 0, kOriginY + kCell / 2, 0, -kCell};
  GDALSetGeoTransform(src, geo);
  ASSERT_EQ(GDALRasterIO(GDALGetRasterBand(src, 1), GF_Write, 0, 0, kCols, kRows, heights.data(), kCols, kRows,
                         GDT_Float32, 0, 0),
            CE_None);
  const std::vector<std::uint8_t> gdal = gdalHillshade(src);
  GDALClose(src);
  ASSERT_EQ(gdal.size(), heights.size());
  const terrain::Heightfield hf(kCols, kRows, heights, kOriginX, kOriginY, kCell, kCell);
  const Comparison c = compare(hf, gdal);
  EXPECT_EQ(c.compared, std::size_t(kCols - 2) * std::size_t(kRows - 2));
  EXPECT_GT(c.shadowed, 20u) << "no slope turned away from the sun: the test would not see max(0, ·)";
  EXPECT_GT(c.bright, 20u) << "no slope facing the sun";
  std::printf("[ hillshade] generated: %zu samples, %zu shadowed, %zu bright, max |diff| %.3f, mean %.3f levels\n",
              c.compared, c.shadowed, c.bright, c.maxDiff, c.sumDiff / double(c.compared));
}

TEST(Hillshade, MatchesGdalOnARealDem) {
  const std::filesystem::path data = test::sharedData();
  if (data.empty()) GTEST_SKIP() << "shared data folder absent (NESTWALK_SHARED_DATA): no real DEM";
  const std::filesystem::path path = data / "terrain" / "storml_elev_orig.tif";
  const terrain::Heightfield hf = terrain::readDem(path.string());
  GDALDatasetH src = GDALOpen(path.string().c_str(), GA_ReadOnly);
  ASSERT_NE(src, nullptr);
  const std::vector<std::uint8_t> gdal = gdalHillshade(src);
  GDALClose(src);
  ASSERT_EQ(gdal.size(), std::size_t(hf.cols()) * std::size_t(hf.rows()));
  const Comparison c = compare(hf, gdal);
  // 143 x 107 samples, 5.7 % nodata along the edges: most of the grid has a full neighbourhood.
  EXPECT_GT(c.compared, std::size_t(hf.cols() * hf.rows()) * 3 / 4);
  EXPECT_GT(c.bright + c.shadowed, 0u);
  std::printf("[ hillshade] %s: %zu samples, %zu shadowed, %zu bright, max |diff| %.3f, mean %.3f levels\n",
              path.filename().c_str(), c.compared, c.shadowed, c.bright, c.maxDiff, c.sumDiff / double(c.compared));
}

TEST(Hillshade, AStepIsTheRuleOnTheCoarserGrid) {
  // hornShade(step 2) on a grid equals hornShade(step 1) on every second sample of it (spacing
  // doubled), the level grid a terrain chunk shades: interior, edges and holes alike.
  constexpr int kCols = 41, kRows = 33;
  std::vector<float> fine, coarse;
  for (int r = 0; r < kRows; ++r)
    for (int c = 0; c < kCols; ++c) {
      float h = float(150 + 9 * std::sin(c / 4.0) * std::cos(r / 3.0) + 0.3 * c);
      if ((c == 10 && r == 12) || (c == 24 && r == 0)) h = std::numeric_limits<float>::quiet_NaN();
      fine.push_back(h);
      if (c % 2 == 0 && r % 2 == 0) coarse.push_back(h);
    }
  const terrain::Heightfield f(kCols, kRows, fine, 600000.0, 7000000.0, 1.5, 2.5);
  const terrain::Heightfield g(kCols / 2 + 1, kRows / 2 + 1, coarse, 600000.0, 7000000.0, 3.0, 5.0);
  const Eigen::Vector3d sun = terrain::sunDirection(315, 45);
  int compared = 0;
  for (int r = 0; r < kRows; r += 2)
    for (int c = 0; c < kCols; c += 2) {
      if (!f.valid(c, r)) continue;
      EXPECT_NEAR(terrain::hornShade(f, c, r, sun, 2), terrain::hornShade(g, c / 2, r / 2, sun), 1e-12) << c << " " << r;
      ++compared;
    }
  EXPECT_GT(compared, 300);
}

}  // namespace
}  // namespace nestwalk
