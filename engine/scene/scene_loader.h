// Loading a scene: the scene file (scene_file.h) made into a Scene (scene.h): the terrain read,
// every model loaded and fitted once, the instances placed and their volumes computed, the
// collision units formed.
#pragma once

#include "nestwalk/scene/scene.h"

#include <Eigen/Core>

#include <string>

namespace nestwalk {

struct SceneLoadOptions {
  // Added to every map coordinate (terrain georeference, equipment positions, origin): tests load
  // a scene at its UTM position and moved near the map origin and compare.
  Eigen::Vector3d mapShift = Eigen::Vector3d::Zero();
};

// Loads the terrain (readDem), every model once (osgDB), fits volumes, places instances (z from
// the ground where the file gives none) and forms the units. The default origin is the centre of
// the terrain's sample extent (x, y) at z 0. Throws InputError naming the scene file: a bad terrain
// (readDem's message), unreadable models (listed together), a model without vertices (named), the
// instances with no ground under them (listed together). Model volumes: aabb = bounds of all the
// model's vertices, hullPoints = convexHull's vertices, obb = fitObb(hullPoints, method.fitter).
// With mapShift, the heightfield is rebuilt with the same samples and its origin moved (heights
// move by mapShift.z, rounded to float; holes stay holes).
Scene loadScene(const SceneSpec& spec, const SceneLoadOptions& options = {});
Scene loadScene(const std::string& path, const SceneLoadOptions& options = {});

}  // namespace nestwalk
