// Loading a scene: the scene file (scene_file.h) made into a Scene (scene.h): the terrain read,
// every model loaded and fitted once, the instances placed and their volumes computed, the
// collision units formed.
//
// Thread safety: loadScene reads every model through readModelFile (a fork,
// core/guarded_process.h): call it from one thread while no other thread holds locks the child
// needs (in practice: before starting other threads). It also uses GDAL (readDem: initGdal's
// process-wide settings) and osgDB's registry.
#pragma once

#include "nestwalk/scene/scene.h"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

namespace nestwalk {

/// Prints "nestwalk: note: " + text on stderr.
void printSceneNote(const std::string& text);

/// A paged terrain's tile budget by default, bytes: terrain::kDefaultHeightTileBudgetBytes
/// (height_tiles.h, not installed; the loader checks they agree).
inline constexpr std::size_t kDefaultTerrainTileBudget = std::size_t(128) << 20;

struct SceneLoadOptions {
  // Added to every map coordinate (terrain georeference, equipment positions, origin): tests load
  // a scene at its UTM position and moved near the map origin and compare.
  Eigen::Vector3d mapShift = Eigen::Vector3d::Zero();
  /// Told of slow first-time work (a plain DEM imported into the terrain cache, terrain_cache.h) and
  /// of a terrain pyramid set aside (Scene::terrainPyramidRefused); by default printed on stderr as
  /// "nestwalk: note: ...". Empty: silent.
  std::function<void(const std::string&)> note = printSceneNote;
  /// Where the terrain's samples live (terrain/heightfield.h): automatic pages a terrain of more than
  /// kResidentTerrainSamples samples (from its own pyramid, else the terrain cache's import) and
  /// holds a smaller one; resident and paged force either (paged falls back to resident when no
  /// pyramid can be had and the DEM fits in memory). The answers are the same bit for bit.
  enum class TerrainStorage { automatic, resident, paged } terrainStorage = TerrainStorage::automatic;
  /// A paged terrain's tile budget, bytes (terrain/height_tiles.h: kDefaultHeightTileBudgetBytes).
  std::size_t terrainTileBudget = kDefaultTerrainTileBudget;
};

/// Terrains of more samples are paged by default (64 MB of heights, 0.5 s to read at 32 M samples
/// a second; a 4,096 x 4,096 DEM is held): below it a resident grid opens fast enough and its
/// ground lookups cost half a paged one's.
inline constexpr std::uint64_t kResidentTerrainSamples = std::uint64_t(1) << 24;

// Loads the terrain and its pyramid (Scene::terrainPyramid: the terrain file's own, else the
// terrain cache's, terrain_cache.h), every model once (osgDB), fits volumes, places instances and
// forms the units. The terrain is read whole (readDem) or paged from its pyramid
// (SceneLoadOptions::terrainStorage): a paged one opens without reading a fine sample.
//
// Standing on the ground: an instance whose position has no z stands with its model-frame z = 0
// (a typed instance: its base, model_catalog.h) at the lowest ground under its footprint, the
// x-y outline of its placed model (terrain/footprint_ground.h, exact for the triangulated
// surface). So it never hangs in the air anywhere over its footprint; on a slope or over a bench
// crest its uphill side sinks into the ground by up to SceneInstance::footprintRise (highest minus
// lowest ground under the footprint), which the scene keeps per instance so that tools can report
// instances that span more than they allow (build-scene's --max-footprint-rise). A footprint that is
// not on ground everywhere (part of it over a hole or beyond the outermost samples) is an error. The default origin is the centre of
// the terrain's sample extent (x, y) at z 0. Throws InputError naming the scene file: a bad terrain
// (readDem's message), unreadable models (listed together), a model without vertices (named), the
// instances without ground under all of their footprint (listed together). Model volumes: aabb = bounds of all the
// model's vertices, hullPoints = convexHull's vertices, obb = fitObb(hullPoints, method.fitter).
// With mapShift, the heightfield is rebuilt with the same samples and its origin moved (heights
// move by mapShift.z, rounded to float; holes stay holes).
Scene loadScene(const SceneSpec& spec, const SceneLoadOptions& options = {});
Scene loadScene(const std::string& path, const SceneLoadOptions& options = {});

}  // namespace nestwalk
