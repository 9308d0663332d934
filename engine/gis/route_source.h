// Reading a route: a line a user drew in QGIS or a track a GPS recorded, from any vector source OGR
// reads (GPX tracks and routes, GeoPackage, Shapefile, GeoJSON, KML, CSV with a WKT column), as
// points in the terrain's CRS, in order, with their heights and times where the source has them.
//
// Which line: the layer named (RouteSelection::layer), else for a GPX file its `tracks` layer (or
// `routes` when it has no track), else the source's one layer with features; the features that
// pass the --where filter, in feature id order, each LineString or MultiLineString part in order,
// joined into one line (the gap between parts or features is walked straight).
// GPX: the points come from the layer's points layer (`track_points`, `route_points`): their
// `ele` (metres) and `time` (ISO 8601; a time zone offset applied, a time without zone taken as
// UTC). Other sources: a 3-D line's z as the height, no times.
// CRS and axis order: as layer_features.h (the layer's own CRS, or assumedCrs for one without;
// east first at both ends). Heights are not transformed (taken to be in the terrain's vertical
// datum).
//
// Errors (InputError, nothing returned): the source cannot be opened; no such layer; several line
// layers and none named; a layer of points only, or empty, or whose --where matches nothing; a
// feature whose geometry is not a line, or that cannot be transformed (naming the source, layer
// and feature id); fewer than two points in all.
//
// Thread safety: as layer_features.h (each call opens and frees its own GDAL objects).
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace nestwalk::gis {

struct RouteSelection {
  std::string source;      // a vector file or any OGR dataset name
  std::string layer;       // "" : see above
  std::string where;       // an OGR attribute filter (SQL WHERE clause) on the line layer
  std::string assumedCrs;  // the CRS of a layer that has none ("": an error)
};

struct RoutePoint {
  Eigen::Vector2d map = Eigen::Vector2d::Zero();  // terrain CRS, map coordinates
  std::optional<double> z;                        // the source's height, metres
  std::optional<double> time;                     // seconds since 1970-01-01 00:00 UTC
  std::string where;  // "walk.gpx: layer 'track_points' feature 17", "lines.gpkg: layer 'r' feature 3 point 5"
};

struct Route {
  std::string source, layer, crs;  // crs: the layer's, as OGR names it
  std::size_t features = 0;        // line features read
  std::vector<RoutePoint> points;  // in order; repeated positions kept (a GPS standing still)

  bool timed() const;  // every point has a time
  bool hasZ() const;   // every point has a height
};

/// Reads the route (see above) into `targetCrs` (WKT or anything OSRSetFromUserInput takes).
Route readRoute(const RouteSelection& selection, const std::string& targetCrs);

}  // namespace nestwalk::gis
