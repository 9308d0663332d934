// The walker's view, rendered offscreen with OpenSceneGraph: the scene graph of a loaded scene
// (terrain tiles with screen-space-error LOD, equipment instances over shared model nodes), lit by
// a sun, a sky behind, optional overlays (volumes, blocked state), read back into an image each
// frame with the time split into cull, draw and readback.
//
// Camera: the eye in map coordinates; heading clockwise from north, pitch up positive (the
// walker's and the scripts' convention); vertical field of view fovYDegrees; near and far fixed
// (no OSG near/far computation, which clips the ground in front of a low eye over a large
// terrain): near is half the body's smaller horizontal half extent (equipment can never be nearer
// to the eye than the body lets it come), far reaches past the terrain's farthest corner.
//
// Culling: equipment is culled with the nested volumes (outer AABB, then inner OBB, see
// nested_cull.h) unless options.nestedCulling is off (then OSG's bounding spheres decide).
//
// The blocked overlay (options.blockedOverlay): a red frame and "BLOCKED by <unit>" in osgText, set
// in the UI font (nestwalk/core/ui_font.h: DejaVu Sans from its file, through OSG's freetype
// plugin), the font of the report's pictures; the constructor throws InputError naming the font's
// file when it cannot be loaded.
//
// The ID pass (options.idPass): no lighting, no sky, no overlays; every pixel carries what it
// shows: sky 0, terrain 1, instance i: i + 2, as 24-bit RGB (R the low byte). Tests use it to
// check what is where on screen.
//
// Threading: SingleThreaded, on the creating thread (the offscreen context is current there).
//
// Ownership: the renderer keeps a reference to `scene`, which must outlive it; its graph shares the
// scene's model nodes (ref_ptr) and compiles GL objects into them for its own context. Several
// renderers may live on one thread (render() makes its context current again), but see
// offscreen_context.h on destroying one while another lives.
#pragma once

#include "nestwalk/render/nested_cull.h"
#include "nestwalk/render/offscreen_context.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_graph.h"

#include <osg/Geometry>
#include <osg/Image>
#include <osg/ref_ptr>
#include <osgViewer/Viewer>

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace osgText {
class Text;
}

namespace nestwalk {

struct RenderOptions {
  int width = 1280, height = 720;
  double fovYDegrees = 60.0;
  double lodMaxPixels = 1.0;     // terrain LOD: the largest vertical error allowed on screen, pixels
  int terrainTileCells = 32;     // cells per terrain tile side (power of two; 32 was fastest here,
                                 // against 16, 64 and 128: `nestwalk bench render`)
  bool nestedCulling = true;     // false: OSG's bounding-sphere culling decides alone
  bool volumes = false;          // outer AABBs (yellow) and inner OBBs (cyan) as wireframes
  bool blockedOverlay = true;    // a red frame and the blocker's name while blocked
  bool idPass = false;           // render IDs instead of colours (see above)
};

// Where the walker is and what it sees (map frame).
struct ViewPose {
  Eigen::Vector3d eye = Eigen::Vector3d::Zero();
  double headingDeg = 0, pitchDeg = 0;
  bool blocked = false;
  std::string blockedBy;
};

struct RenderFrameStats {
  double cullMs = 0;       // event, update and cull traversals (nested culling included)
  double drawMs = 0;       // draw traversal until the GL has finished (glFinish)
  double readbackMs = 0;   // glReadPixels into the image
  double totalMs = 0;      // the whole frame
  std::uint64_t triangles = 0;    // triangles drawn (OSG's scene statistics)
  std::uint64_t terrainTiles = 0; // terrain tiles in view
  double terrainErrorM = 0;       // largest vertical error (m) of the terrain levels drawn
  double terrainErrorPx = 0;      // largest projected vertical error of a drawn tile level, pixels
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
  osg::Matrixd viewMatrix(const ViewPose& pose) const;
  const osg::Matrixd& projectionMatrix() const { return projection_; }
  double nearPlane() const { return near_; }
  double farPlane() const { return far_; }

  // The last frame's view frustum in the local frame (nested_cull.h).
  Frustum frustumLocal() const;
  // The equipment instances' bounding spheres as OSG sees them (local frame), for comparisons.
  std::vector<osg::BoundingSphere> instanceSpheres() const;
  const SceneGraphParts& parts() const { return parts_; }

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
  void setUpStates();
  void setUpOverlay();
  void updateOverlay(const ViewPose& pose);
  void measureTerrain(const Eigen::Vector3d& eyeMap);

  const Scene& scene_;
  RenderOptions options_;
  std::unique_ptr<OffscreenContext> context_;
  osg::ref_ptr<osgViewer::Viewer> viewer_;
  osg::ref_ptr<osg::Group> root_;
  SceneGraphParts parts_;
  osg::ref_ptr<osg::Image> image_;
  osg::ref_ptr<osg::Group> overlay_;
  osg::ref_ptr<osg::Geometry> sky_;
  osg::ref_ptr<osg::Node> blockedFrame_;
  osg::ref_ptr<osgText::Text> blockedText_;
  std::unique_ptr<NestedFrustumCuller> culler_;
  std::shared_ptr<Timing> timing_;
  osg::Matrixd projection_, view_;
  osg::Matrixd localToMap_;                                  // translation by the scene's origin
  Eigen::Vector2d terrainOffset_ = Eigen::Vector2d::Zero();  // map x, y of the mesh frame's origin
  double pixelsPerRadian_ = 0;                               // the LOD rule's, for the drawn error
  double near_ = 0.1, far_ = 10000;
  RenderFrameStats stats_;
};

}  // namespace nestwalk
