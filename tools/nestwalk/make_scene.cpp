// nestwalk make-scene DIR [--seed N] [--gis-inputs] [--ortho-pixel M] [--overwrite]: generates the bundled
// mining-dump scene (assets/generators/scene_generator.h): DIR/terrain.tif, DIR/ortho.tif (its synthetic
// orthophoto, the scene's draped imagery; at M metres a pixel with --ortho-pixel), DIR/models/*.osgt, DIR/scene.json and
// DIR/scripts/{bench_patrol,ramp_descent,low_flight,equipment_walk,equipment_fly}.txt, built in a temporary folder beside DIR
// and renamed to DIR at the end. An existing DIR is replaced only with --overwrite. With
// --gis-inputs it writes instead what a user brings to `nestwalk build-scene` (gis_inputs.h): a
// dump generated at a high-latitude UTM site, as a DEM, a GeoPackage, a catalog, models and the
// flythroughs.
#include "assets/generators/gis_inputs.h"
#include "assets/generators/scene_generator.h"
#include "tools/nestwalk/commands.h"

#include <cstdio>
#include <map>
#include <memory>

namespace nestwalk::tools {
namespace {

struct MakeSceneArgs {
  std::string dir;
  std::uint64_t seed = 1;
  bool overwrite = false;
  bool gisInputs = false;
  double orthoPixel = 0;  // ortho.tif's pixel, metres; 0: the terrain's cell
};

void runMakeScene(const MakeSceneArgs& args) {
  if (args.gisInputs) {
    const assets::GeneratedScene scene = assets::generateScene(args.seed, assets::kGisSampleSite);
    assets::writeGisInputs(scene, args.dir, args.overwrite);
    std::printf("wrote the GIS inputs of a generated dump (seed %llu, %s) to %s:\n"
                "  dem.tif, equipment.gpkg (layers equipment and fences, EPSG:4326), catalog.json, models/, "
                "scripts/\n"
                "build the scene with: nestwalk build-scene --terrain %s/dem.tif --equipment %s/equipment.gpkg "
                "--catalog %s/catalog.json --out SCENE_DIR\n",
                static_cast<unsigned long long>(args.seed), scene.site.crs, args.dir.c_str(), args.dir.c_str(),
                args.dir.c_str(), args.dir.c_str());
    return;
  }
  const assets::GeneratedScene scene = assets::generateScene(args.seed);
  assets::writeScene(scene, args.dir, args.overwrite, args.orthoPixel);
  std::map<std::string, int> kinds;
  for (const auto& p : scene.equipment) ++kinds[assets::modelKindLabel(p.model)];
  const auto& L = scene.dump.layout;
  const auto& P = scene.points;
  std::printf("generated %s (seed %llu)\n", args.dir.c_str(), static_cast<unsigned long long>(args.seed));
  std::printf("  terrain:    terrain.tif, %d x %d samples at %.10g m, EPSG:32651; benches every %.3f m from %.3f to %.3f m\n",
              scene.dump.cols, scene.dump.rows, scene.dump.cell, scene.geometry.benchHeight, L.baseHeight,
              L.topHeight);
  if (args.orthoPixel > 0 && args.orthoPixel < scene.dump.cell)
    std::printf("  imagery:    ortho.tif, a drone's synthetic orthophoto at %.10g m (JPEG COG; materials with gravel, "
                "stones, vegetation and tyre tracks on the ramp)\n",
                args.orthoPixel);
  else
    std::printf("  imagery:    ortho.tif, a synthetic orthophoto on the terrain's grid (RGB; materials of the top, "
                "berms, faces, ramp, ditch and ground)\n");
  std::printf("  equipment:  %zu pieces:", scene.equipment.size());
  for (const auto& [kind, n] : kinds) std::printf(" %s %d", kind.c_str(), n);
  std::printf("\n  models:     models/*.osgt (%zu)\n", assets::kAllModels.size());
  std::printf("  patrol:     scripts/bench_patrol.txt: lane blocked by %s (mast at %.3f %.3f)\n",
              P.patrolStation.c_str(), P.patrolMast.x(), P.patrolMast.y());
  std::printf("  ramp:       scripts/ramp_descent.txt: %.3f %.3f -> %.3f %.3f\n", P.rampTop.x(), P.rampTop.y(),
              P.rampToe.x(), P.rampToe.y());
  std::printf("  flight:     scripts/low_flight.txt: %.3f %.3f -> %.3f %.3f\n", P.flightStart.x(), P.flightStart.y(),
              P.flightEnd.x(), P.flightEnd.y());
  for (const auto& [file, events] : scene.tourEvents) {
    std::map<std::string, int> byKind;
    for (const auto& [group, kind] : events) ++byKind[kind];
    std::printf("  tour:       scripts/%s: %zu blocking events:", file.c_str(), events.size());
    for (const auto& [kind, n] : byKind) std::printf(" %s %d", kind.c_str(), n);
    std::printf("\n");
  }
}

}  // namespace

void registerMakeScene(CLI::App& app) {
  auto args = std::make_shared<MakeSceneArgs>();
  CLI::App* cmd = app.add_subcommand(
      "make-scene",
      "Generate the bundled mining-dump scene: terrain, equipment models (OSG native), scene.json and its scripts");
  cmd->add_option("DIR", args->dir, "Output folder; replaced only with --overwrite")->required();
  cmd->add_option("--seed", args->seed, "Random seed (same seed, same scene)")->default_val(1);
  CLI::Option* gis = cmd->add_flag("--gis-inputs", args->gisInputs,
                                    "Write GIS inputs for build-scene instead (DEM, GeoPackage, catalog, models, flythroughs)");
  cmd->add_option("--ortho-pixel", args->orthoPixel,
                  "ortho.tif's pixel in metres, finer than the terrain's cell: a drone's orthophoto with the ground's "
                  "texture (default: the terrain's grid)")
      ->check(CLI::PositiveNumber)
      ->excludes(gis);
  cmd->add_flag("--overwrite", args->overwrite, "Replace an existing DIR");
  cmd->callback([args] { runMakeScene(*args); });
}

}  // namespace nestwalk::tools
