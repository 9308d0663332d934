// Reading a user's equipment layers with OGR: point layers (each feature one instance) and line
// layers (each feature a fence or barrier row), from any vector source OGR reads: GeoPackage,
// Shapefile, GeoJSON, KML, or CSV with X/Y or WKT columns. Features come out in the map frame of a
// target CRS (the terrain's), through OGR/PROJ, with their attributes read by field name.
//
// CRS: each layer's own; a layer without one (a CSV) takes LayerSelection::assumedCrs, or is an
// error. Both ends use the traditional GIS axis order (east first: longitude, latitude for
// EPSG:4326), set explicitly, whatever the CRS's official order.
//
// Geometry: Point -> a point feature; LineString -> a line; Polygon -> its outer ring as a closed
// line (a fence around an area); MultiPoint, MultiLineString, MultiPolygon -> one feature per
// part (named "<name>#<part>"). Z values are ignored (heights come from the terrain). Anything
// else (geometry collections, empty or missing geometry) is a problem of that feature.
//
// Headings (the heading field, degrees): an azimuth clockwise from north, where north is the layer
// CRS's north: true north for a geographic layer (EPSG:4326), the grid's +y for a projected one.
// It is turned into the target CRS's grid azimuth at the feature's position: the direction is
// carried through the transformation (two points half a millimetre either side along the heading:
// on the ellipsoid, with its meridian and prime-vertical radii, for a geographic layer), so the
// local grid convergence (and any rotation between projected CRSs) is applied.
//
// Problems of single features (unknown geometry, a heading or scale that is not a number, a
// transformation that fails) are collected with the source, layer and feature id; problems of a
// whole source or layer (cannot be opened, no such layer, no CRS, a bad --where, a --where that
// matches nothing, an empty layer, no type field) throw InputError.
//
// Thread safety: each call opens its own datasets, spatial references and transformations and frees
// them before it returns, so calls share no GDAL object of their own; GDAL's last-error text is per
// thread. The first call runs initGdal (terrain/dem_reader.h), which sets process-wide GDAL
// options.
// Locale: heading and scale fields given as text are parsed with std::strtod, which follows the
// process's C locale (LC_NUMERIC); nestwalk never changes it, and under the default "C" locale the
// decimal mark is '.'.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace nestwalk::gis {

/// The attribute fields features are read by (case-insensitive, as OGR matches field names).
struct LayerFieldNames {
  std::string type = "type";        // the catalog type (required, unless defaultType is given)
  std::string name = "name";        // the instance's name (optional)
  std::string heading = "heading";  // degrees clockwise from north (optional, 0)
  std::string scale = "scale";      // uniform scale (optional: the type's)
  std::string group = "group";      // the template hierarchy's group path (optional)
};

struct LayerSelection {
  std::vector<std::string> sources;  // vector files or any OGR dataset names
  std::vector<std::string> layers;   // read only these layer names (empty: every point and line layer)
  std::string where;                 // an OGR attribute filter (SQL WHERE clause) for every layer read
  std::string assumedCrs;            // the CRS of layers that have none ("EPSG:4326"; "": an error)
  std::string defaultType;           // the type of features in layers without the type field ("": error)
  LayerFieldNames fields;
};

enum class FeatureShape : std::uint8_t { Point, Line, Ring };  // ring: closed (a polygon's outline)

struct MapFeature {
  std::string where;           // "points.gpkg: layer 'equipment' feature 12" (messages)
  std::string source, layer;
  std::int64_t fid = 0;
  FeatureShape shape = FeatureShape::Point;
  std::vector<Eigen::Vector2d> points;  // target CRS, map coordinates (a ring does not repeat its first point)
  std::string type, name, group;        // name: "" when the feature has none
  double headingDeg = 0;                // target grid azimuth, clockwise from the grid's +y
  std::optional<double> scale;
};

struct FeatureProblem {
  std::string where, problem;
  std::string source, layer;  // for ordering: by source, layer and feature id
  std::int64_t fid = 0;
};

struct LayerRead {
  std::string source, layer, crs;  // crs: the layer's CRS name as OGR gives it
  std::size_t features = 0;        // after the --where filter
};

struct LayerFeatures {
  std::vector<MapFeature> features;
  std::vector<FeatureProblem> problems;
  std::vector<LayerRead> layers;
};

/// Reads the selected layers (see above) into `targetCrs` (WKT or anything OGR's SetFromUserInput
/// takes). Throws InputError for problems of a whole source or layer.
LayerFeatures readLayerFeatures(const LayerSelection& selection, const std::string& targetCrs);

}  // namespace nestwalk::gis
