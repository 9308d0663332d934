// The offscreen view renderer (view_renderer.h).
#include "nestwalk/render/view_renderer.h"

#include "nestwalk/render/view_graph.h"

#include <osg/Geode>
#include <osg/Polytope>
#include <osg/Timer>
#include <osgUtil/GLObjectsVisitor>

#include <GL/gl.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace nestwalk {
namespace {

// Drawn after the view graph's bins (sky, scene, overlays): ends the timed draw.
constexpr int kFinishBin = 100000;

double millis(osg::Timer_t from, osg::Timer_t to) { return osg::Timer::instance()->delta_m(from, to); }

}  // namespace

// Time stamps set from inside the draw traversal.
struct ViewRenderer::Timing {
  osg::Timer_t drawStart = 0, drawEnd = 0, readEnd = 0;
};

namespace {

struct StampCallback : osg::Camera::DrawCallback {
  StampCallback(std::shared_ptr<void> owner, osg::Timer_t* stamp) : owner_(std::move(owner)), stamp_(stamp) {}
  void operator()(osg::RenderInfo&) const override { *stamp_ = osg::Timer::instance()->tick(); }
  std::shared_ptr<void> owner_;
  osg::Timer_t* stamp_;
};

// Drawn last in the camera's render stage, while the frame buffer object is still bound: waits for
// the GL to finish drawing, so that what follows (the image read-back) is timed on its own.
struct FinishMarker : osg::Drawable {
  FinishMarker(std::shared_ptr<void> owner, osg::Timer_t* stamp) : owner_(std::move(owner)), stamp_(stamp) {
    setUseDisplayList(false);
    setCullingActive(false);
  }
  FinishMarker(const FinishMarker& o, const osg::CopyOp& op) : osg::Drawable(o, op), owner_(o.owner_), stamp_(o.stamp_) {}
  META_Object(nestwalk, FinishMarker)
  FinishMarker() = default;
  void drawImplementation(osg::RenderInfo&) const override {
    glFinish();
    if (stamp_) *stamp_ = osg::Timer::instance()->tick();
  }
  osg::BoundingSphere computeBound() const override { return osg::BoundingSphere(osg::Vec3(), 1.0f); }
  std::shared_ptr<void> owner_;
  osg::Timer_t* stamp_ = nullptr;
};

}  // namespace

ViewRenderer::ViewRenderer(const Scene& scene, const RenderOptions& options)
    : ViewRenderer(scene, options, TerrainNodeMaker()) {}

ViewRenderer::ViewRenderer(const Scene& scene, const RenderOptions& options, const TerrainNodeMaker& makeTerrain)
    : scene_(scene), options_(options), timing_(std::make_shared<Timing>()) {
  graph_ = std::make_unique<ViewGraph>(scene_, options_, makeTerrain);  // checks the size and the terrain first
  context_ = OffscreenContext::create(options_.width, options_.height);

  viewer_ = new osgViewer::Viewer;
  viewer_->setThreadingModel(osgViewer::Viewer::SingleThreaded);
  viewer_->setKeyEventSetsDone(0);
  osg::Camera* camera = viewer_->getCamera();
  if (context_->route() == OffscreenRoute::EglSurfaceless) {
    viewer_->setUpViewerAsEmbeddedInWindow(0, 0, options_.width, options_.height);
  } else {
    camera->setGraphicsContext(context_->pbuffer());
    camera->setViewport(0, 0, options_.width, options_.height);
  }
  image_ = new osg::Image;
  image_->allocateImage(options_.width, options_.height, 1, GL_RGB, GL_UNSIGNED_BYTE);
  camera->setRenderTargetImplementation(osg::Camera::FRAME_BUFFER_OBJECT);
  camera->attach(osg::Camera::COLOR_BUFFER, image_.get());
  camera->attach(osg::Camera::DEPTH_BUFFER, GL_DEPTH_COMPONENT24);
  camera->setInitialDrawCallback(new StampCallback(timing_, &timing_->drawStart));
  camera->setFinalDrawCallback(new StampCallback(timing_, &timing_->readEnd));
  graph_->attachTo(*viewer_);

  osg::ref_ptr<osg::Group> root = new osg::Group;
  root->addChild(graph_->root());
  osg::ref_ptr<osg::Geode> finish = new osg::Geode;
  finish->setCullingActive(false);
  finish->addDrawable(new FinishMarker(timing_, &timing_->drawEnd));
  finish->getOrCreateStateSet()->setRenderBinDetails(kFinishBin, "RenderBin");
  root->addChild(finish);
  viewer_->setSceneData(root.get());
  context_->makeCurrent();
  viewer_->realize();
  // Upload every model now, not when it first comes into view: otherwise that frame pays for the
  // upload (seen: 300 ms spikes at 1280 x 720). One frame first, so that OSG's GL state is set up,
  // then every node in the graph. (Terrain chunks are uploaded as they are first drawn: each is
  // small, paged_terrain.h.)
  viewer_->frame();
  osg::GraphicsContext* gc = camera->getGraphicsContext();
  if (gc && gc->getState()) {
    if (context_->route() == OffscreenRoute::X11Pbuffer) gc->makeCurrent();
    osgUtil::GLObjectsVisitor compile(osgUtil::GLObjectsVisitor::COMPILE_DISPLAY_LISTS |
                                      osgUtil::GLObjectsVisitor::COMPILE_STATE_ATTRIBUTES);
    osg::RenderInfo renderInfo(gc->getState(), viewer_.get());
    renderInfo.pushCamera(camera);
    compile.setRenderInfo(renderInfo);
    root->accept(compile);
    if (context_->route() == OffscreenRoute::X11Pbuffer) gc->releaseContext();
  }
}

