// terrain/terrain_import: the import pipeline, checked with GDAL's own reads of the output: the COG
// layout (Float32, tiled, compressed, overviews, CRS), sample-exact copies of every shared DEM, and
// the options (band, crop window, resolution, target CRS, nodata fill, vertical scale, rotated
// geotransforms warped north-up), temp-file-and-rename and --overwrite.
#include "nestwalk/core/input_error.h"
#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/terrain/terrain_import.h"
#include "tests/terrain/gdal_test_util.h"
#include "tests/common/run_command.h"
#include "tests/common/test_data.h"

#include <cpl_conv.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <cmath>
#include <numbers>
#include <filesystem>

namespace nestwalk::test {
namespace {

namespace fs = std::filesystem;
using terrain::ImportOptions;
using terrain::kTerrainNoData;

struct Raster {
  int cols = 0, rows = 0, overviews = 0, bands = 0;
  double gt[6] = {0, 1, 0, 0, 0, 1};
  bool hasGt = false, hasNoData = false;
  double noData = 0;
  GDALDataType type = GDT_Unknown;
  std::string wkt, layout, compression;
  int blockX = 0, blockY = 0;
  std::vector<double> v;
  double at(int c, int r) const { return v[std::size_t(r) * std::size_t(cols) + std::size_t(c)]; }
};

Raster readRaster(const fs::path& path, int bandNo = 1) {
  terrain::initGdal();
  Raster r;
  GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
  EXPECT_NE(ds, nullptr) << path;
  if (!ds) return r;
  r.cols = GDALGetRasterXSize(ds);
  r.rows = GDALGetRasterYSize(ds);
  r.bands = GDALGetRasterCount(ds);
  r.hasGt = GDALGetGeoTransform(ds, r.gt) == CE_None;
  r.wkt = GDALGetProjectionRef(ds);
  if (const char* l = GDALGetMetadataItem(ds, "LAYOUT", "IMAGE_STRUCTURE")) r.layout = l;
  if (const char* c = GDALGetMetadataItem(ds, "COMPRESSION", "IMAGE_STRUCTURE")) r.compression = c;
  GDALRasterBandH band = GDALGetRasterBand(ds, bandNo);
  int has = 0;
  r.noData = GDALGetRasterNoDataValue(band, &has);
  r.hasNoData = has != 0;
  r.type = GDALGetRasterDataType(band);
  r.overviews = GDALGetOverviewCount(band);
  GDALGetBlockSize(band, &r.blockX, &r.blockY);
  r.v.resize(std::size_t(r.cols) * std::size_t(r.rows));
  EXPECT_EQ(GDALRasterIO(band, GF_Read, 0, 0, r.cols, r.rows, r.v.data(), r.cols, r.rows, GDT_Float64, 0, 0), CE_None);
  GDALClose(ds);
  return r;
}

void writeTiff(const fs::path& path, int cols, int rows, const std::vector<double>& values, const double* gt,
               std::optional<double> noData = std::nullopt, int bands = 1, const char* epsg = nullptr) {
  terrain::initGdal();
  GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), path.c_str(), cols, rows, bands, GDT_Float32, nullptr);
  ASSERT_NE(ds, nullptr);
  if (gt) GDALSetGeoTransform(ds, const_cast<double*>(gt));
  if (epsg) {
    OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
    OSRSetFromUserInput(srs, epsg);
    char* wkt = nullptr;
    OSRExportToWkt(srs, &wkt);
    GDALSetProjection(ds, wkt);
    CPLFree(wkt);
    OSRDestroySpatialReference(srs);
  }
  writeBands(ds, cols, rows, values, noData, bands);
  if (::testing::Test::HasFatalFailure()) return;
  GDALClose(ds);
}

/// A smooth 200 x 150 test surface in UTM 51N with a hole.
fs::path smoothDem(const fs::path& dir) {
  const int cols = 200, rows = 150;
  std::vector<double> v(std::size_t(cols) * rows);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) v[std::size_t(r) * cols + c] = 100.0 + 0.5 * c + 0.25 * r + 5.0 * std::sin(0.05 * c);
  for (int r = 60; r < 64; ++r)
    for (int c = 80; c < 85; ++c) v[std::size_t(r) * cols + c] = -9999.0;
  const double gt[6] = {550000.0, 2.0, 0, 4650000.0, 0, -2.0};
  const fs::path p = dir / "smooth.tif";
  writeTiff(p, cols, rows, v, gt, -9999.0, 1, "EPSG:32651");
  return p;
}

