// The route options shared by `nestwalk route` and `run --route` (engine/gis/route_plan.h): the
// layer, filter and CRS of the route, walking or flying, height, speed, recorded times and stops.
#pragma once

#include "nestwalk/gis/route_plan.h"

#include <CLI/CLI.hpp>

#include <string>

namespace nestwalk::tools {

struct RouteArgs {
  gis::RouteRequest request;  // request.route.source: the ROUTE (positional in `route`, --route in `run`)
  std::string mode = "walk";
  double height = 0, speed = 0;  // 0: not given
};

/// --layer, --where, --layer-crs, --mode, --height, --speed, --use-times, --stops, --stop-distance,
/// --stop-wait; with routeOption, --route ROUTE too (`run`; `route` takes it as its second argument).
void addRouteOptions(CLI::App& cmd, RouteArgs& args, bool routeOption);

/// The script of the route for the scene; InputError for a bad option or route.
gis::RouteScript planRouteArgs(const std::string& scene, RouteArgs& args);

/// `run`'s choice between --script and --route (exactly one; InputError otherwise): "" for a
/// script, else the route's script text, with `script` set to the route's source (for messages).
std::string scriptOrRoute(const std::string& scene, std::string& script, RouteArgs& args);

}  // namespace nestwalk::tools
