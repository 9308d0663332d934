#include "tools/nestwalk/route_options.h"

#include "nestwalk/core/input_error.h"

namespace nestwalk::tools {

void addRouteOptions(CLI::App& cmd, RouteArgs& a, bool routeOption) {
  if (routeOption)
    cmd.add_option("--route", a.request.route.source, "Or a route to walk: a GPS track or GIS line (see `route`)");
  cmd.add_option("--layer", a.request.route.layer, "The route's layer (default: a GPX's tracks, else the one layer)");
  cmd.add_option("--where", a.request.route.where, "OGR attribute filter (SQL WHERE) choosing the route's lines");
  cmd.add_option("--layer-crs", a.request.route.assumedCrs, "CRS of a route layer that has none (a CSV)");
  cmd.add_option("--mode", a.mode, "walk (on the ground) or fly")->check(CLI::IsMember({"walk", "fly"}));
  cmd.add_option("--height", a.height, "Flying: eye height above the ground, m (default: the route's own z)")
      ->check(CLI::PositiveNumber);
  cmd.add_option("--speed", a.speed, "m/s (default: the scene's)")->check(CLI::PositiveNumber);
  cmd.add_flag("--use-times", a.request.script.useTimes, "Replay the GPX points' times: the recorded pace");
  cmd.add_option("--stops", a.request.stops,
                 "Point layer of the route's source (or a vector file) whose points to stop and look at");
  cmd.add_option("--stop-distance", a.request.script.stopDistance, "Stop at points this close to the route, m")
      ->default_val(gis::kDefaultStopDistance)->check(CLI::NonNegativeNumber);
  cmd.add_option("--stop-wait", a.request.script.stopWait, "Seconds to look at each stop")
      ->default_val(gis::kDefaultStopWait)->check(CLI::NonNegativeNumber);
}

gis::RouteScript planRouteArgs(const std::string& scene, RouteArgs& a) {
  gis::RouteScriptOptions& o = a.request.script;
  o.fly = a.mode == "fly";
  if (a.height > 0) {
    if (!o.fly) throw InputError("--height: flying only (give --mode fly)");
    o.height = a.height;
  }
  if (a.speed > 0) o.speed = a.speed;
  return gis::planRoute(scene, a.request);
}

std::string scriptOrRoute(const std::string& scene, std::string& script, RouteArgs& a) {
  const std::string& route = a.request.route.source;
  if (script.empty() == route.empty()) throw InputError("run: give --script FILE or --route ROUTE (one of them)");
  if (route.empty()) return {};
  script = route;
  return planRouteArgs(scene, a).text;
}

}  // namespace nestwalk::tools
