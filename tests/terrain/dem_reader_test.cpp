// terrain/dem_reader: every shared DEM read into a Heightfield agrees sample for sample with GDAL's
// own RasterIO (and groundHeight at samples and edge midpoints), georeferencing is sample-centred,
// flipped rasters come out north-up, and bad rasters are refused with the file's name.
#include "nestwalk/core/input_error.h"
#include "nestwalk/terrain/dem_reader.h"
#include "tests/terrain/gdal_test_util.h"
#include "tests/common/input_error_of.h"
#include "tests/common/run_command.h"
#include "tests/common/test_data.h"

#include <gdal.h>
#include <ogr_srs_api.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace nestwalk::test {
namespace {

using terrain::Heightfield;
namespace fs = std::filesystem;

struct GdalGrid {
  int cols = 0, rows = 0;
  double gt[6] = {0, 1, 0, 0, 0, 1};
  bool hasNoData = false;
  double noData = 0;
  std::vector<double> v;  // row-major as stored
  bool valid(int c, int r) const {
    const double s = v[std::size_t(r) * std::size_t(cols) + std::size_t(c)];
    return !(hasNoData && s == noData) && std::isfinite(s);
  }
  double at(int c, int r) const { return v[std::size_t(r) * std::size_t(cols) + std::size_t(c)]; }
};

/// The band as GDAL itself reads it (RasterIO), independently of the reader under test.
GdalGrid readWithGdal(const fs::path& path, int bandNo = 1) {
  terrain::initGdal();
  GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
  EXPECT_NE(ds, nullptr) << path;
  GdalGrid g;
  if (!ds) return g;
  g.cols = GDALGetRasterXSize(ds);
  g.rows = GDALGetRasterYSize(ds);
  GDALGetGeoTransform(ds, g.gt);
  GDALRasterBandH band = GDALGetRasterBand(ds, bandNo);
  int has = 0;
  g.noData = GDALGetRasterNoDataValue(band, &has);
  g.hasNoData = has != 0;
  g.v.resize(std::size_t(g.cols) * std::size_t(g.rows));
  EXPECT_EQ(GDALRasterIO(band, GF_Read, 0, 0, g.cols, g.rows, g.v.data(), g.cols, g.rows, GDT_Float64, 0, 0), CE_None);
  GDALClose(ds);
  return g;
}

std::vector<fs::path> sharedDems() {
  std::vector<fs::path> out;
  const fs::path dir = sharedData();
  if (dir.empty() || !fs::is_directory(dir / "terrain")) return out;
  for (const auto& e : fs::directory_iterator(dir / "terrain")) {
    const auto ext = e.path().extension().string();
    if (ext == ".tif" || ext == ".asc") out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

/// Samples, edge midpoints (horizontal and vertical) of the heightfield against GDAL's values.
void expectAgrees(const Heightfield& hf, const GdalGrid& g, const std::string& name) {
  ASSERT_EQ(hf.cols(), g.cols);
  ASSERT_EQ(hf.rows(), g.rows);
  EXPECT_DOUBLE_EQ(hf.origin().x(), g.gt[0] + 0.5 * g.gt[1]) << name;
  EXPECT_DOUBLE_EQ(hf.origin().y(), g.gt[3] + 0.5 * g.gt[5]) << name;
  EXPECT_DOUBLE_EQ(hf.dx(), g.gt[1]);
  EXPECT_DOUBLE_EQ(hf.dy(), -g.gt[5]);
  const int stride = g.cols * g.rows > 200000 ? 7 : 1;
  std::size_t samples = 0, holes = 0, mids = 0;
  double maxDiff = 0;
  for (int r = 0; r < g.rows; r += stride) {
    for (int c = 0; c < g.cols; c += stride) {
      const auto p = hf.samplePosition(c, r);
      const auto z = hf.groundHeight(p.x(), p.y());
      if (g.valid(c, r)) {
        ASSERT_TRUE(z.has_value()) << name << " sample " << c << "," << r;
        maxDiff = std::max(maxDiff, std::abs(*z - g.at(c, r)));
        EXPECT_EQ(hf.sample(c, r), float(g.at(c, r)));
        ++samples;
      } else {
        EXPECT_FALSE(z.has_value()) << name << " nodata sample " << c << "," << r;
        EXPECT_FALSE(hf.valid(c, r));
        ++holes;
      }
      for (int k = 0; k < 2; ++k) {
        const int c2 = c + (k == 0), r2 = r + (k == 1);
        if (c2 >= g.cols || r2 >= g.rows || !g.valid(c, r) || !g.valid(c2, r2)) continue;
        const auto q = hf.samplePosition(c2, r2);
        const auto zm = hf.groundHeight(k == 0 ? 0.5 * (p.x() + q.x()) : p.x(), k == 0 ? p.y() : 0.5 * (p.y() + q.y()));
        ASSERT_TRUE(zm.has_value()) << name << " midpoint " << c << "," << r << " k=" << k;
        maxDiff = std::max(maxDiff, std::abs(*zm - 0.5 * (g.at(c, r) + g.at(c2, r2))));
        ++mids;
      }
    }
  }
  EXPECT_LE(maxDiff, 1e-4) << name;
  std::printf("[ reader   ] %s: %zu samples, %zu nodata, %zu midpoints, max |diff| %.3g m\n", name.c_str(), samples,
              holes, mids, maxDiff);
}

TEST(DemReader, EverySharedDemAgreesWithGdalRasterIO) {
  const auto dems = sharedDems();
  if (dems.empty()) GTEST_SKIP() << "shared data folder absent (NESTWALK_SHARED_DATA): no DEM to read";
  for (const auto& p : dems) {
    const auto before = fs::last_write_time(p);
    std::vector<std::string> warnings;
    const Heightfield hf = terrain::readDem(p.string(), {}, &warnings);
    expectAgrees(hf, readWithGdal(p), p.filename().string());
    EXPECT_TRUE(warnings.empty());
    EXPECT_EQ(fs::last_write_time(p), before);
    EXPECT_FALSE(fs::exists(p.string() + ".aux.xml"));
  }
}

TEST(DemReader, DegreeBasedCrsReadInDegrees) {
  const fs::path dir = sharedData();
  if (dir.empty() || !fs::exists(dir / "terrain/mt_rainier_90m.tif")) GTEST_SKIP() << "shared mt_rainier_90m.tif absent";
  const Heightfield hf = terrain::readDem((dir / "terrain/mt_rainier_90m.tif").string());
  EXPECT_NEAR(hf.dx(), 1.0 / 1200.0, 1e-12);  // degrees, not metres
  EXPECT_NEAR(hf.origin().x(), -122.0, 1e-9);  // longitude first
  EXPECT_NEAR(hf.origin().y(), 47.0, 1e-9);
  EXPECT_NE(hf.crsWkt().find("WGS 84"), std::string::npos);
  const auto z = hf.groundHeight(-121.7603, 46.8523);  // near the summit: metres
  ASSERT_TRUE(z.has_value());
  EXPECT_GT(*z, 4000.0);
}

/// A small GeoTIFF written with GDAL: values row-major, optional geotransform and nodata.
void writeTiff(const fs::path& path, int cols, int rows, const std::vector<double>& values, const double* gt,
               std::optional<double> noData = std::nullopt, GDALDataType type = GDT_Float32, int bands = 1) {
  terrain::initGdal();
  GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), path.c_str(), cols, rows, bands, type, nullptr);
  ASSERT_NE(ds, nullptr);
  if (gt) GDALSetGeoTransform(ds, const_cast<double*>(gt));
  writeBands(ds, cols, rows, values, noData, bands);
  if (::testing::Test::HasFatalFailure()) return;
  GDALClose(ds);
}

TEST(DemReader, FlippedRastersComeOutNorthUp) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  // 3 x 2, stored south-up (positive pixel height) and east-to-west.
  const double gt[6] = {1000.0, -2.0, 0, 500.0, 0, 4.0};
  writeTiff(dir / "flip.tif", 3, 2, {1, 2, 3, 4, 5, 6}, gt);
  const Heightfield hf = terrain::readDem((dir / "flip.tif").string());
  // Stored (c, r) is at x = 1000 - 2 (c + 0.5), y = 500 + 4 (r + 0.5): north-west is stored (2, 1) = 6.
  EXPECT_DOUBLE_EQ(hf.origin().x(), 1000.0 - 5.0);
  EXPECT_DOUBLE_EQ(hf.origin().y(), 500.0 + 6.0);
  EXPECT_DOUBLE_EQ(hf.dx(), 2.0);
  EXPECT_DOUBLE_EQ(hf.dy(), 4.0);
  EXPECT_EQ(hf.sample(0, 0), 6.0f);
  EXPECT_EQ(hf.sample(2, 1), 1.0f);
  EXPECT_DOUBLE_EQ(*hf.groundHeight(1000.0 - 1.0, 502.0), 1.0);
}