osg::Matrixd ViewRenderer::viewMatrix(const ViewPose& pose) const { return graph_->viewMatrix(pose); }
const osg::Matrixd& ViewRenderer::projectionMatrix() const { return graph_->projectionMatrix(); }
double ViewRenderer::nearPlane() const { return graph_->nearPlane(); }
double ViewRenderer::farPlane() const { return graph_->farPlane(); }
Frustum ViewRenderer::frustumLocal() const { return graph_->frustumLocal(); }
const SceneGraphParts& ViewRenderer::parts() const { return graph_->parts(); }
std::string ViewRenderer::overlayFontFile() const { return graph_->overlayFontFile(); }

ViewRenderer::~ViewRenderer() {
  if (viewer_) {
    context_->makeCurrent();
    viewer_->setSceneData(nullptr);
    viewer_ = nullptr;  // releases the GL objects while the context is still current
  }
}

const RenderFrameStats& ViewRenderer::render(const ViewPose& pose) {
  const osg::Timer_t t0 = osg::Timer::instance()->tick();
  stats_ = RenderFrameStats{};
  stats_.cull = graph_->update(*viewer_->getCamera(), pose);
  *timing_ = Timing{};
  context_->makeCurrent();  // another renderer's context may have been current since
  viewer_->frame();
  const osg::Timer_t t1 = osg::Timer::instance()->tick();
  const Timing& t = *timing_;
  stats_.totalMs = millis(t0, t1);
  if (t.drawStart && t.drawEnd && t.readEnd) {
    stats_.cullMs = millis(t0, t.drawStart);
    stats_.drawMs = millis(t.drawStart, t.drawEnd);
    stats_.readbackMs = millis(t.drawEnd, t.readEnd);
  }
  const PagedTerrainStats terrain = graph_->terrainStats();  // whichever terrain draws (view_graph.h)
  stats_.terrain = terrain;
  stats_.terrainChunks = terrain.chunksDrawn;
  stats_.triangles += terrain.trianglesDrawn;
  stats_.terrainErrorM = terrain.maxErrorM;
  stats_.terrainErrorPx = terrain.maxErrorPx;
  // Triangles submitted: the terrain levels in view and the instances that survived culling.
  const SceneGraphParts& parts = graph_->parts();
  const NestedFrustumCuller* culler = graph_->culler();
  if (parts.equipment) {
    osg::Polytope osgFrustum;  // what OSG's own culling tests the instances' spheres against
    if (!culler) {
      osgFrustum.setToUnitFrustum();
      osgFrustum.transformProvidingInverse(graph_->localToMap() * graph_->lastViewMatrix() * graph_->projectionMatrix());
    }
    for (std::size_t i = 0; i < scene_.instances.size(); ++i) {
      const bool drawn =
          culler ? culler->visible(i) : osgFrustum.contains(parts.equipment->getChild(unsigned(i))->getBound());
      if (drawn) stats_.triangles += scene_.models[scene_.instances[i].model].mesh.triangles.size();
    }
  }
  return stats_;
}

std::vector<osg::BoundingSphere> ViewRenderer::instanceSpheres() const {
  std::vector<osg::BoundingSphere> spheres;
  const SceneGraphParts& parts = graph_->parts();
  if (!parts.equipment) return spheres;
  for (unsigned i = 0; i < parts.equipment->getNumChildren(); ++i)
    spheres.push_back(parts.equipment->getChild(i)->getBound());
  return spheres;
}

std::optional<Eigen::Vector2d> ViewRenderer::project(const Eigen::Vector3d& map) const {
  const osg::Vec4d clip = osg::Vec4d(map.x(), map.y(), map.z(), 1.0) * (graph_->lastViewMatrix() * graph_->projectionMatrix());
  if (clip.w() <= 0) return std::nullopt;
  const double nx = clip.x() / clip.w(), ny = clip.y() / clip.w();
  return Eigen::Vector2d(0.5 * (nx + 1.0) * options_.width, 0.5 * (1.0 - ny) * options_.height);
}

std::pair<Eigen::Vector3d, Eigen::Vector3d> ViewRenderer::pixelRay(double x, double y) const {
  const osg::Matrixd& view = graph_->lastViewMatrix();
  const osg::Matrixd inverse = osg::Matrixd::inverse(view * graph_->projectionMatrix());
  const double nx = 2.0 * x / options_.width - 1.0, ny = 1.0 - 2.0 * y / options_.height;
  const osg::Vec3d a = osg::Vec3d(nx, ny, -1.0) * inverse, b = osg::Vec3d(nx, ny, 1.0) * inverse;
  const osg::Vec3d eye = osg::Vec3d(0, 0, 0) * osg::Matrixd::inverse(view);
  osg::Vec3d dir = b - a;
  dir.normalize();
  return {Eigen::Vector3d(eye.x(), eye.y(), eye.z()), Eigen::Vector3d(dir.x(), dir.y(), dir.z())};
}

std::uint32_t ViewRenderer::idAt(const osg::Image& image, int x, int yFromTop) {
  const int row = image.t() - 1 - yFromTop;
  const unsigned char* p = image.data(x, row);
  return std::uint32_t(p[0]) | (std::uint32_t(p[1]) << 8) | (std::uint32_t(p[2]) << 16);
}

}  // namespace nestwalk
