// Nested view-frustum culling of the scene's equipment: each instance is tested against the view
// frustum with the same nested volumes the walker uses (scene.h): the outer AABB first (flat
// arrays, n-vertex/p-vertex plane tests), and the inner OBB only for the instances the AABB test
// cannot decide. Per-frame counts say what each stage culled. sphereCull is OpenSceneGraph's own
// bounding-sphere test (osg::Polytope) on the same frustum, for comparison.
//
// Frame: everything here is in the scene's local frame (map - Scene::origin), in double. The scene
// graph's equipment group lives in that frame (buildSceneGraph: root -> "local_to_map" ->
// "equipment"), so a renderer whose camera view matrix maps *map* coordinates to the eye passes
//   Frustum::fromMatrices(osg::Matrixd::translate(origin) * viewMap, projection)
// (OSG row-vector convention: local -> map -> eye).
//
// Ownership: NestedFrustumCuller copies the volumes it needs and keeps no reference to the Scene.
// Frustum::fromMatrices and sphereCull are pure functions.
#pragma once

#include "nestwalk/geometry/volumes.h"
#include "nestwalk/render/frame_stats.h"

#include <osg/BoundingSphere>
#include <osg/Group>
#include <osg/Matrixd>
#include <osg/Referenced>
#include <osg/ref_ptr>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace nestwalk {

struct Scene;

/// A plane n.x + offset = 0 with a unit normal; points with n.x + offset >= 0 are on its inner side.
struct FrustumPlane {
  Vec3<double> normal = Vec3<double>::UnitZ();
  double offset = 0;
  /// Signed distance (positive inside).
  double distance(const Vec3<double>& p) const { return normal.dot(p) + offset; }
};

/// A view frustum in the local frame: six planes with inward unit normals and its eight corners.
struct Frustum {
  enum Side : int { kLeft = 0, kRight = 1, kBottom = 2, kTop = 3, kNear = 4, kFar = 5 };
  static constexpr int kPlaneCount = 6;

  std::array<FrustumPlane, kPlaneCount> planes;  // indexed by Side
  /// Corner i: bit 0 right (else left), bit 1 top (else bottom), bit 2 far (else near); the meeting
  /// point of those three planes.
  std::array<Vec3<double>, 8> corners;

  /// The frustum of an OSG camera: `viewLocal` maps the local frame to the eye, `projection` the eye
  /// to OpenGL clip space (OSG row-vector convention: clip = p * viewLocal * projection). Planes by
  /// Gribb & Hartmann (the rows of the combined matrix), perspective or orthographic.
  static Frustum fromMatrices(const osg::Matrixd& viewLocal, const osg::Matrixd& projection);
};


/// Per-instance visibility of the equipment against the view frustum, by the nested volumes, and
/// cull callbacks that make OSG's cull traversal obey it.
///
/// An instance is culled when its outer AABB or its inner OBB lies entirely on the outer side of
/// one frustum plane (both volumes contain the instance's geometry). Conservative: a tiny slack,
/// bounded by the rounding of the plane distances, keeps boxes that touch a plane. The test is the
/// plane test, not an exact box-frustum intersection: a box near a frustum edge or corner may be
/// kept although it misses the frustum.
///
/// Use: construct once per scene, install() on the scene graph's "equipment" group, and call
/// update() with the camera's frustum before each frame's cull traversal (not while a cull
/// traversal of another thread runs). The callbacks act on every cull traversal of the graph, so
/// graphs culled for other views (shadow cameras, a second view) need their own culler or none.
class NestedFrustumCuller {
 public:
  /// Copies the instances' volumes (Scene::instances[i].volume, local frame) into flat arrays.
  /// Every instance is visible until the first update().
  explicit NestedFrustumCuller(const Scene& scene);
  ~NestedFrustumCuller();
  NestedFrustumCuller(const NestedFrustumCuller&) = delete;
  NestedFrustumCuller& operator=(const NestedFrustumCuller&) = delete;

  /// Classifies every instance against `frustum` (local frame); returns this frame's counts.
  const CullCounts& update(const Frustum& frustum);
  /// Whether instance i was kept by the last update().
  bool visible(std::size_t instance) const;
  const CullCounts& counts() const { return counts_; }
  std::size_t size() const { return inner_.size(); }

  /// Puts a cull callback on child i of `equipment` (instance i) that traverses only when
  /// visible(i), and turns OSG's own bounding-sphere test off on those children
  /// (setCullingActive(false)) so the nested test decides for them (nodes below, such as the
  /// model's, keep their own OSG tests). `enabled = false` removes the callbacks and turns OSG's
  /// culling back on. Installing twice does not stack callbacks; the callbacks keep the visibility
  /// they share with this culler alive, so they stay valid after the culler is destroyed (frozen at
  /// its last update()). Throws std::invalid_argument when `equipment` is null or its child count
  /// differs from the number of instances.
  void install(osg::Group* equipment, bool enabled = true);

  /// Per-instance flags, shared with the installed callbacks (1: visible).
  struct Visibility : osg::Referenced {
    std::vector<std::uint8_t> flags;
  };

 private:
  // The AABB stage: leaves the instances it does not cull first in kept_ and returns how many;
  // straddling_[i]: instance i's AABB crosses a plane (the OBB decides).
  std::size_t classifyAabbs(const Frustum& frustum);
  bool obbOutside(std::size_t instance, const Frustum& frustum) const;  // the OBB stage

  // Outer AABBs, structure of arrays: min and max per axis.
  std::array<std::vector<double>, 3> boxMin_, boxMax_;
  std::vector<Obb<double>> inner_;
  double magnitude_ = 0;  // the largest coordinate magnitude of any volume, for the rounding slack
  std::array<double, Frustum::kPlaneCount> slack_{};  // this frame's rounding slack per plane
  std::vector<std::uint32_t> kept_;       // the AABB stage's survivors, this frame
  std::vector<std::uint8_t> straddling_;  // the AABB stage's undecided instances, this frame
  osg::ref_ptr<Visibility> visibility_;
  CullCounts counts_;
};

/// OpenSceneGraph's own test on the same frustum, for comparison: how many of `spheres` (each
/// equipment child's getBound(), local frame) an osg::Polytope of the frustum's six planes keeps
/// (osg::Polytope::contains; an invalid sphere is kept, as OSG's cull traversal keeps a node
/// without bounds). Fills instances, visible and micros.
CullCounts sphereCull(const std::vector<osg::BoundingSphere>& spheres, const Frustum& frustum);

}  // namespace nestwalk
