#include "nestwalk/gis/route_source.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/gis/ogr_source.h"
#include "nestwalk/terrain/dem_reader.h"

#include <cpl_error.h>
#include <cpl_time.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <set>

namespace nestwalk::gis {
namespace {

bool isLineType(OGRwkbGeometryType t) {
  t = wkbFlatten(t);
  return t == wkbLineString || t == wkbMultiLineString;
}

/// The GPX layer's points layer: `tracks` -> `track_points`, `routes` -> `route_points`.
std::string gpxPointsLayer(const std::string& lineLayer) {
  if (lineLayer == "tracks") return "track_points";
  if (lineLayer == "routes") return "route_points";
  return {};
}

/// The time field as seconds since the Unix epoch (UTC), nullopt when unset; InputError naming
/// `where` when it is set but not a date and time.
std::optional<double> timeField(OGRFeatureH f, int field, const std::string& where) {
  if (field < 0 || !OGR_F_IsFieldSetAndNotNull(f, field)) return std::nullopt;
  int year = 0, month = 0, day = 0, hour = 0, minute = 0, zone = 0;
  float second = 0;
  if (!OGR_F_GetFieldAsDateTimeEx(f, field, &year, &month, &day, &hour, &minute, &second, &zone) || year <= 0)
    throw InputError(where + ": time '" + textField(f, field) + "' is not a date and time");
  std::tm tm{};
  tm.tm_year = year - 1900;
  tm.tm_mon = month - 1;
  tm.tm_mday = day;
  tm.tm_hour = hour;
  tm.tm_min = minute;
  tm.tm_sec = 0;
  // OGR's zone flag: 100 is UTC, 100 +- n is n quarter hours east/west of it; 0 (unknown) and 1
  // (local time) are taken as UTC.
  const double offsetSeconds = zone > 1 ? (zone - 100) * 15.0 * 60.0 : 0.0;
  return double(CPLYMDHMSToUnixTime(&tm)) + double(second) - offsetSeconds;
}

class RouteReader {
 public:
  RouteReader(const RouteSelection& sel, const std::string& targetCrs)
      : sel_(sel), ds_(openVectorSource(sel.source)), target_(srsFrom(targetCrs, "the terrain")) {
    const char* driver = GDALGetDriverShortName(GDALGetDatasetDriver(ds_.get()));
    gpx_ = driver && std::string(driver) == "GPX";
  }

  Route read() {
    OGRLayerH layer = chooseLayer();
    route_.source = sel_.source;
    route_.layer = OGR_L_GetName(layer);
    const std::string what = sel_.source + ": layer '" + route_.layer + "'";
    const std::unique_ptr<LayerTransform> transform = transformOf(layer, what);
    if (!sel_.where.empty()) {
      CPLErrorReset();
      if (OGR_L_SetAttributeFilter(layer, sel_.where.c_str()) != OGRERR_NONE)
        throw InputError(what + ": --where '" + sel_.where + "': " + terrain::lastGdalError());
    }
    // The features in id order (most drivers give them so; GPX, GeoJSON and CSV always do).
    std::vector<Feature> features;
    OGR_L_ResetReading(layer);
    for (Feature f(OGR_L_GetNextFeature(layer)); f; f.reset(OGR_L_GetNextFeature(layer))) features.push_back(std::move(f));
    if (features.empty())
      throw InputError(what + (sel_.where.empty() ? ": has no features" : ": --where '" + sel_.where + "' matches no feature"));
    std::stable_sort(features.begin(), features.end(),
                     [](const Feature& a, const Feature& b) { return OGR_F_GetFID(a.get()) < OGR_F_GetFID(b.get()); });
    route_.features = features.size();
    const std::string pointsLayer = gpx_ ? gpxPointsLayer(route_.layer) : std::string();
    if (!pointsLayer.empty()) {
      std::set<GIntBig> fids;
      for (const Feature& f : features) fids.insert(OGR_F_GetFID(f.get()));
      readGpxPoints(pointsLayer, fids, *transform);
    } else {
      for (const Feature& f : features) readLine(f.get(), what, *transform);
    }
    if (route_.points.size() < 2)
      throw InputError(what + ": the route has " + std::to_string(route_.points.size()) +
                       " point(s); a route needs a line of at least two");
    return std::move(route_);
  }

 private:
  /// The named layer, else the default one (see route_source.h).
  OGRLayerH chooseLayer() {
    if (!sel_.layer.empty()) {
      OGRLayerH l = GDALDatasetGetLayerByName(ds_.get(), sel_.layer.c_str());
      if (!l) throw InputError(sel_.source + ": has no layer '" + sel_.layer + "' (" + layerList() + ")");
      if (gpx_ && gpxPointsLayer(sel_.layer).empty())
        throw InputError(sel_.source + ": layer '" + sel_.layer + "' holds points, not a line: give --layer tracks or routes");
      return l;
    }
    if (gpx_) {
      for (const char* name : {"tracks", "routes"}) {
        OGRLayerH l = GDALDatasetGetLayerByName(ds_.get(), name);
        if (l && OGR_L_GetFeatureCount(l, TRUE) > 0) return l;
      }
      throw InputError(sel_.source + ": has no track and no route (a GPX of waypoints only is not a line)");
    }
    std::vector<OGRLayerH> withFeatures;
    for (int i = 0; i < GDALDatasetGetLayerCount(ds_.get()); ++i) {
      OGRLayerH l = GDALDatasetGetLayer(ds_.get(), i);
      if (wkbFlatten(OGR_L_GetGeomType(l)) != wkbNone && OGR_L_GetFeatureCount(l, TRUE) > 0) withFeatures.push_back(l);
    }
    if (withFeatures.empty()) throw InputError(sel_.source + ": has no layer with features");
    if (withFeatures.size() > 1) {
      std::vector<OGRLayerH> lines;
      for (OGRLayerH l : withFeatures)
        if (isLineType(OGR_L_GetGeomType(l))) lines.push_back(l);
      if (lines.size() != 1)
        throw InputError(sel_.source + ": has several layers (" + layerList() + "): name the route's with --layer");
      return lines[0];
    }
    return withFeatures[0];
  }

