// build-scene: a walkable scene from a user's own data. A DEM (any raster GDAL reads), point and
// line layers of equipment (layer_features.h) and a model catalog (scene/model_catalog.h) become a
// scene folder: scene.json (the scene file schema, scene_file.h, with the catalog's types it uses)
// and terrain.tif (the DEM imported to the engine's terrain format, unless it already is one: then
// the scene refers to it where it is).
//
// Each point feature becomes an instance of its type, at its position (the terrain's CRS),
// turned to its heading (layer_features.h: the grid azimuth), at its scale (or the type's). Each
// line feature becomes a fence: its type's model repeated along it (fence_layout.h); the pieces
// form the group named after the fence, so the template hierarchy keeps a fence together. Names:
// the feature's name field, else "<layer>/<type>#<feature id>"; a fence's pieces are
// "<fence>/<k>". Groups: the feature's group field, else its layer's name.
//
// Standing on the ground: every instance is checked as the scene loader will place it
// (scene_loader.h: the lowest ground under its footprint). A feature any of whose instances is not
// on ground everywhere (outside the terrain, over nodata) is bad; one whose footprint spans more
// than maxFootprintRise metres of ground is reported as a warning (its uphill side sinks into the
// ground by that much: a bench crest under a container, a slope under a truck).
//
// Bad features (unknown type, unsupported geometry, a heading that is not a number, off the
// terrain, a name used twice, a fence segment that cannot be covered within the catalog's limits)
// are all listed in one InputError with their source, layer and feature id, and nothing is
// written; with skipBad they are left out and listed in the summary and in the scene file's
// "source". Problems of a whole input (the DEM, the catalog, a source or layer) are InputErrors
// naming it. The folder is written under a temporary name beside OUT and renamed at the end; an
// existing OUT is replaced only with overwrite. Before that the written scene is loaded once as
// `nestwalk run` will load it.
//
// Thread safety: call from one thread while no other thread runs: it reads model files through
// runGuarded (a fork, core/guarded_process.h), uses GDAL (initGdal's process-wide settings,
// terrain/dem_reader.h), and its folder's temporary name depends only on OUT and the process id
// (core/output_file.h).
#pragma once

#include "nestwalk/gis/layer_features.h"

#include <string>
#include <vector>

namespace nestwalk::gis {

struct BuildSceneOptions {
  std::string terrain;  // the DEM
  std::string imagery;  // an orthophoto to drape (empty: none)
  std::string catalog;  // the model catalog
  LayerSelection layers;
  std::string out;      // the scene's folder
  bool overwrite = false;
  bool skipBad = false;
  double maxFootprintRise = 0.5;  // metres of ground under one footprint before it is reported
};

struct BuildSceneSummary {
  std::string sceneFile;
  bool terrainImported = false;
  std::string terrainCrs;
  bool imageryImported = false;  // written as imagery.tif (else named where it is: ready to drape)
  std::size_t pointInstances = 0, fences = 0, fencePieces = 0;
  std::vector<LayerRead> layers;
  std::vector<FeatureProblem> skipped;  // with skipBad
  std::vector<std::string> warnings;    // footprints that rise more than allowed
};

BuildSceneSummary buildScene(const BuildSceneOptions& options);

}  // namespace nestwalk::gis
