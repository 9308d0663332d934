// The scene file (JSON): what a scene is made of, as the user wrote it, checked field by field.
//
// Schema (documented for users in README.md, "Scene files"):
// {
//   "terrain": "terrain.tif",              // DEM or imported terrain, any raster GDAL reads; relative
//                                          // paths are relative to the scene file's folder
//   "imagery": "ortho.tif",                // optional: imagery draped over the terrain (an
//                                          // orthophoto, any raster GDAL reads, in any CRS:
//                                          // terrain/terrain_imagery.h), relative as above
//   "shading": "hillshade" | "none",       // optional: Horn's hillshade blended into the terrain's
//                                          // colours (default: hillshade without imagery, none with it)
//   "origin": [x, y, z],                   // optional: map point of the local frame's origin
//                                          // (default: the terrain's centre, z 0)
//   "types": { "gauge": {...} },           // optional: equipment types, as in a model catalog
//                                          // (model_catalog.h), model paths relative as above
//   "equipment": [                         // instances, in any order
//     { "name": "bench3/station7/mast",    // optional, unique; default "<group>/<model stem>#<index>"
//                                          // ("<group>/<type>#<index>" for a typed instance)
//       "model": "models/pole.osgt",       // any format OpenSceneGraph reads (relative as above), or
//       "type": "gauge",                   // a type of "types": its model read as the type says,
//                                          // kind, use_only and scale defaulting to the type's
//       "position": [x, y] | [x, y, z],    // map coordinates; without z the instance stands on the
//                                          // ground (scene_loader.h: the lowest ground under its
//                                          // footprint)
//       "heading": 0, "pitch": 0, "roll": 0,  // degrees; heading clockwise from north (map +y)
//       "scale": 1,                        // uniform, > 0
//       "group": "bench3/station7",        // template hierarchy path ("" or absent: under the root)
//       "use_only": false,                 // true: part of its group's volume, never tested alone
//       "kind": "pole" }                   // optional free label (colour, reports)
//   ],
//   "viewer": { "eye_height": 1.7, "body_half_extents": [0.25, 0.25, 0.9],
//               "max_step": 0.3, "max_slope_deg": 30, "speed": 1.4, "fly_clearance": 2.0 },
//   "method": { "volumes": "nested", "hierarchy": "auto" | "template", "degree": 8,
//               "split_axis": "longest" | "splatter", "split_point": "mean" | "median",
//               "fitter": "hull-search" | "covariance" },
//   "source": {...}                        // optional, not interpreted: where the scene came from
//                                          // (build-scene writes its inputs and findings here)
// }
// Unknown keys are errors (a typo must not silently fall back to a default), and so is a key given
// twice in one object. Every error names the file and the field (e.g. "scene.json:
// equipment[12].scale: must be > 0", "scene.json: viewer.max_slope_deg: expected a number, got
// string"); missing model files are all reported in one error. The imagery file must exist (a
// missing one is an error naming the scene file, the field and the path) but is not opened here:
// whoever draws the terrain opens it (terrain::TerrainImagery). Further checks: "terrain", and each
// instance's "position" and either its "model" or its "type" (one of "types"), are required; group paths have no empty component (no
// leading, trailing or doubled '/'); a use_only instance needs a group; names (given or default)
// are unique, and no instance is named like a use_only group (that group's unit carries the name);
// viewer: eye_height, speed and the half extents > 0, max_step and fly_clearance >= 0,
// 0 < max_slope_deg < 90; method.degree is 2, 4 or 8. The default name at the root is
// "<model stem>#<index>" (index: the entry's position in "equipment", from 0).
//
// Thread safety: pure functions (readSceneFile reads the file and checks that the model files
// exist); nothing is kept.
#pragma once

#include "nestwalk/scene/method_spec.h"
#include "nestwalk/scene/model_catalog.h"

#include <Eigen/Core>

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace nestwalk {

struct EquipmentSpec {
  std::string name;    // unique within the scene
  std::string model;   // resolved path (absolute or relative to the working directory)
  std::string type;    // a key of SceneSpec::types ("" for a plain model file)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // map frame
  bool hasZ = false;   // false: position.z() is unused, the model stands on the ground
  double headingDeg = 0, pitchDeg = 0, rollDeg = 0;
  double scale = 1;
  std::string group;   // '/'-separated, no leading or trailing '/'
  bool useOnly = false;
  std::string kind;
};

struct ViewerSpec {
  double eyeHeight = 1.7;                                   // metres above the ground (walking)
  Eigen::Vector3d bodyHalfExtents{0.25, 0.25, 0.9};         // forward, sideways, up; metres
  double maxStep = 0.3;                                     // highest rise walked up in one go, metres
  double maxSlopeDeg = 30;                                  // steepest walkable slope
  double speed = 1.4;                                       // default m/s
  double flyClearance = 2.0;                                // flying: lowest body bottom above ground
};

struct SceneSpec {
  std::string path;        // the scene file as given
  std::string terrain;     // resolved path
  std::optional<std::string> imagery;  // resolved path of the draped imagery; unset: none
  /// "shading": "hillshade" (true) or "none" (false); unset: hillshade without imagery, none with it
  /// (a real orthophoto carries its own shadows). hillshadeOn() says which.
  std::optional<bool> hillshade;
  bool hillshadeOn() const { return hillshade.value_or(!imagery); }
  std::optional<Eigen::Vector3d> origin;
  std::map<std::string, ModelType> types;  // "types", model paths resolved
  std::vector<EquipmentSpec> equipment;
  ViewerSpec viewer;
  MethodSpec method;
};

// Reads and checks a scene file; throws InputError (file and field named). Model files must exist
// (all missing ones are listed together); they are not loaded here.
SceneSpec readSceneFile(const std::string& path);
SceneSpec parseSceneJson(const std::string& text, const std::string& path);  // for tests; paths relative to path's folder

}  // namespace nestwalk
