// Shared by the make-terrain and make-scene tests: the synthetic orthophoto read back with GDAL
// (independently of the engine's imagery reader), its grid compared with the DEM's, and the material
// a map point's colour shows: the base colour (terrain/mining_dump_ortho.h) nearest the mean of the
// 3 x 3 pixels around the point's pixel.
#pragma once

#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/terrain/mining_dump_ortho.h"

#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

namespace nestwalk::test {

class OrthoProbe {
 public:
  explicit OrthoProbe(const std::filesystem::path& file) {
    terrain::initGdal();
    ds_ = GDALOpen(file.c_str(), GA_ReadOnly);
    EXPECT_NE(ds_, nullptr) << file;
    if (ds_) GDALGetGeoTransform(ds_, gt_);
  }
  ~OrthoProbe() {
    if (ds_) GDALClose(ds_);
  }
  OrthoProbe(const OrthoProbe&) = delete;
  OrthoProbe& operator=(const OrthoProbe&) = delete;

  GDALDatasetH dataset() const { return ds_; }

  /// Expects the orthophoto to be RGB 8-bit (with overviews when larger than a tile) on exactly the grid of the raster at
  /// `dem` (size, geotransform, CRS).
  void expectOnTheGridOf(const std::filesystem::path& dem) const {
    ASSERT_NE(ds_, nullptr);
    GDALDatasetH d = GDALOpen(dem.c_str(), GA_ReadOnly);
    ASSERT_NE(d, nullptr) << dem;
    EXPECT_EQ(GDALGetRasterXSize(ds_), GDALGetRasterXSize(d));
    EXPECT_EQ(GDALGetRasterYSize(ds_), GDALGetRasterYSize(d));
    double gt[6];
    ASSERT_EQ(GDALGetGeoTransform(d, gt), CE_None);
    for (int k = 0; k < 6; ++k) EXPECT_DOUBLE_EQ(gt_[k], gt[k]) << "geotransform[" << k << "]";
    OGRSpatialReferenceH a = OSRNewSpatialReference(GDALGetProjectionRef(ds_));
    OGRSpatialReferenceH b = OSRNewSpatialReference(GDALGetProjectionRef(d));
    EXPECT_TRUE(OSRIsSame(a, b)) << GDALGetProjectionRef(ds_);
    OSRDestroySpatialReference(a);
    OSRDestroySpatialReference(b);
    GDALClose(d);
    ASSERT_EQ(GDALGetRasterCount(ds_), 3);
    for (int band = 1; band <= 3; ++band)
      EXPECT_EQ(GDALGetRasterDataType(GDALGetRasterBand(ds_, band)), GDT_Byte);
    // Overviews down to one 512-pixel tile (terrain_imagery.h, writeImageryCog), for cheap coarse reads.
    if (std::max(GDALGetRasterXSize(ds_), GDALGetRasterYSize(ds_)) > 512) {
      EXPECT_GE(GDALGetOverviewCount(GDALGetRasterBand(ds_, 1)), 1) << "overviews, for cheap coarse reads";
    }
  }

  /// The material the colour around map (x, y) shows ("top", "face", ...: dumpSurfaceName).
  std::string materialAt(double x, double y) const {
    if (!ds_) return "";
    const int col = int(std::floor((x - gt_[0]) / gt_[1])), row = int(std::floor((y - gt_[3]) / gt_[5]));
    double mean[3] = {0, 0, 0};
    for (int band = 1; band <= 3; ++band) {
      unsigned char px[9];
      if (GDALRasterIO(GDALGetRasterBand(ds_, band), GF_Read, col - 1, row - 1, 3, 3, px, 3, 3, GDT_Byte, 0, 0) !=
          CE_None) {
        ADD_FAILURE() << "cannot read the orthophoto around " << x << ", " << y;
        return "";
      }
      for (unsigned char v : px) mean[band - 1] += v / 9.0;
    }
    int nearest = 0;
    double best = 1e9;
    for (int m = 0; m < terrain::kDumpSurfaceCount; ++m) {
      const auto& base = terrain::kDumpSurfaceColours[std::size_t(m)];
      const double d = std::hypot(mean[0] - base[0], mean[1] - base[1], mean[2] - base[2]);
      if (d < best) best = d, nearest = m;
    }
    return terrain::dumpSurfaceName(terrain::DumpSurface(nearest));
  }

 private:
  GDALDatasetH ds_ = nullptr;
  double gt_[6] = {0, 1, 0, 0, 0, -1};
};

}  // namespace nestwalk::test
