// A route for a scene, the whole of `nestwalk route` and `run --route`: the scene file's terrain
// opened (paged from its pyramid when it has one: the terrain's size does not matter), the route
// read in the terrain's CRS (route_source.h), the stops read from a point layer
// (layer_features.h), and the script written (route_script.h) with the scene's eye height.
//
// Stops: `stops` names a layer of the route's own source (a GPX's `waypoints`, a GeoPackage's
// `instruments`), or a vector file whose point layers are all read (a GPX's waypoints, not its
// track or route points); every point is a stop, named by its `name` field (else
// "<layer>#<feature id>"). Neither a file nor a layer of the route's source: InputError.
//
// Errors: InputError, as the parts say (the scene file, its terrain, the route, the stops).
// Thread safety: as readRoute (GDAL objects of its own).
#pragma once

#include "nestwalk/gis/route_script.h"
#include "nestwalk/gis/route_source.h"

#include <string>

namespace nestwalk::gis {

struct RouteRequest {
  RouteSelection route;
  std::string stops;            // "" : none (see above)
  RouteScriptOptions script;    // its stops and eyeHeight are filled in here
};

RouteScript planRoute(const std::string& sceneFile, const RouteRequest& request);

}  // namespace nestwalk::gis
