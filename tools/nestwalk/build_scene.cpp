// nestwalk build-scene --terrain DEM [--imagery ORTHO] --equipment SOURCE [--equipment ...] --catalog CATALOG --out DIR:
// a scene from a user's GIS layers and models (engine/gis/scene_builder.h). SOURCE is any vector
// file OGR reads (GeoPackage, Shapefile, GeoJSON, KML, CSV with X/Y or WKT columns); without
// --layer every point and line layer of every source is read. The fields type, name, heading,
// scale and group are read by name (--type-field etc.). Prints what was placed, the warnings and
// (with --skip-bad) the features left out.
#include "nestwalk/gis/scene_builder.h"
#include "tools/nestwalk/commands.h"

#include <cstdio>
#include <memory>

namespace nestwalk::tools {
namespace {

void runBuildScene(const gis::BuildSceneOptions& o) {
  const gis::BuildSceneSummary s = gis::buildScene(o);
  std::printf("wrote %s\n", s.sceneFile.c_str());
  std::printf("  terrain:   %s (%s), CRS %s\n", o.terrain.c_str(),
              s.terrainImported ? "imported as terrain.tif" : "used as it is: already the engine's format",
              s.terrainCrs.c_str());
  if (!o.imagery.empty())
    std::printf("  imagery:   %s (%s)\n", o.imagery.c_str(),
                s.imageryImported ? "imported as imagery.tif" : "used as it is: ready to drape");
  for (const gis::LayerRead& l : s.layers)
    std::printf("  layer:     %s: '%s', %zu features, CRS %s\n", l.source.c_str(), l.layer.c_str(), l.features,
                l.crs.c_str());
  std::printf("  equipment: %zu instances from points, %zu fences of %zu pieces\n", s.pointInstances, s.fences,
              s.fencePieces);
  for (const std::string& w : s.warnings) std::printf("  warning:   %s\n", w.c_str());
  for (const gis::FeatureProblem& p : s.skipped) std::printf("  skipped:   %s: %s\n", p.where.c_str(), p.problem.c_str());
}

}  // namespace

void registerBuildScene(CLI::App& app) {
  auto o = std::make_shared<gis::BuildSceneOptions>();
  CLI::App* cmd = app.add_subcommand(
      "build-scene", "Build a scene from a DEM, GIS layers of equipment points and fence lines, and a model catalog");
  cmd->add_option("--terrain", o->terrain, "DEM, any raster GDAL reads (imported unless it is already a terrain COG)")
      ->required();
  cmd->add_option("--equipment", o->layers.sources,
                  "Vector source OGR reads: GeoPackage, Shapefile, GeoJSON, KML, CSV (repeatable)")
      ->required();
  cmd->add_option("--layer", o->layers.layers, "Read only this layer (repeatable; default: every point and line layer)");
  cmd->add_option("--where", o->layers.where, "OGR attribute filter for every layer read (SQL WHERE clause)");
  cmd->add_option("--imagery", o->imagery,
                  "An orthophoto to drape, any raster GDAL reads (named where it is when it is tiled with overviews in the "
                  "terrain's CRS; else imported beside the terrain as imagery.tif, a JPEG COG)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--catalog", o->catalog, "Model catalog (JSON: types, their model files and how to read them)")
      ->required();
  cmd->add_option("--out", o->out, "Folder for the scene (scene.json, terrain.tif)")->required();
  cmd->add_option("--layer-crs", o->layers.assumedCrs, "CRS of layers that have none, e.g. EPSG:4326 (CSV files)");
  cmd->add_option("--type-field", o->layers.fields.type, "Field with the equipment type (default: type)");
  cmd->add_option("--name-field", o->layers.fields.name, "Field with the instance name (default: name)");
  cmd->add_option("--heading-field", o->layers.fields.heading,
                  "Field with the heading, degrees clockwise from north (default: heading)");
  cmd->add_option("--scale-field", o->layers.fields.scale, "Field with the scale (default: scale)");
  cmd->add_option("--group-field", o->layers.fields.group, "Field with the group path (default: group; else the layer)");
  cmd->add_option("--default-type", o->layers.defaultType, "Type of features in layers without the type field");
  cmd->add_option("--max-footprint-rise", o->maxFootprintRise,
                  "Report instances standing on more than this much rising ground, metres (default 0.5)");
  cmd->add_flag("--skip-bad", o->skipBad, "Leave bad features out (listed) instead of stopping");
  cmd->add_flag("--overwrite", o->overwrite, "Replace an existing output folder");
  cmd->callback([o] { runBuildScene(*o); });
}

}  // namespace nestwalk::tools
