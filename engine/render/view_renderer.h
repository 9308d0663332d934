// The walker's view, rendered offscreen with OpenSceneGraph: the view graph (view_graph.h: the
// scene, sun, sky, haze, blocked overlay, nested culling; or the ID pass) drawn into a frame-buffer
// object and read back into an image each frame, with the time split into cull, draw and readback.
// Camera conventions, culling and the ID pass's colours: view_graph.h. The blocked overlay's font
// cannot be loaded: the constructor throws InputError naming its file.
//
// Threading: SingleThreaded, on the creating thread (the offscreen context is current there).
//
// Ownership: the renderer keeps a reference to `scene`, which must outlive it; its graph shares the
// scene's model nodes (ref_ptr) and compiles GL objects into them for its own context. Several
// renderers may live on one thread (render() makes its context current again), but see
// offscreen_context.h on destroying one while another lives.
#pragma once

#include "nestwalk/render/offscreen_context.h"
#include "nestwalk/render/view_graph.h"

#include <osg/Geometry>
#include <osg/Image>
#include <osg/ref_ptr>
#include <osgViewer/Viewer>

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace nestwalk {

struct RenderFrameStats {
  double cullMs = 0;       // event, update and cull traversals (nested culling included)
  double drawMs = 0;       // draw traversal until the GL has finished (glFinish)
  double readbackMs = 0;   // glReadPixels into the image
  double totalMs = 0;      // the whole frame
  std::uint64_t triangles = 0;    // triangles drawn (OSG's scene statistics)
  std::uint64_t terrainTiles = 0; // terrain chunks drawn
  double terrainErrorM = 0;       // largest vertical error (m) of the terrain chunks drawn
  double terrainErrorPx = 0;      // largest projected vertical error of a drawn chunk, pixels
  PagedTerrainStats terrain;      // the paged terrain's own figures for this frame (paged_terrain.h)
  CullCounts cull;                // nested culling's counts (all zero when it is off)
};

class ViewRenderer {
 public:
  // Builds the graph, creates the offscreen context (offscreen_context.h) and realizes the
  // viewer. Throws std::runtime_error when no context can be had, InputError (naming the file)
  // when the overlay's font cannot be loaded.
  explicit ViewRenderer(const Scene& scene, const RenderOptions& options = {});
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
  osg::Matrixd viewMatrix(const ViewPose& pose) const { return graph_->viewMatrix(pose); }
  const osg::Matrixd& projectionMatrix() const { return graph_->projectionMatrix(); }
  double nearPlane() const { return graph_->nearPlane(); }
  double farPlane() const { return graph_->farPlane(); }

  // The last frame's view frustum in the local frame (nested_cull.h).
  Frustum frustumLocal() const { return graph_->frustumLocal(); }
  // The equipment instances' bounding spheres as OSG sees them (local frame), for comparisons.
  std::vector<osg::BoundingSphere> instanceSpheres() const;
  const SceneGraphParts& parts() const { return graph_->parts(); }
  const ViewGraph& graph() const { return *graph_; }

  OffscreenRoute route() const { return context_->route(); }
  const std::string& glRenderer() const { return context_->glRenderer(); }
  const RenderOptions& options() const { return options_; }
  // The file of the overlay text's font (kUiFontPath; empty without an overlay text font: ID pass,
  // or blockedOverlay off).
  std::string overlayFontFile() const { return graph_->overlayFontFile(); }
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
