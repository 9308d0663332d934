// What the walker's view draws, whatever draws it: the offscreen renderer (view_renderer.h) and
// the interactive window (engine/viewer) build the same graph, so that a screenshot of the window
// and an offscreen frame of the same pose agree.
//
// The graph: the view-bounded terrain (paged_terrain.h: chunks of the heightfield chosen by their
// projected error, loaded in the background, colours with the hillshade and any draped imagery
// baked in, unlit), the scene graph's equipment instances over shared model nodes and optional
// volume wireframes (scene_graph.h), lit by a sun from the north-west (the hillshade's sun), a sky
// gradient behind whose horizon follows the pitch, aerial haze, and
// the blocked overlay (a red frame and "BLOCKED by <unit>" in the UI font, nestwalk/core/ui_font.h).
// Or, for the ID pass, every pixel coloured with what it shows: sky 0, terrain 1, instance i: i + 2
// (24-bit RGB, R the low byte).
//
// Camera: the eye in map coordinates; heading clockwise from north, pitch up positive (the walker's
// convention); vertical field of view fovYDegrees; near and far fixed (no OSG near/far computation,
// which clips the ground in front of a low eye over a large terrain): near is half the body's
// smaller horizontal half extent (equipment can never be nearer to the eye than the body lets it
// come), far reaches past the terrain's farthest corner.
//
// Terrain paging: the engine's own quadtree (paged_terrain.h, the default and the window's), or
// or a terrain the caller makes (terrain_node.h: a peer measured beside ours), under the same
// "terrain" transform.
//
// Culling: equipment is culled with the nested volumes (nested_cull.h) unless
// options.nestedCulling is off (then OSG's bounding spheres decide).
//
// Ownership: the graph keeps a reference to `scene`, which must outlive it, and shares the scene's
// model nodes (ref_ptr). Thread safety: build, update and draw it on one thread.
#pragma once

#include "nestwalk/render/frame_stats.h"
#include "nestwalk/render/nested_cull.h"
#include "nestwalk/render/paged_terrain.h"
#include "nestwalk/render/scene_graph.h"
#include "nestwalk/render/terrain_node.h"
#include "nestwalk/render/view_options.h"
#include "nestwalk/render/view_renderer.h"
#include "nestwalk/scene/scene.h"

#include <osg/Camera>
#include <osg/Geometry>
#include <osg/MatrixTransform>
#include <osg/View>
#include <osg/ref_ptr>

#include <Eigen/Core>

#include <memory>
#include <string>

namespace osgText {
class Text;
}

namespace nestwalk {




// The camera's view matrix (map frame -> eye) for a pose: eye at pose.eye looking along the heading
// and pitch, up tilted with the pitch.
osg::Matrixd walkerViewMatrix(const ViewPose& pose);

class ViewGraph {
 public:
  // Builds the graph. Throws std::invalid_argument for a size under 16 x 16 or a scene without
  // terrain, InputError (naming the file) when the overlay's font or the scene's imagery cannot be
  // loaded (terrain/terrain_imagery.h) or the imagery does not overlap the terrain.
  // With makeTerrain, the terrain is the node it makes instead of the own quadtree.
  ViewGraph(const Scene& scene, const RenderOptions& options, const TerrainNodeMaker& makeTerrain = {});
  ~ViewGraph();
  ViewGraph(const ViewGraph&) = delete;
  ViewGraph& operator=(const ViewGraph&) = delete;

  // The graph's root, to be the view's scene data.
  osg::Group* root() const { return root_.get(); }
  // Sets up a view to draw the graph: its lighting (the sun, or none for the ID pass) and its
  // master camera (projection, clear colour, fixed near and far).
  void attachTo(osg::View& view) const;
  // A window resized to width x height pixels: the projection keeps the vertical field of view
  // and takes the new aspect (the overlay layer keeps its own coordinates, stretched).
  void setViewportSize(int width, int height);
  // Moves the camera to a pose for the next frame: view matrix, sky horizon, blocked overlay,
  // nested culling. Returns the culling counts (all zero without nested culling).
  CullCounts update(osg::Camera& camera, const ViewPose& pose);
  // A screen-space layer over [0, width] x [0, height] pixels (y up), no lighting or depth test,
  // drawn after the scene: for a HUD. Its children are drawn in the order they are added.
  osg::MatrixTransform* overlayLayer() const { return overlay_.get(); }

  // The camera's matrices: view (map frame -> eye) for a pose, the projection, near and far.
  osg::Matrixd viewMatrix(const ViewPose& pose) const { return walkerViewMatrix(pose); }
  const osg::Matrixd& projectionMatrix() const { return projection_; }
  const osg::Matrixd& lastViewMatrix() const { return view_; }
  double nearPlane() const { return near_; }
  double farPlane() const { return far_; }
  // The last pose's view frustum in the local frame (nested_cull.h).
  Frustum frustumLocal() const;
  const osg::Matrixd& localToMap() const { return localToMap_; }
  const NestedFrustumCuller* culler() const { return culler_.get(); }
  // parts().terrain is the paged terrain's transform (mesh frame -> map); the scene graph's own
  // static terrain cut is not built (terrainCut stays empty).
  const SceneGraphParts& parts() const { return parts_; }
  // The own quadtree; throws std::logic_error when the terrain is a made one.
  PagedTerrain& pagedTerrain() const;
  // The terrain that draws, whichever it is: exactly one of the two is non-null.
  PagedTerrain* ownQuadtreeTerrain() const { return terrain_.get(); }
  TerrainNode* madeTerrain() const { return madeTerrain_.get(); }
  // The last cull's terrain figures, in PagedTerrain's terms for either terrain.
  PagedTerrainStats terrainStats() const;
  const RenderOptions& options() const { return options_; }
  const Scene& scene() const { return scene_; }
  // Pixels per radian of the vertical field of view (the terrain LOD rule's).
  double pixelsPerRadian() const { return pixelsPerRadian_; }
  // The file of the overlay text's font (empty without one: the ID pass, or blockedOverlay off).
  std::string overlayFontFile() const;

 private:
  void setUpStates();
  void setUpOverlay();
  void updateOverlay(const ViewPose& pose);

  const Scene& scene_;
  RenderOptions options_;
  osg::ref_ptr<osg::Group> root_;
  SceneGraphParts parts_;
  osg::ref_ptr<osg::MatrixTransform> overlay_;
  osg::ref_ptr<osg::Geometry> sky_;
  osg::ref_ptr<osg::Node> blockedFrame_;
  osg::ref_ptr<osgText::Text> blockedText_;
  std::unique_ptr<NestedFrustumCuller> culler_;
  osg::ref_ptr<PagedTerrain> terrain_;      // the own quadtree
  osg::ref_ptr<TerrainNode> madeTerrain_;   // or the made one
  osg::Matrixd projection_, view_;
  osg::Matrixd localToMap_;  // translation by the scene's origin
  double pixelsPerRadian_ = 0;
  double near_ = 0.1, far_ = 10000, hazeStart_ = 1500, hazeEnd_ = 10000;
};

}  // namespace nestwalk
