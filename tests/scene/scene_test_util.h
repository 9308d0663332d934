// Shared by the scene tests: a per-test temporary folder fixture, a small planar GeoTIFF terrain
// written with GDAL (and a fixture writing it at the origin and at UTM magnitudes), and catching an
// InputError's message.
#pragma once

#include "nestwalk/core/input_error.h"
#include "nestwalk/terrain/dem_reader.h"
#include "tests/common/input_error_of.h"
#include "tests/common/temp_folder.h"
#include "tests/common/test_data.h"
#include "tests/terrain/gdal_test_util.h"

#include <gdal.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace nestwalk::test {

namespace fs = std::filesystem;

/// A fixture with an empty temporary folder per test (TempFolder: removed afterwards unless the
/// test failed).
class TempFolderTest : public ::testing::Test {
 protected:
  const fs::path& dir() const { return folder_->path(); }
  void SetUp() override { folder_ = std::make_unique<TempFolder>(); }
  void TearDown() override { folder_.reset(); }

 private:
  std::unique_ptr<TempFolder> folder_;
};

/// The planar test terrain: sample (c, r) has height kPlane0 + kPlaneEast * c + kPlaneSouth * r,
/// exact in float, so the triangulated surface is the plane itself.
inline constexpr double kPlane0 = 100.0, kPlaneEast = 0.5, kPlaneSouth = 0.25;

struct PlaneTerrain {
  double west = 0, north = 0;  // the raster's outer corner (GDAL geotransform origin)
  double cell = 1;
  int cols = 65, rows = 65;
  /// Map position of sample (c, r)'s centre.
  double sampleX(double c) const { return west + (c + 0.5) * cell; }
  double sampleY(double r) const { return north - (r + 0.5) * cell; }
  /// The plane at map (x, y), computed from the construction (not through the heightfield).
  double height(double x, double y) const {
    const double c = (x - sampleX(0)) / cell, r = (sampleY(0) - y) / cell;
    return kPlane0 + kPlaneEast * c + kPlaneSouth * r;
  }
};

/// Writes `t` as a Float32 GeoTIFF at `path`.
inline void writePlaneTiff(const fs::path& path, const PlaneTerrain& t) {
  terrain::initGdal();
  std::vector<double> values;
  for (int r = 0; r < t.rows; ++r)
    for (int c = 0; c < t.cols; ++c) values.push_back(kPlane0 + kPlaneEast * c + kPlaneSouth * r);
  GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), path.c_str(), t.cols, t.rows, 1, GDT_Float32, nullptr);
  ASSERT_NE(ds, nullptr);
  double gt[6] = {t.west, t.cell, 0.0, t.north, 0.0, -t.cell};
  GDALSetGeoTransform(ds, gt);
  writeBands(ds, t.cols, t.rows, values, std::nullopt, 1);
  GDALClose(ds);
}

/// Where a test terrain's north-west corner is: at the origin, and at UTM magnitudes (zone 51N-like).
struct TerrainPlace {
  const char* name;
  double west, north;
};
inline const TerrainPlace kTerrainPlaces[] = {{"origin", 0.0, 65.0}, {"utm", 550000.0, 4650065.0}};
inline void PrintTo(const TerrainPlace& p, std::ostream* os) { *os << p.name; }

/// A fixture with the planar terrain written as terrain.tif in its folder, at each TerrainPlace
/// (INSTANTIATE_TEST_SUITE_P over kTerrainPlaces).
class PlaneTerrainTest : public TempFolderTest, public ::testing::WithParamInterface<TerrainPlace> {
 protected:
  void SetUp() override {
    TempFolderTest::SetUp();
    terrain_.west = GetParam().west;
    terrain_.north = GetParam().north;
    writePlaneTiff(dir() / "terrain.tif", terrain_);
  }
  /// Map position of fractional sample (c, r), as a scene file writes it.
  nlohmann::json at(double c, double r) const { return nlohmann::json::array({terrain_.sampleX(c), terrain_.sampleY(r)}); }
  PlaneTerrain terrain_;
};

}  // namespace nestwalk::test