  std::string layerList() const {
    std::string out;
    for (int i = 0; i < GDALDatasetGetLayerCount(ds_.get()); ++i)
      out += (i ? ", " : "") + std::string(OGR_L_GetName(GDALDatasetGetLayer(ds_.get(), i)));
    return out.empty() ? "no layers" : "layers: " + out;
  }

  std::unique_ptr<LayerTransform> transformOf(OGRLayerH layer, const std::string& what) {
    const Srs srs = layerSrs(layer, sel_.assumedCrs, what);
    route_.crs = srsName(srs.get());
    return std::make_unique<LayerTransform>(srs.get(), target_.get(), what);
  }

  void addPoint(double x, double y, std::optional<double> z, std::optional<double> time, std::string where,
                const LayerTransform& transform) {
    RoutePoint p;
    if (!transform.point(x, y, p.map))
      throw InputError(where + ": cannot be transformed to the terrain's CRS (from " + route_.crs + ")");
    p.z = z;
    p.time = time;
    p.where = std::move(where);
    route_.points.push_back(std::move(p));
  }

  void readLine(OGRFeatureH f, const std::string& what, const LayerTransform& transform) {
    const std::string where = what + " feature " + std::to_string(OGR_F_GetFID(f));
    OGRGeometryH g = OGR_F_GetGeometryRef(f);
    if (!g || OGR_G_IsEmpty(g)) throw InputError(where + ": has no geometry");
    const OGRwkbGeometryType t = wkbFlatten(OGR_G_GetGeometryType(g));
    if (!isLineType(t))
      throw InputError(where + ": is a " + OGRGeometryTypeToName(t) +
                       ", not a line (a route is a LineString or MultiLineString; points only are no route)");
    std::vector<OGRGeometryH> parts;
    if (t == wkbLineString) parts.push_back(g);
    else
      for (int i = 0; i < OGR_G_GetGeometryCount(g); ++i) parts.push_back(OGR_G_GetGeometryRef(g, i));
    int index = 0;
    for (OGRGeometryH part : parts) {
      const bool hasZ = OGR_G_Is3D(part) != 0;
      for (int i = 0; i < OGR_G_GetPointCount(part); ++i, ++index) {
        const std::string point = where + " point " + std::to_string(index);
        std::optional<double> z;
        if (hasZ) {
          z = OGR_G_GetZ(part, i);
          if (!std::isfinite(*z)) throw InputError(point + ": its height is not a finite number");
        }
        addPoint(OGR_G_GetX(part, i), OGR_G_GetY(part, i), z, std::nullopt, point, transform);
      }
    }
  }

  /// A GPX line's points from its points layer, in file order, with their ele and time.
  void readGpxPoints(const std::string& layerName, const std::set<GIntBig>& fids, const LayerTransform& transform) {
    OGRLayerH layer = GDALDatasetGetLayerByName(ds_.get(), layerName.c_str());
    const std::string what = sel_.source + ": layer '" + layerName + "'";
    if (!layer) throw InputError(what + ": not found (GDAL's GPX driver gives it beside '" + route_.layer + "')");
    OGRFeatureDefnH defn = OGR_L_GetLayerDefn(layer);
    const int owner = OGR_FD_GetFieldIndex(defn, layerName == "track_points" ? "track_fid" : "route_fid");
    const int ele = OGR_FD_GetFieldIndex(defn, "ele"), time = OGR_FD_GetFieldIndex(defn, "time");
    if (owner < 0) throw InputError(what + ": has no field naming its line");
    OGR_L_ResetReading(layer);
    for (Feature f(OGR_L_GetNextFeature(layer)); f; f.reset(OGR_L_GetNextFeature(layer))) {
      if (!fids.count(OGR_F_GetFieldAsInteger64(f.get(), owner))) continue;
      const std::string where = what + " feature " + std::to_string(OGR_F_GetFID(f.get()));
      OGRGeometryH g = OGR_F_GetGeometryRef(f.get());
      if (!g || OGR_G_IsEmpty(g) || wkbFlatten(OGR_G_GetGeometryType(g)) != wkbPoint)
        throw InputError(where + ": has no point");
      bool ok = true;
      const std::optional<double> z = numberField(f.get(), ele, ok);
      if (!ok) throw InputError(where + ": ele '" + textField(f.get(), ele) + "' is not a number (metres)");
      addPoint(OGR_G_GetX(g, 0), OGR_G_GetY(g, 0), z, timeField(f.get(), time, where), where, transform);
    }
  }

  const RouteSelection& sel_;
  Dataset ds_;
  Srs target_;
  bool gpx_ = false;
  Route route_;
};

}  // namespace

bool Route::timed() const {
  return std::all_of(points.begin(), points.end(), [](const RoutePoint& p) { return p.time.has_value(); });
}

bool Route::hasZ() const {
  return std::all_of(points.begin(), points.end(), [](const RoutePoint& p) { return p.z.has_value(); });
}

Route readRoute(const RouteSelection& selection, const std::string& targetCrs) {
  return RouteReader(selection, targetCrs).read();
}

}  // namespace nestwalk::gis