void expectTerrainCog(const Raster& r) {
  EXPECT_EQ(r.layout, "COG");
  EXPECT_EQ(r.type, GDT_Float32);
  EXPECT_EQ(r.compression, "DEFLATE");
  EXPECT_TRUE(r.hasNoData);
  EXPECT_EQ(r.noData, double(kTerrainNoData));
}

TEST(TerrainImport, EverySharedDemCopiesSampleForSample) {
  const fs::path data = sharedData();
  if (data.empty()) GTEST_SKIP() << "shared data folder absent (NESTWALK_SHARED_DATA): no DEM to import";
  const TempFolder folder;
  const fs::path dir = folder.path();
  for (const char* name : {"mt_rainier_90m.tif", "storml_elev_orig.tif", "pre_runout_DEM.asc"}) {
    const fs::path in = data / "terrain" / name;
    if (!fs::exists(in)) continue;
    const fs::path out = dir / (std::string(name) + ".cog.tif");
    const auto summary = terrain::importTerrain(in.string(), out.string(), {});
    const Raster src = readRaster(in), dst = readRaster(out);
    expectTerrainCog(dst);
    ASSERT_EQ(dst.cols, src.cols);
    ASSERT_EQ(dst.rows, src.rows);
    for (int k = 0; k < 6; ++k) EXPECT_DOUBLE_EQ(dst.gt[k], src.gt[k]) << name;
    EXPECT_EQ(dst.wkt.empty(), src.wkt.empty());
    if (src.cols * src.rows > 1024 * 1024) {
      EXPECT_GT(dst.overviews, 0) << name;
    }
    std::size_t holes = 0;
    double maxDiff = 0;
    for (std::size_t i = 0; i < src.v.size(); ++i) {
      if (src.hasNoData && src.v[i] == src.noData) {
        EXPECT_EQ(dst.v[i], double(kTerrainNoData));
        ++holes;
      } else {
        maxDiff = std::max(maxDiff, std::abs(dst.v[i] - double(float(src.v[i]))));
      }
    }
    EXPECT_EQ(maxDiff, 0.0) << name;
    EXPECT_NEAR(summary.noDataFraction, double(holes) / double(src.v.size()), 1e-12);
    EXPECT_EQ(summary.cols, src.cols);
    std::printf("[ import   ] %s: %dx%d, %zu nodata, CRS %s, heights %.2f..%.2f\n", name, summary.cols, summary.rows,
                holes, summary.crsName.c_str(), summary.minHeight, summary.maxHeight);
  }
}

TEST(TerrainImport, CropWindowSnapsToSamples) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const auto in = smoothDem(dir);
  ImportOptions o;
  o.window = std::array<double, 4>{550020.0, 4649900.0, 550100.0, 4649960.0};
  terrain::importTerrain(in.string(), (dir / "crop.tif").string(), o);
  const Raster src = readRaster(in), dst = readRaster(dir / "crop.tif");
  EXPECT_EQ(dst.cols, 40);
  EXPECT_EQ(dst.rows, 30);
  EXPECT_DOUBLE_EQ(dst.gt[0], 550020.0);
  EXPECT_DOUBLE_EQ(dst.gt[3], 4649960.0);
  for (int r = 0; r < dst.rows; ++r)
    for (int c = 0; c < dst.cols; ++c) ASSERT_EQ(dst.at(c, r), double(float(src.at(c + 10, r + 20))));
  ImportOptions outside;
  outside.window = std::array<double, 4>{0.0, 0.0, 10.0, 10.0};
  EXPECT_THROW(terrain::importTerrain(in.string(), (dir / "none.tif").string(), outside), InputError);
  EXPECT_FALSE(fs::exists(dir / "none.tif"));
}