TEST(DemReader, BandChoiceAndNoData) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const double gt[6] = {0, 1, 0, 10, 0, -1};
  writeTiff(dir / "two.tif", 2, 2, {1, 2, 3, -5}, gt, -5.0, GDT_Float32, 2);
  const Heightfield b1 = terrain::readDem((dir / "two.tif").string());
  EXPECT_FALSE(b1.valid(1, 1));
  EXPECT_EQ(b1.noData(), -5.0f);
  const Heightfield b2 = terrain::readDem((dir / "two.tif").string(), {2});
  EXPECT_EQ(b2.sample(0, 0), 1001.0f);
  EXPECT_NE(inputError([&] { terrain::readDem((dir / "two.tif").string(), {3}); }).find("band 3 does not exist"),
            std::string::npos);
}

TEST(DemReader, BadInputsNameTheFileAndTheProblem) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const double gt[6] = {0, 1, 0, 10, 0, -1};
  const double rotated[6] = {0, 0.8, 0.6, 10, 0.6, -0.8};
  writeText(dir / "text.tif", "this is not a raster\n");
  writeText(dir / "zero.tif", "");
  writeTiff(dir / "allnodata.tif", 2, 2, {-9, -9, -9, -9}, gt, -9.0);
  writeTiff(dir / "nan.tif", 2, 2, {1, NAN, 3, 4}, gt);
  writeTiff(dir / "inf.tif", 2, 2, {1, 2, INFINITY, 4}, gt);
  writeTiff(dir / "rotated.tif", 2, 2, {1, 2, 3, 4}, rotated);
  writeTiff(dir / "thin.tif", 5, 1, {1, 2, 3, 4, 5}, gt);
  writeTiff(dir / "big.tif", 256, 256, std::vector<double>(256 * 256, 7.0), gt);
  {
    const auto size = fs::file_size(dir / "big.tif");
    fs::copy_file(dir / "big.tif", dir / "truncated.tif");
    fs::resize_file(dir / "truncated.tif", size / 2);
  }
  const struct {
    const char* file;
    const char* message;
  } cases[] = {
      {"missing.tif", "no such file"},       {"text.tif", "not a raster GDAL can read"},
      {"zero.tif", "empty file"},            {"allnodata.tif", "every sample is nodata"},
      {"nan.tif", "NaN or infinite sample"}, {"inf.tif", "NaN or infinite sample"},
      {"rotated.tif", "rotated or sheared"}, {"truncated.tif", "truncated or corrupt"},
      {"thin.tif", "5 x 1 samples; a ground surface needs at least 2 x 2"},
  };
  for (const auto& c : cases) {
    const std::string path = (dir / c.file).string();
    const std::string msg = inputError([&] { terrain::readDem(path); });
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find(c.message), std::string::npos) << c.file << ": " << msg;
  }
}

TEST(DemReader, NoGeoreferencingIsPixelUnitsWithAWarning) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  writeTiff(dir / "plain.tif", 3, 2, {1, 2, 3, 4, 5, 6}, nullptr);
  std::vector<std::string> warnings;
  const Heightfield hf = terrain::readDem((dir / "plain.tif").string(), {}, &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("no georeferencing"), std::string::npos);
  EXPECT_DOUBLE_EQ(hf.origin().x(), 0.5);
  EXPECT_DOUBLE_EQ(hf.origin().y(), -0.5);
  EXPECT_DOUBLE_EQ(*hf.groundHeight(2.5, -1.5), 6.0);
}

}  // namespace
}  // namespace nestwalk::test
