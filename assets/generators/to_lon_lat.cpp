#include "assets/generators/to_lon_lat.h"

#include "nestwalk/core/angles.h"

#include <stdexcept>
#include <string>

namespace nestwalk::assets {
namespace {

constexpr double kHeadingBaseline = 0.5;  // metres either side of a point along its grid heading

}  // namespace

ToLonLat::ToLonLat(const char* crs) {
  map_.SetFromUserInput(crs);
  map_.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  wgs84_.importFromEPSG(4326);
  wgs84_.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  transform_.reset(OGRCreateCoordinateTransformation(&map_, &wgs84_));
  if (!transform_) throw std::runtime_error(std::string("no transformation from ") + crs + " to EPSG:4326");
  geod_init(&geodesic_, 6378137.0, 1 / 298.257223563);  // WGS 84
}

Eigen::Vector2d ToLonLat::operator()(const Eigen::Vector2d& p) const {
  double x = p.x(), y = p.y();
  if (!transform_->Transform(1, &x, &y)) throw std::runtime_error("a point could not be transformed to EPSG:4326");
  return {x, y};
}

double ToLonLat::trueAzimuth(const Eigen::Vector2d& p, double gridHeadingDeg) const {
  const auto [s, c] = sinCosDegrees(gridHeadingDeg);
  const Eigen::Vector2d step = kHeadingBaseline * Eigen::Vector2d(s, c);
  const Eigen::Vector2d a = (*this)(p - step), b = (*this)(p + step);
  double distance, azimuthA, azimuthB;
  geod_inverse(&geodesic_, a.y(), a.x(), b.y(), b.x(), &distance, &azimuthA, &azimuthB);
  return wrapDegrees360(azimuthA + 0.5 * wrapDegrees180(azimuthB - azimuthA));
}

}  // namespace nestwalk::assets
