// A loaded scene: the terrain, the models (loaded and fitted once per file), the instances with
// their world volumes, and the collision units the broad phase is built over.
//
// Frames: map (the terrain's CRS, double) and local = map - origin, where every volume lives.
// Collision units: each instance that is not `use_only` is a unit of its own; the `use_only`
// instances of a group form one unit together (volumes fitted to all their points), named after
// the group. The set of units does not depend on the hierarchy, so every hierarchy sees the same
// contacts.
//
// Units: map and local coordinates in metres (projected CRS); SceneModel's model-frame data in the
// model file's own frame and units (SceneInstance::toLocal includes the type's transform to
// metres); angles in degrees.
// A model is kept twice, once per side: its triangle mesh (what the collision side measures) and
// the scene graph its file held, as the .osgb bytes the guarded read handed back (what the drawing
// side rebuilds its nodes from: render/model_nodes.h). No OpenSceneGraph type appears here, so the
// simulation layers above compile without it.
// Ownership: a Scene owns its data; the terrain is a shared_ptr to const.
// Thread safety: nothing in the engine changes a loaded Scene, so its fields and const members may
// be read from several threads at once.
#pragma once

#include "nestwalk/geometry/nested.h"
#include "nestwalk/geometry/triangle_mesh.h"
#include "nestwalk/scene/scene_file.h"
#include "nestwalk/terrain/heightfield.h"

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace nestwalk::terrain {
class TerrainPyramid;
}

namespace nestwalk {

struct SceneModel {
  std::string path;
  TriangleMesh mesh;                      // model frame: every vertex and triangle (node_geometry.h)
  std::string drawing;                    // the file's scene graph in OSG's native binary form (.osgb
                                          // bytes, images included), read once: the renderer's source
  std::vector<Vec3<double>> hullPoints;   // model frame: the convex hull's vertices
  Aabb<double> aabb;                      // model frame
  Obb<double> obb;                        // model frame, fitted once with the scene's fitter
};

/// The attitude of an instance: model frame -> map axes, R = Rz(-heading) * Rx(pitch) * Ry(roll)
/// (angles in degrees; Rk(a) the right-handed rotation by a about axis k). The model's own axes are
/// taken as +y forward, +x right, +z up; map axes are +x east, +y north, +z up. So heading is
/// clockwise from north seen from above (heading 90 turns the model's +y forward into +x east),
/// pitch turns about the right axis with nose up positive, roll about the forward axis with the
/// right side down positive; the rotations apply roll first, heading last. Multiples of 90 degrees
/// give exact 0 and +-1 entries.
Mat3<double> attitudeRotation(double headingDeg, double pitchDeg, double rollDeg);

struct SceneInstance {
  std::uint32_t spec = 0;                 // index into SceneSpec::equipment (equal to this instance's index)
  std::uint32_t model = 0;                // index into Scene::models
  Similarity<double> toLocal;             // model file frame -> local frame: the type's transform (a
                                          // typed instance), then rotation attitudeRotation(heading, pitch,
                                          // roll), scale, translation = map position - origin (z: the
                                          // lowest ground under the footprint when the file gives none)
  NestedVolume<double> volume;            // local frame: outer = exact AABB of the transformed hull points,
                                          // rounded outward by kOutwardRounding (volumes.h) times the
                                          // magnitudes involved (|translation| + scale * max |p|) so that
                                          // it contains them despite rounding; inner = the
                                          // model's OBB transformed (exact up to rounding). The outer box
                                          // need not contain the inner one.
  std::uint32_t unit = 0;                 // the collision unit it belongs to
  double footprintRise = 0;               // metres: highest minus lowest ground under its footprint
                                          // (0 for an instance the file gives a z)
};

struct CollisionUnit {
  std::string name;                       // instance name, or the group path for a use_only unit
  std::string group;                      // group path for the template hierarchy (a use_only unit: its
                                          // members' group, i.e. its own name)
  std::string kind;                       // the instance's kind; a use_only unit: its members' common
                                          // kind, empty when they differ
  NestedVolume<double> volume;            // local frame; a use_only unit: outer = outward-rounded exact
                                          // AABB and inner = fitObb (scene's fitter) of all members'
                                          // transformed hull points
  std::vector<std::uint32_t> instances;   // members, indices into Scene::instances
};

struct Scene {
  SceneSpec spec;
  std::shared_ptr<const terrain::Heightfield> terrain;  // map frame
  /// The terrain file's pyramid (terrain/terrain_pyramid.h) when it has a valid one: the renderer
  /// then reads its coarse chunks' errors instead of computing them. Null without one; a pyramid
  /// that is refused (stale, corrupt, from a newer nestwalk) is not used, and says why here.
  std::shared_ptr<const terrain::TerrainPyramid> terrainPyramid;
  std::string terrainPyramidRefused;
  /// Metres the terrain's heights were moved by on loading (SceneLoadOptions::mapShift.z): the
  /// pyramid's pages hold the file's own heights, this much apart from the scene's.
  double terrainHeightShift = 0;
  /// The file the imagery is drawn from (empty: no imagery): SceneSpec::imagery itself, or its import
  /// in the terrain cache when it is not ready to drape as it is (terrain_cache.h, cachedImagery).
  std::string drapedImagery;
  std::map<std::string, Similarity<double>> typeTransforms;  // per type: model file frame -> the
                                                             // engine's model frame (model_catalog.h)
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();     // map point of the local origin
  std::vector<SceneModel> models;         // in order of first use in the file
  std::vector<SceneInstance> instances;   // file order, one per SceneSpec::equipment entry
  std::vector<CollisionUnit> units;       // file order; a use_only group's unit where its first member is

  Eigen::Vector3d toLocal(const Eigen::Vector3d& map) const { return map - origin; }
  Eigen::Vector3d toMap(const Eigen::Vector3d& local) const { return local + origin; }
  std::vector<Aabb<double>> unitBoxes() const;           // units' outer AABBs, for BoxTree
  std::vector<std::string> unitGroups() const;           // units' group paths, for BoxTree
  int findUnit(const std::string& name) const;           // -1 when absent
};

}  // namespace nestwalk
