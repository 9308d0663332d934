// The generators' map-to-geographic conversion: points of the site's projected CRS to WGS 84
// longitude and latitude (traditional GIS order, x east) through OGR/PROJ, and grid headings to
// true azimuths along the WGS 84 geodesic. Used to write inputs the way a user's GPS or GIS gives
// them (the GIS sample's GeoPackage, the bundled GPS tracks).
// Errors: std::runtime_error when a CRS or point cannot be transformed. Thread safety: an object
// belongs to one thread.
#pragma once

#include <Eigen/Core>
#include <geodesic.h>
#include <ogr_spatialref.h>

#include <memory>

namespace nestwalk::assets {

class ToLonLat {
 public:
  explicit ToLonLat(const char* crs);
  const OGRSpatialReference& wgs84() const { return wgs84_; }

  Eigen::Vector2d operator()(const Eigen::Vector2d& p) const;
  /// The true azimuth (degrees clockwise from north, [0, 360)) of the grid heading at p: the
  /// geodesic between the points kHeadingBaseline (0.5 m) either side, its mean azimuth.
  double trueAzimuth(const Eigen::Vector2d& p, double gridHeadingDeg) const;

 private:
  OGRSpatialReference map_, wgs84_;
  std::unique_ptr<OGRCoordinateTransformation> transform_;
  geod_geodesic geodesic_;
};

}  // namespace nestwalk::assets
