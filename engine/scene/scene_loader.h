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

#include <functional>
#include <string>

namespace nestwalk {

/// Prints "nestwalk: note: " + text on stderr.
void printSceneNote(const std::string& text);

struct SceneLoadOptions {
  // Added to every map coordinate (terrain georeference, equipment positions, origin): tests load
  // a scene at its UTM position and moved near the map origin and compare.
  Eigen::Vector3d mapShift = Eigen::Vector3d::Zero();
  /// Told of slow first-time work (a plain DEM imported into the terrain cache, terrain_cache.h) and
  /// of a terrain pyramid set aside (Scene::terrainPyramidRefused); by default printed on stderr as
  /// "nestwalk: note: ...". Empty: silent.
  std::function<void(const std::string&)> note = printSceneNote;
};

// Loads the terrain (readDem) and its pyramid (Scene::terrainPyramid: the terrain file's own, else
// the terrain cache's, terrain_cache.h), every model once (osgDB), fits volumes, places instances and forms
// the units.
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
