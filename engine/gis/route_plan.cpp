#include "nestwalk/gis/route_plan.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/gis/layer_features.h"
#include "nestwalk/gis/ogr_source.h"
#include "nestwalk/scene/scene_file.h"
#include "nestwalk/terrain/paged_heightfield.h"

#include <filesystem>

namespace nestwalk::gis {

RouteScript planRoute(const std::string& sceneFile, const RouteRequest& request) {
  const SceneSpec spec = readSceneFile(sceneFile);
  const terrain::Heightfield terrain = terrain::openTerrainHeightfield(spec.terrain);
  if (terrain.crsWkt().empty())
    throw InputError(spec.terrain + ": the scene's terrain has no CRS, so a route cannot be placed on it");
  RouteScriptOptions options = request.script;
  options.eyeHeight = spec.viewer.eyeHeight;
  options.stops.clear();
  const Route route = readRoute(request.route, terrain.crsWkt());
  if (!request.stops.empty()) {
    LayerSelection stops;
    std::error_code ec;
    if (std::filesystem::is_regular_file(request.stops, ec)) {
      // A file of stops: its point layers (a GPX's waypoints; not its track or route points).
      stops.sources = {request.stops};
      const Dataset ds = openVectorSource(request.stops);
      for (int i = 0; i < GDALDatasetGetLayerCount(ds.get()); ++i) {
        OGRLayerH l = GDALDatasetGetLayer(ds.get(), i);
        const std::string name = OGR_L_GetName(l);
        const OGRwkbGeometryType t = wkbFlatten(OGR_L_GetGeomType(l));
        if ((t == wkbPoint || t == wkbMultiPoint) && name != "track_points" && name != "route_points")
          stops.layers.push_back(name);
      }
      if (stops.layers.empty()) throw InputError(request.stops + ": --stops: has no point layer");
    } else {
      const Dataset ds = openVectorSource(request.route.source);
      if (!GDALDatasetGetLayerByName(ds.get(), request.stops.c_str()))
        throw InputError("--stops " + request.stops + ": neither a file nor a layer of " + request.route.source);
      stops.sources = {request.route.source};
      stops.layers = {request.stops};
    }
    stops.assumedCrs = request.route.assumedCrs;
    stops.defaultType = "stop";
    stops.fields.type = "";  // every point is a stop, whatever its fields
    const LayerFeatures read = readLayerFeatures(stops, terrain.crsWkt());
    if (!read.problems.empty())
      throw InputError(read.problems.front().where + ": " + read.problems.front().problem);
    for (const MapFeature& f : read.features) {
      if (f.shape != FeatureShape::Point) throw InputError(f.where + ": a stop is a point, not a line");
      options.stops.push_back({f.points.front(), f.name.empty() ? f.layer + "#" + std::to_string(f.fid) : f.name, f.where});
    }
  }
  return routeScript(route, terrain, options);
}

}  // namespace nestwalk::gis
