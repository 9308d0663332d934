// nestwalk route SCENE ROUTE --out SCRIPT [--layer NAME] [--where SQL] [--layer-crs CRS]
// [--mode walk|fly] [--height H] [--speed V] [--use-times] [--stops LAYER] [--stop-distance M]
// [--stop-wait S] [--overwrite]: a line or GPS track turned into a flythrough script for the scene
// (engine/gis/route_plan.h). The script is written beside SCRIPT under a temporary name and renamed;
// an existing SCRIPT is replaced only with --overwrite. Prints one summary line.
#include "nestwalk/core/input_error.h"
#include "nestwalk/core/output_file.h"
#include "nestwalk/gis/route_plan.h"
#include "tools/nestwalk/commands.h"

#include <cstdio>
#include <filesystem>
#include <memory>

namespace nestwalk::tools {
namespace {

struct RouteArgs {
  std::string scene, out, mode = "walk";
  bool overwrite = false;
  double height = 0, speed = 0;
  gis::RouteRequest request;
};

void runRoute(RouteArgs& a) {
  if (std::filesystem::exists(a.out) && !a.overwrite) throw InputError(a.out + ": exists; pass --overwrite to replace it");
  gis::RouteScriptOptions& o = a.request.script;
  o.fly = a.mode == "fly";
  if (a.height > 0) {
    if (!o.fly) throw InputError("--height: flying only (give --mode fly)");
    o.height = a.height;
  }
  if (a.speed > 0) o.speed = a.speed;
  const gis::RouteScript script = gis::planRoute(a.scene, a.request);
  writeFileAtomically(a.out, script.text);
  std::printf("%s: %zu gotos, %.1f m%s, %zu stop(s)%s\n", a.out.c_str(), script.gotos, script.length,
              o.useTimes ? (", " + std::to_string(int(script.duration + 0.5)) + " s as recorded").c_str() : "",
              script.stops,
              script.dropped ? (", " + std::to_string(script.dropped) + " repeated point(s) left out").c_str() : "");
}

}  // namespace

void registerRoute(CLI::App& app) {
  auto args = std::make_shared<RouteArgs>();
  CLI::App* cmd = app.add_subcommand("route", "Turn a GIS line or GPS track into a flythrough script for a scene");
  cmd->add_option("SCENE", args->scene, "Scene file (JSON): its terrain's CRS and ground")->required();
  cmd->add_option("ROUTE", args->request.route.source,
                  "The route: a GPX track or route, or a line in any vector file OGR reads")->required();
  cmd->add_option("--out", args->out, "The script to write (replaced only with --overwrite)")->required();
  cmd->add_option("--layer", args->request.route.layer, "The route's layer (default: a GPX's tracks, else the one layer)");
  cmd->add_option("--where", args->request.route.where, "OGR attribute filter (SQL WHERE) choosing the line features");
  cmd->add_option("--layer-crs", args->request.route.assumedCrs, "CRS of a layer that has none (a CSV), e.g. EPSG:4326");
  cmd->add_option("--mode", args->mode, "walk (on the ground) or fly")->check(CLI::IsMember({"walk", "fly"}));
  cmd->add_option("--height", args->height, "Flying: eye height above the ground, m (default: the route's own z)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--speed", args->speed, "m/s (default: the scene's)")->check(CLI::PositiveNumber);
  cmd->add_flag("--use-times", args->request.script.useTimes,
                "Replay the GPX points' times: the recorded pace, pauses included");
  cmd->add_option("--stops", args->request.stops,
                  "Point layer of the route's source (or a vector file) whose points to stop and look at");
  cmd->add_option("--stop-distance", args->request.script.stopDistance, "Stop at points this close to the route, m")
      ->default_val(gis::kDefaultStopDistance)->check(CLI::NonNegativeNumber);
  cmd->add_option("--stop-wait", args->request.script.stopWait, "Seconds to look at each stop")
      ->default_val(gis::kDefaultStopWait)->check(CLI::NonNegativeNumber);
  cmd->add_flag("--overwrite", args->overwrite, "Replace an existing script");
  cmd->callback([args] { runRoute(*args); });
}

}  // namespace nestwalk::tools
