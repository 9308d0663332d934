// The walker's view, rendered offscreen with OpenSceneGraph: the view graph (view_graph.h: the
// scene, sun, sky, haze, blocked overlay, nested culling; or the ID pass) drawn into a frame-buffer
// object and read back into an image each frame, with the time split into cull, draw and readback.
// Camera conventions, culling and the ID pass's colours: view_graph.h. The blocked overlay's font
// cannot be loaded: the constructor throws InputError naming its file.
//
// Threading: SingleThreaded, on the creating thread (the offscreen context is current there).
//
// Ownership: the renderer keeps a reference to `scene`, which must outlive it; its graph has model
// nodes of its own (rebuilt from the scene's .osgb bytes, model_nodes.h) and compiles GL objects
// into them for its own context. Several renderers may live on one thread (render() makes its
// context current again), but see offscreen_context.h on destroying one while another lives.
// This header shows only the vocabulary (view_options.h, frame_stats.h): the graph, the terrain
// paging and the culler (view_graph.h) stay the drawing side's own, reached through graph().
#pragma once

#include "nestwalk/render/frame_stats.h"
#include "nestwalk/render/offscreen_context.h"
#include "nestwalk/render/view_options.h"

#include <osg/BoundingSphere>
#include <osg/Image>
#include <osg/Matrixd>
#include <osg/ref_ptr>
#include <osgViewer/Viewer>

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace nestwalk {

struct Frustum;              // nested_cull.h
struct Scene;                // scene/scene.h
struct SceneGraphParts;      // scene_graph.h
class ViewGraph;             // view_graph.h
class TerrainNode;           // terrain_node.h
struct PagedTerrainOptions;  // paged_terrain.h
namespace terrain {
class Heightfield;  // terrain/heightfield.h
}

/// Makes the terrain a view draws instead of its own quadtree, from the options the quadtree would
/// have had (terrain_node.h: a peer measured beside ours).
using TerrainNodeMaker = std::function<osg::ref_ptr<TerrainNode>(std::shared_ptr<const terrain::Heightfield>,
                                                                 const PagedTerrainOptions&)>;


class ViewRenderer {
 public:
  // Builds the graph, creates the offscreen context (offscreen_context.h) and realizes the
  // viewer. Throws std::runtime_error when no context can be had, InputError (naming the file)
  // when the overlay's font cannot be loaded.
  explicit ViewRenderer(const Scene& scene, const RenderOptions& options = {});
  // The same, drawing the terrain that `makeTerrain` makes (terrain_node.h).
  ViewRenderer(const Scene& scene, const RenderOptions& options, const TerrainNodeMaker& makeTerrain);
  ~ViewRenderer();
  ViewRenderer(const ViewRenderer&) = delete;
  ViewRenderer& operator=(const ViewRenderer&) = delete;

  // Renders one frame from the pose; the image holds it afterwards.
  const RenderFrameStats& render(const ViewPose& pose);
  const RenderFrameStats& lastStats() const { return stats_; }
  // RGB, 8 bits per channel, rows bottom-up (OpenGL order; osgDB writes PNGs upright).
  const osg::Image& image() const { return *image_; }

  // Pixel (x right, y down from the top-left corner, pixel centres at +0.5) of a map point in the
  // last rendered frame's camera; nullopt behind the eye.
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& map) const;
  // The ray (map frame, unit direction) through pixel (x, y) (same convention) of the last frame.
  std::pair<Eigen::Vector3d, Eigen::Vector3d> pixelRay(double x, double y) const;
  // The camera's matrices for a pose: view (map frame -> eye) and projection.
  osg::Matrixd viewMatrix(const ViewPose& pose) const;
  const osg::Matrixd& projectionMatrix() const;
  double nearPlane() const;
  double farPlane() const;

  // The last frame's view frustum in the local frame (nested_cull.h).
  Frustum frustumLocal() const;
  // The equipment instances' bounding spheres as OSG sees them (local frame), for comparisons.
  std::vector<osg::BoundingSphere> instanceSpheres() const;
  const SceneGraphParts& parts() const;
  const ViewGraph& graph() const { return *graph_; }

  OffscreenRoute route() const { return context_->route(); }
  const std::string& glRenderer() const { return context_->glRenderer(); }
  const RenderOptions& options() const { return options_; }
  // The file of the overlay text's font (kUiFontPath; empty without an overlay text font: ID pass,
  // or blockedOverlay off).
  std::string overlayFontFile() const;
  // The ID pass colour of a thing: 0 sky, 1 terrain, i + 2 instance i (see above).
  static std::uint32_t idAt(const osg::Image& image, int x, int yFromTop);

 private:
  struct Timing;

  const Scene& scene_;
  RenderOptions options_;
  std::unique_ptr<OffscreenContext> context_;
  std::unique_ptr<ViewGraph> graph_;
  osg::ref_ptr<osgViewer::Viewer> viewer_;
  osg::ref_ptr<osg::Image> image_;
  std::shared_ptr<Timing> timing_;
  RenderFrameStats stats_;
};

}  // namespace nestwalk