TEST(TerrainImport, ResolutionAndTargetCrsGoThroughTheWarper) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const auto in = smoothDem(dir);
  ImportOptions res;
  res.resolution = 4.0;
  terrain::importTerrain(in.string(), (dir / "res.tif").string(), res);
  const Raster r4 = readRaster(dir / "res.tif");
  EXPECT_EQ(r4.cols, 100);
  EXPECT_EQ(r4.rows, 75);
  EXPECT_DOUBLE_EQ(r4.gt[1], 4.0);
  // Bilinear on a nearly linear surface: the centre of a 4 m cell is a corner of 2 m cells.
  const Raster src = readRaster(in);
  const double mean = 0.25 * (src.at(20, 20) + src.at(21, 20) + src.at(20, 21) + src.at(21, 21));
  EXPECT_NEAR(r4.at(10, 10), mean, 0.05);

  ImportOptions crs;
  crs.targetCrs = "EPSG:4326";
  terrain::importTerrain(in.string(), (dir / "geo.tif").string(), crs);
  const Raster g = readRaster(dir / "geo.tif");
  EXPECT_NE(g.wkt.find("WGS 84"), std::string::npos);
  EXPECT_LT(g.gt[1], 1e-3);  // degrees
  EXPECT_GT(g.gt[0], 123.0);  // UTM 51N is around 123 E
  EXPECT_LT(g.gt[0], 124.0);
  // Back to the source: the height range is preserved within interpolation.
  double lo = 1e9, hi = -1e9;
  for (double v : g.v)
    if (v != double(kTerrainNoData)) lo = std::min(lo, v), hi = std::max(hi, v);
  double srcLo = 1e9, srcHi = -1e9;
  for (double v : src.v)
    if (v != -9999.0) srcLo = std::min(srcLo, v), srcHi = std::max(srcHi, v);
  EXPECT_NEAR(lo, srcLo, 1.0);
  EXPECT_NEAR(hi, srcHi, 1.0);
}

TEST(TerrainImport, NoDataFillAndVerticalScale) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const auto in = smoothDem(dir);
  ImportOptions fill;
  fill.fillNoData = true;
  const auto s = terrain::importTerrain(in.string(), (dir / "fill.tif").string(), fill);
  EXPECT_EQ(s.noDataFraction, 0.0);
  const Raster src = readRaster(in), f = readRaster(dir / "fill.tif");
  EXPECT_NEAR(f.at(82, 61), 100.0 + 0.5 * 82 + 0.25 * 61 + 5.0 * std::sin(0.05 * 82), 1.0);
  ImportOptions feet;
  feet.verticalScale = 0.3048;
  const auto sf = terrain::importTerrain(in.string(), (dir / "feet.tif").string(), feet);
  const Raster ft = readRaster(dir / "feet.tif");
  EXPECT_NEAR(ft.at(3, 4), double(float(src.at(3, 4) * 0.3048)), 1e-4);
  EXPECT_EQ(ft.at(82, 61), double(kTerrainNoData));
  EXPECT_NEAR(sf.noDataFraction, 20.0 / (200 * 150), 1e-12);
}

TEST(TerrainImport, BandRotationAndNoGeoreferencing) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const double gt[6] = {100, 1, 0, 200, 0, -1};
  writeTiff(dir / "two.tif", 4, 3, {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12}, gt, std::nullopt, 2);
  ImportOptions b2;
  b2.band = 2;
  terrain::importTerrain((dir / "two.tif").string(), (dir / "b2.tif").string(), b2);
  EXPECT_EQ(readRaster(dir / "b2.tif").at(0, 0), 1001.0);
  b2.band = 3;
  EXPECT_THROW(terrain::importTerrain((dir / "two.tif").string(), (dir / "b3.tif").string(), b2), InputError);

  // 30 degrees rotated: warped north-up, with a warning.
  const double a = std::numbers::pi / 6;
  const double rot[6] = {1000, std::cos(a), std::sin(a), 2000, std::sin(a), -std::cos(a)};
  std::vector<double> v(40 * 40);
  for (int r = 0; r < 40; ++r)
    for (int c = 0; c < 40; ++c) v[std::size_t(r) * 40 + c] = 10.0 + c;
  writeTiff(dir / "rot.tif", 40, 40, v, rot);
  const auto s = terrain::importTerrain((dir / "rot.tif").string(), (dir / "rot_out.tif").string(), {});
  ASSERT_FALSE(s.warnings.empty());
  EXPECT_NE(s.warnings[0].find("warped north-up"), std::string::npos);
  const Raster w = readRaster(dir / "rot_out.tif");
  EXPECT_EQ(w.gt[2], 0.0);
  EXPECT_EQ(w.gt[4], 0.0);
  EXPECT_GT(w.cols, 40);
  EXPECT_GT(s.noDataFraction, 0.1);  // the rotated square's corners

  writeTiff(dir / "plain.tif", 3, 2, {1, 2, 3, 4, 5, 6}, nullptr);
  const auto sp = terrain::importTerrain((dir / "plain.tif").string(), (dir / "plain_out.tif").string(), {});
  ASSERT_EQ(sp.warnings.size(), 1u);
  EXPECT_NE(sp.warnings[0].find("no georeferencing"), std::string::npos);
  EXPECT_EQ(readRaster(dir / "plain_out.tif").at(2, 1), 6.0);
}

