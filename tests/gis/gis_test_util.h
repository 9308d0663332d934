// Shared by the GIS tests: a UTM terrain written with GDAL, box models and a catalog, layers of
// equipment written with OGR in any format, and PROJ's own answers (positions through
// proj_trans, headings through a geodesic on the ellipsoid) to check the code under test against.
#pragma once

#include "tests/common/box_model.h"
#include "tests/common/temp_folder.h"

#include <Eigen/Core>
#include <cpl_conv.h>
#include <gdal.h>
#include <geodesic.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <ogr_api.h>
#include <ogr_srs_api.h>
#include <osg/Geode>
#include <osg/Geometry>
#include <osgDB/WriteFile>
#include <proj.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace nestwalk::test {

/// A feature as the tests write it: geographic (longitude, latitude) points, and its attributes.
struct GeoFeature {
  std::string type, name;
  std::optional<double> heading;
  std::vector<Eigen::Vector2d> lonLat;  // one point, or a line
};

/// A UTM terrain: `size` x `size` samples of 1 m around (east, north) in EPSG:`epsg`, heights a
/// gentle plane with small waves (exact in float).
struct UtmTerrain {
  int epsg = 32612;
  double west = 0, north = 0;  // the raster's outer corner
  int size = 400;
  double height(double x, double y) const {
    return 1000.0 + 0.02 * (x - west) + 0.01 * (north - y) + std::sin((x - west) * 0.05) * 0.5;
  }
};

inline void writeUtmTerrain(const std::filesystem::path& path, const UtmTerrain& t,
                            std::optional<std::pair<int, int>> holeAt = std::nullopt) {
  GDALAllRegister();
  GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), path.c_str(), t.size, t.size, 1, GDT_Float32, nullptr);
  ASSERT_NE(ds, nullptr);
  double gt[6] = {t.west, 1.0, 0.0, t.north, 0.0, -1.0};
  GDALSetGeoTransform(ds, gt);
  OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
  OSRImportFromEPSG(srs, t.epsg);
  char* wkt = nullptr;
  OSRExportToWkt(srs, &wkt);
  GDALSetProjection(ds, wkt);
  CPLFree(wkt);
  OSRDestroySpatialReference(srs);
  std::vector<float> h(std::size_t(t.size) * std::size_t(t.size));
  for (int r = 0; r < t.size; ++r)
    for (int c = 0; c < t.size; ++c) h[std::size_t(r) * std::size_t(t.size) + std::size_t(c)] = float(t.height(t.west + c + 0.5, t.north - r - 0.5));
  GDALRasterBandH band = GDALGetRasterBand(ds, 1);
  if (holeAt) {
    GDALSetRasterNoDataValue(band, -9999.0);
    for (int r = holeAt->second - 3; r <= holeAt->second + 3; ++r)
      for (int c = holeAt->first - 3; c <= holeAt->first + 3; ++c) h[std::size_t(r) * std::size_t(t.size) + std::size_t(c)] = -9999.0f;
  }
  ASSERT_EQ(GDALRasterIO(band, GF_Write, 0, 0, t.size, t.size, h.data(), t.size, t.size, GDT_Float32, 0, 0), CE_None);
  GDALClose(ds);
}


