// nestwalk route SCENE ROUTE --out SCRIPT [route options, route_options.h] [--overwrite]: a line or
// GPS track turned into a flythrough script for the scene (engine/gis/route_plan.h). The script is
// written beside SCRIPT under a temporary name and renamed; an existing SCRIPT is replaced only
// with --overwrite. Prints one summary line.
#include "nestwalk/core/input_error.h"
#include "nestwalk/core/output_file.h"
#include "tools/nestwalk/commands.h"
#include "tools/nestwalk/route_options.h"

#include <cstdio>
#include <filesystem>
#include <memory>

namespace nestwalk::tools {
namespace {

struct RouteCommandArgs {
  std::string scene, out;
  bool overwrite = false;
  RouteArgs route;
};

void runRoute(RouteCommandArgs& a) {
  if (std::filesystem::exists(a.out) && !a.overwrite) throw InputError(a.out + ": exists; pass --overwrite to replace it");
  const gis::RouteScript script = planRouteArgs(a.scene, a.route);
  writeFileAtomically(a.out, script.text);
  std::printf("%s: %zu gotos, %.1f m%s, %zu stop(s)%s\n", a.out.c_str(), script.gotos, script.length,
              a.route.request.script.useTimes ? (", " + std::to_string(int(script.duration + 0.5)) + " s as recorded").c_str() : "",
              script.stops,
              script.dropped ? (", " + std::to_string(script.dropped) + " repeated point(s) left out").c_str() : "");
}

}  // namespace

void registerRoute(CLI::App& app) {
  auto args = std::make_shared<RouteCommandArgs>();
  CLI::App* cmd = app.add_subcommand("route", "Turn a GIS line or GPS track into a flythrough script for a scene");
  cmd->add_option("SCENE", args->scene, "Scene file (JSON): its terrain's CRS and ground")->required();
  cmd->add_option("ROUTE", args->route.request.route.source,
                  "The route: a GPX track or route, or a line in any vector file OGR reads")->required();
  cmd->add_option("--out", args->out, "The script to write (replaced only with --overwrite)")->required();
  addRouteOptions(*cmd, args->route, /*routeOption=*/false);
  cmd->add_flag("--overwrite", args->overwrite, "Replace an existing script");
  cmd->callback([args] { runRoute(*args); });
}

}  // namespace nestwalk::tools