TEST(TerrainImport, SouthUpGridIsWrittenNorthUpSampleExact) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const double gt[6] = {1000.0, 2.0, 0, 500.0, 0, 3.0};  // row 0 is the south row
  writeTiff(dir / "south.tif", 3, 2, {1.25, 2, 3, 4, 5, 6.5}, gt, std::nullopt, 1, "EPSG:32651");
  terrain::importTerrain((dir / "south.tif").string(), (dir / "north.tif").string(), {});
  const Raster r = readRaster(dir / "north.tif");
  ASSERT_EQ(r.cols, 3);
  ASSERT_EQ(r.rows, 2);
  EXPECT_DOUBLE_EQ(r.gt[3], 506.0);
  EXPECT_DOUBLE_EQ(r.gt[5], -3.0);
  const double expected[6] = {4, 5, 6.5, 1.25, 2, 3};
  for (int k = 0; k < 6; ++k) EXPECT_EQ(r.v[std::size_t(k)], expected[k]) << k;
  // A window snaps outward to whole samples: the two western samples of the southern row.
  ImportOptions o;
  o.window = std::array<double, 4>{1000.5, 500.5, 1003.5, 502.5};
  terrain::importTerrain((dir / "south.tif").string(), (dir / "crop.tif").string(), o);
  const Raster c = readRaster(dir / "crop.tif");
  ASSERT_EQ(c.cols, 2);
  ASSERT_EQ(c.rows, 1);
  EXPECT_EQ(c.v[0], 1.25);
  EXPECT_EQ(c.v[1], 2.0);
}

TEST(TerrainImport, OverwriteAndNoLeftovers) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const auto in = smoothDem(dir);
  const fs::path out = dir / "out.tif";
  writeText(out, "precious");
  EXPECT_THROW(terrain::importTerrain(in.string(), out.string(), {}), InputError);
  EXPECT_EQ(readText(out), "precious");
  ImportOptions o;
  o.overwrite = true;
  EXPECT_THROW(terrain::importTerrain(in.string(), in.string(), o), InputError);
  terrain::importTerrain(in.string(), out.string(), o);
  EXPECT_EQ(readRaster(out).layout, "COG");
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    ++files;
    EXPECT_NE(e.path().filename().string()[0], '.');
  }
  EXPECT_EQ(files, 3);  // smooth.tif, out.tif and its out.pyramid.tif: no temporary or staging file left
  EXPECT_TRUE(fs::exists(dir / "out.pyramid.tif"));
}

TEST(TerrainImport, WriteTerrainCogRoundTrips) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  std::vector<float> h = {1, 2, 3, NAN, 5, 6};
  terrain::writeTerrainCog((dir / "w.tif").string(), 3, 2, h, 550000.5, 4650000.5, 1.0, 1.0, "EPSG:32651", false);
  const auto hf = terrain::readDem((dir / "w.tif").string());
  EXPECT_DOUBLE_EQ(hf.origin().x(), 550000.5);
  EXPECT_DOUBLE_EQ(hf.origin().y(), 4650000.5);
  EXPECT_FALSE(hf.valid(0, 1));
  EXPECT_EQ(hf.sample(2, 1), 6.0f);
  EXPECT_NE(terrain::crsName(hf.crsWkt()).find("EPSG:32651"), std::string::npos);
}

}  // namespace
}  // namespace nestwalk::test