/// Adds `features` to the open vector dataset `ds` as one layer named `layer` in EPSG:4326; fields
/// type, name, heading (real).
inline void addGeoLayer(GDALDatasetH ds, const char* layer, const std::vector<GeoFeature>& features) {
  OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
  OSRImportFromEPSG(srs, 4326);
  OSRSetAxisMappingStrategy(srs, OAMS_TRADITIONAL_GIS_ORDER);
  const bool lines = features.size() > 0 && features[0].lonLat.size() > 1;
  OGRLayerH l = GDALDatasetCreateLayer(ds, layer, srs, lines ? wkbLineString : wkbPoint, nullptr);
  ASSERT_NE(l, nullptr);
  for (const char* f : {"type", "name"}) {
    OGRFieldDefnH d = OGR_Fld_Create(f, OFTString);
    OGR_L_CreateField(l, d, TRUE);
    OGR_Fld_Destroy(d);
  }
  OGRFieldDefnH h = OGR_Fld_Create("heading", OFTReal);
  OGR_L_CreateField(l, h, TRUE);
  OGR_Fld_Destroy(h);
  for (const GeoFeature& f : features) {
    OGRFeatureH feature = OGR_F_Create(OGR_L_GetLayerDefn(l));
    OGR_F_SetFieldString(feature, OGR_F_GetFieldIndex(feature, "type"), f.type.c_str());
    if (!f.name.empty()) OGR_F_SetFieldString(feature, OGR_F_GetFieldIndex(feature, "name"), f.name.c_str());
    if (f.heading) OGR_F_SetFieldDouble(feature, OGR_F_GetFieldIndex(feature, "heading"), *f.heading);
    OGRGeometryH g = OGR_G_CreateGeometry(f.lonLat.size() > 1 ? wkbLineString : wkbPoint);
    for (const auto& p : f.lonLat) OGR_G_AddPoint_2D(g, p.x(), p.y());
    OGR_F_SetGeometryDirectly(feature, g);
    ASSERT_EQ(OGR_L_CreateFeature(l, feature), OGRERR_NONE);
    OGR_F_Destroy(feature);
  }
  OSRDestroySpatialReference(srs);
}

/// Writes `features` as a new file with one layer, with OGR's `driver` (GPKG, ESRI Shapefile,
/// GeoJSON, LIBKML).
inline void writeGeoLayer(const std::filesystem::path& path, const char* driver, const char* layer,
                          const std::vector<GeoFeature>& features) {
  GDALAllRegister();
  GDALDatasetH ds = GDALCreate(GDALGetDriverByName(driver), path.c_str(), 0, 0, 0, GDT_Unknown, nullptr);
  ASSERT_NE(ds, nullptr) << driver;
  addGeoLayer(ds, layer, features);
  GDALClose(ds);
}

/// PROJ's own answers, independent of the code under test.
class ProjOracle {
 public:
  explicit ProjOracle(int utmEpsg) {
    ctx_ = proj_context_create();
    PJ* p = proj_create_crs_to_crs(ctx_, "EPSG:4326", ("EPSG:" + std::to_string(utmEpsg)).c_str(), nullptr);
    pj_ = proj_normalize_for_visualization(ctx_, p);  // longitude, latitude in; east, north out
    proj_destroy(p);
    geod_init(&geodesic_, 6378137.0, 1.0 / 298.257223563);  // WGS 84
  }
  ~ProjOracle() {
    proj_destroy(pj_);
    proj_context_destroy(ctx_);
  }
  ProjOracle(const ProjOracle&) = delete;
  ProjOracle& operator=(const ProjOracle&) = delete;

  Eigen::Vector2d toUtm(const Eigen::Vector2d& lonLat) const {
    const PJ_COORD c = proj_trans(pj_, PJ_FWD, proj_coord(lonLat.x(), lonLat.y(), 0, 0));
    return {c.xy.x, c.xy.y};
  }
  /// The grid azimuth (degrees clockwise from grid north) of the true azimuth `heading` at
  /// `lonLat`: the geodesic half a metre either way along it, both ends projected.
  double gridHeading(const Eigen::Vector2d& lonLat, double heading) const {
    double lat2, lon2, lat1, lon1;
    geod_direct(&geodesic_, lonLat.y(), lonLat.x(), heading, 0.5, &lat2, &lon2, nullptr);
    geod_direct(&geodesic_, lonLat.y(), lonLat.x(), heading + 180.0, 0.5, &lat1, &lon1, nullptr);
    const Eigen::Vector2d d = toUtm({lon2, lat2}) - toUtm({lon1, lat1});
    double h = std::atan2(d.x(), d.y()) * 180.0 / std::numbers::pi;
    return h < 0 ? h + 360.0 : h;
  }
  /// The geographic position of a UTM point (for placing test features inside a terrain).
  Eigen::Vector2d toLonLat(const Eigen::Vector2d& utm) const {
    const PJ_COORD c = proj_trans(pj_, PJ_INV, proj_coord(utm.x(), utm.y(), 0, 0));
    return {c.lp.lam, c.lp.phi};
  }

 private:
  PJ_CONTEXT* ctx_;
  PJ* pj_;
  geod_geodesic geodesic_;
};

}  // namespace nestwalk::test
