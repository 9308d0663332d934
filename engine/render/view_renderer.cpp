// The offscreen view renderer (view_renderer.h).
#include "nestwalk/render/view_renderer.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/core/ui_font.h"

#include <osg/BlendFunc>
#include <osg/Depth>
#include <osg/Fog>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/Light>
#include <osg/Material>
#include <osg/MatrixTransform>
#include <osg/Polytope>
#include <osg/Program>
#include <osg/Projection>
#include <osg/Timer>
#include <osgText/Font>
#include <osgText/Text>
#include <osgUtil/GLObjectsVisitor>

#include <GL/gl.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace nestwalk {
namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

// Colours: sky from the horizon haze up to the zenith; the fog takes the horizon's colour so far
// terrain fades into the sky.
const osg::Vec4 kSkyHorizon(0.78f, 0.85f, 0.93f, 1.0f);
const osg::Vec4 kSkyZenith(0.30f, 0.50f, 0.82f, 1.0f);
const osg::Vec4 kBlockedRed(0.90f, 0.10f, 0.10f, 1.0f);
const osg::Vec4 kBlockedTextHalo(1.0f, 1.0f, 1.0f, 0.85f);
// The sun: from the north-west, about 45 degrees up (the hillshade convention), as a direction
// towards the light in map axes.
const osg::Vec4 kSunDirection(-0.5f, 0.5f, 0.7071f, 0.0f);

// Render bins: sky first, the scene, the overlays, then the marker that ends the timed draw.
constexpr int kSkyBin = -10;
constexpr int kOverlayBin = 1000;
constexpr int kFinishBin = 100000;

const char* kIdVertexShader = R"(#version 120
void main() { gl_Position = ftransform(); }
)";
const char* kIdFragmentShader = R"(#version 120
uniform vec3 nw_id;
void main() { gl_FragColor = vec4(nw_id, 1.0); }
)";

osg::Vec3 idColour(std::uint32_t id) {
  return osg::Vec3(float(id & 0xFFu) / 255.0f, float((id >> 8) & 0xFFu) / 255.0f, float((id >> 16) & 0xFFu) / 255.0f);
}

Eigen::Vector3d viewDirection(double headingDeg, double pitchDeg) {
  const double h = headingDeg * kDegree, p = pitchDeg * kDegree;
  return {std::sin(h) * std::cos(p), std::cos(h) * std::cos(p), std::sin(p)};
}

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

// A screen-space layer: an orthographic projection over [0, w] x [0, h], absolute reference frame,
// no lighting, no depth test, drawn in `bin`.
osg::ref_ptr<osg::MatrixTransform> screenLayer(osg::Group* parent, double w, double h, int bin) {
  osg::ref_ptr<osg::Projection> projection = new osg::Projection(osg::Matrixd::ortho2D(0, w, 0, h));
  osg::ref_ptr<osg::MatrixTransform> layer = new osg::MatrixTransform;
  layer->setReferenceFrame(osg::Transform::ABSOLUTE_RF);
  projection->addChild(layer);
  projection->setCullingActive(false);
  layer->setCullingActive(false);
  osg::StateSet* ss = projection->getOrCreateStateSet();
  ss->setMode(GL_LIGHTING, osg::StateAttribute::OFF | osg::StateAttribute::PROTECTED);
  ss->setMode(GL_DEPTH_TEST, osg::StateAttribute::OFF | osg::StateAttribute::PROTECTED);
  ss->setMode(GL_FOG, osg::StateAttribute::OFF | osg::StateAttribute::PROTECTED);
  ss->setAttributeAndModes(new osg::Depth(osg::Depth::ALWAYS, 0, 1, false), osg::StateAttribute::ON);
  ss->setRenderBinDetails(bin, "RenderBin");
  parent->addChild(projection);
  return layer;
}

osg::ref_ptr<osg::Geometry> quads(osg::Vec3Array* vertices, osg::Vec4Array* colours) {
  osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
  g->setUseDisplayList(false);
  g->setUseVertexBufferObjects(true);
  g->setDataVariance(osg::Object::DYNAMIC);
  g->setVertexArray(vertices);
  g->setColorArray(colours, osg::Array::BIND_PER_VERTEX);
  g->addPrimitiveSet(new osg::DrawArrays(GL_QUADS, 0, GLsizei(vertices->size())));
  g->setCullingActive(false);
  return g;
}

}  // namespace

ViewRenderer::ViewRenderer(const Scene& scene, const RenderOptions& options)
    : scene_(scene), options_(options), timing_(std::make_shared<Timing>()) {
  if (options_.width < 16 || options_.height < 16)
    throw std::invalid_argument("render size must be at least 16 x 16 pixels");
  if (!scene_.terrain) throw std::invalid_argument("the scene has no terrain to render");
  context_ = OffscreenContext::create(options_.width, options_.height);

  // Near: nothing the walker may come to is nearer to the eye than the body's horizontal half
  // extent; half of the smaller one leaves the near plane's corners clear of it too. Far: past the
  // terrain's farthest corner from anywhere above it.
  const Eigen::Vector3d& body = scene_.spec.viewer.bodyHalfExtents;
  near_ = std::clamp(0.5 * std::min(body.x(), body.y()), 0.05, 0.5);
  const terrain::Heightfield& hf = *scene_.terrain;
  const double width = hf.cols() * hf.dx(), height = hf.rows() * hf.dy();
  far_ = 1.5 * std::hypot(width, height) + 1000.0;
  const double aspect = double(options_.width) / double(options_.height);
  projection_ = osg::Matrixd::perspective(options_.fovYDegrees, aspect, near_, far_);
  localToMap_ = osg::Matrixd::translate(scene_.origin.x(), scene_.origin.y(), scene_.origin.z());
  terrainOffset_ = hf.origin();

  SceneGraphOptions graph;
  graph.volumes = options_.volumes && !options_.idPass;
  graph.terrainTileCells = options_.terrainTileCells;
  graph.terrainLod.fovYDegrees = options_.fovYDegrees;
  graph.terrainLod.screenHeightPx = options_.height;
  graph.terrainLod.maxPixels = options_.lodMaxPixels;
  pixelsPerRadian_ = graph.terrainLod.pixelsPerRadian();
  root_ = new osg::Group;
  root_->addChild(buildSceneGraph(scene_, graph, &parts_));

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
  camera->setComputeNearFarMode(osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);
  camera->setProjectionMatrix(projection_);
  camera->setClearColor(options_.idPass ? osg::Vec4(0, 0, 0, 1) : kSkyHorizon);
  camera->setInitialDrawCallback(new StampCallback(timing_, &timing_->drawStart));
  camera->setFinalDrawCallback(new StampCallback(timing_, &timing_->readEnd));

  setUpStates();
  setUpOverlay();
  osg::ref_ptr<osg::Geode> finish = new osg::Geode;
  finish->setCullingActive(false);
  finish->addDrawable(new FinishMarker(timing_, &timing_->drawEnd));
  finish->getOrCreateStateSet()->setRenderBinDetails(kFinishBin, "RenderBin");
  root_->addChild(finish);

  if (options_.nestedCulling && parts_.equipment) {
    culler_ = std::make_unique<NestedFrustumCuller>(scene_);
    culler_->install(parts_.equipment.get());
  }
  viewer_->setSceneData(root_.get());
  context_->makeCurrent();
  viewer_->realize();
  // Upload every terrain level and model now, not when the LOD first picks it: otherwise a frame
  // that switches levels pays for the upload (seen: 300 ms spikes at 1280 x 720). One frame first,
  // so that OSG's GL state is set up, then every node, whatever its LOD range.
  viewer_->frame();
  osg::GraphicsContext* gc = camera->getGraphicsContext();
  if (gc && gc->getState()) {
    if (context_->route() == OffscreenRoute::X11Pbuffer) gc->makeCurrent();
    osgUtil::GLObjectsVisitor compile(osgUtil::GLObjectsVisitor::COMPILE_DISPLAY_LISTS |
                                      osgUtil::GLObjectsVisitor::COMPILE_STATE_ATTRIBUTES);
    osg::RenderInfo renderInfo(gc->getState(), viewer_.get());
    renderInfo.pushCamera(camera);
    compile.setRenderInfo(renderInfo);
    root_->accept(compile);
    if (context_->route() == OffscreenRoute::X11Pbuffer) gc->releaseContext();
  }
}

ViewRenderer::~ViewRenderer() {
  if (viewer_) {
    context_->makeCurrent();
    viewer_->setSceneData(nullptr);
    viewer_ = nullptr;  // releases the GL objects while the context is still current
  }
}

void ViewRenderer::setUpStates() {
  osg::StateSet* ss = root_->getOrCreateStateSet();
  if (options_.idPass) {
    viewer_->setLightingMode(osg::View::NO_LIGHT);
    osg::ref_ptr<osg::Program> program = new osg::Program;
    program->addShader(new osg::Shader(osg::Shader::VERTEX, kIdVertexShader));
    program->addShader(new osg::Shader(osg::Shader::FRAGMENT, kIdFragmentShader));
    ss->setAttributeAndModes(program.get(), osg::StateAttribute::ON | osg::StateAttribute::OVERRIDE);
    ss->addUniform(new osg::Uniform("nw_id", idColour(0)));
    if (parts_.terrain) parts_.terrain->getOrCreateStateSet()->addUniform(new osg::Uniform("nw_id", idColour(1)));
    if (parts_.equipment)
      for (unsigned i = 0; i < parts_.equipment->getNumChildren(); ++i)
        parts_.equipment->getChild(i)->getOrCreateStateSet()->addUniform(new osg::Uniform("nw_id", idColour(i + 2)));
    return;
  }
  // A sun and sky light, positioned in the map frame.
  viewer_->setLightingMode(osg::View::SKY_LIGHT);
  osg::Light* sun = viewer_->getLight();
  sun->setPosition(kSunDirection);
  sun->setAmbient(osg::Vec4(0.30f, 0.30f, 0.32f, 1.0f));
  sun->setDiffuse(osg::Vec4(0.85f, 0.83f, 0.78f, 1.0f));
  sun->setSpecular(osg::Vec4(0, 0, 0, 1));
  // Vertex colours (the terrain's colours by height) feed the lit material; the equipment models
  // carry their own materials.
  osg::ref_ptr<osg::Material> material = new osg::Material;
  material->setColorMode(osg::Material::AMBIENT_AND_DIFFUSE);
  ss->setAttributeAndModes(material.get(), osg::StateAttribute::ON);
  // Aerial haze: far terrain fades into the horizon's colour.
  osg::ref_ptr<osg::Fog> fog = new osg::Fog;
  fog->setMode(osg::Fog::LINEAR);
  fog->setColor(kSkyHorizon);
  fog->setStart(float(std::min(1500.0, 0.3 * far_)));
  fog->setEnd(float(far_));
  ss->setAttributeAndModes(fog.get(), osg::StateAttribute::ON);
  // The terrain is only ever seen from above: its back faces (slopes turned away) are skipped
  // before they are rasterised (measured: a quarter of the frame time on llvmpipe).
  if (parts_.terrain) parts_.terrain->getOrCreateStateSet()->setMode(GL_CULL_FACE, osg::StateAttribute::ON);
}

void ViewRenderer::setUpOverlay() {
  if (options_.idPass) return;
  const double w = options_.width, h = options_.height;
  // The sky: a vertical gradient behind everything; its horizon row follows the pitch (render()).
  osg::ref_ptr<osg::MatrixTransform> sky = screenLayer(root_.get(), 1, 1, kSkyBin);
  sky->setName("sky");
  {
    osg::ref_ptr<osg::Vec3Array> v = new osg::Vec3Array(8);
    osg::ref_ptr<osg::Vec4Array> c = new osg::Vec4Array(8);
    osg::ref_ptr<osg::Geode> geode = new osg::Geode;
    sky_ = quads(v.get(), c.get());
    geode->addDrawable(sky_.get());
    sky->addChild(geode);
  }
  overlay_ = screenLayer(root_.get(), w, h, kOverlayBin);
  overlay_->setName("overlay");
  // The blocked state: a red frame and the blocker's name.
  osg::ref_ptr<osg::Geode> frame = new osg::Geode;
  {
    const float b = float(std::max(4.0, 0.006 * h));
    const float W = float(w), H = float(h);
    osg::ref_ptr<osg::Vec3Array> v = new osg::Vec3Array;
    auto rect = [&](float x0, float y0, float x1, float y1) {
      v->push_back({x0, y0, 0});
      v->push_back({x1, y0, 0});
      v->push_back({x1, y1, 0});
      v->push_back({x0, y1, 0});
    };
    rect(0, 0, W, b);
    rect(0, H - b, W, H);
    rect(0, b, b, H - b);
    rect(W - b, b, W, H - b);
    osg::ref_ptr<osg::Vec4Array> c = new osg::Vec4Array(v->size());
    std::fill(c->begin(), c->end(), kBlockedRed);
    frame->addDrawable(quads(v.get(), c.get()));
    osg::ref_ptr<osgText::Text> text = new osgText::Text;
    if (options_.blockedOverlay) {
      // The UI font from its file (ui_font.h), as the report's pictures use it.
      const std::string fontPath = uiFontPath();
      osg::ref_ptr<osgText::Font> font = osgText::readRefFontFile(fontPath);
      if (!font)
        throw InputError(fontPath + ": osgText cannot load the overlay's font (is OpenSceneGraph's freetype plugin installed?)");
      text->setFont(font);
    }
    text->setCharacterSize(float(std::max(12.0, 0.035 * h)));
    text->setColor(kBlockedRed);
    // A light outline keeps the name readable over dark equipment and bright sky alike (the report's
    // map labels have the same halo).
    text->setBackdropType(osgText::Text::OUTLINE);
    text->setBackdropColor(kBlockedTextHalo);
    text->setPosition(osg::Vec3(float(2.5 * b), float(h - 2.5 * b), 0));
    text->setAlignment(osgText::Text::LEFT_TOP);
    text->setDataVariance(osg::Object::DYNAMIC);
    frame->addDrawable(text.get());
    blockedText_ = text;
  }
  frame->setNodeMask(0);
  blockedFrame_ = frame;
  overlay_->addChild(frame);
}

void ViewRenderer::updateOverlay(const ViewPose& pose) {
  if (options_.idPass) return;
  // Sky gradient rows: bottom, horizon (where a level line of sight meets the screen), top.
  const double tanHalf = std::tan(0.5 * options_.fovYDegrees * kDegree);
  const double horizon = std::clamp(0.5 - 0.5 * std::tan(pose.pitchDeg * kDegree) / tanHalf, 0.0, 1.0);
  osg::Geometry* g = sky_.get();
  auto* v = static_cast<osg::Vec3Array*>(g->getVertexArray());
  auto* c = static_cast<osg::Vec4Array*>(g->getColorArray());
  const float y = float(horizon);
  (*v)[0] = {0, 0, 0};
  (*v)[1] = {1, 0, 0};
  (*v)[2] = {1, y, 0};
  (*v)[3] = {0, y, 0};
  (*v)[4] = {0, y, 0};
  (*v)[5] = {1, y, 0};
  (*v)[6] = {1, 1, 0};
  (*v)[7] = {0, 1, 0};
  for (int i = 0; i < 6; ++i) (*c)[i] = kSkyHorizon;
  (*c)[6] = (*c)[7] = kSkyZenith;
  v->dirty();
  c->dirty();
  g->dirtyBound();

  const bool show = options_.blockedOverlay && pose.blocked;
  blockedFrame_->setNodeMask(show ? ~0u : 0u);
  if (show) blockedText_->setText("BLOCKED by " + pose.blockedBy);
}

std::string ViewRenderer::overlayFontFile() const {
  return blockedText_ && blockedText_->getFont() ? blockedText_->getFont()->getFileName() : std::string();
}

osg::Matrixd ViewRenderer::viewMatrix(const ViewPose& pose) const {
  const Eigen::Vector3d dir = viewDirection(pose.headingDeg, pose.pitchDeg);
  const double h = pose.headingDeg * kDegree, p = pose.pitchDeg * kDegree;
  const Eigen::Vector3d up(-std::sin(h) * std::sin(p), -std::cos(h) * std::sin(p), std::cos(p));
  const osg::Vec3d eye(pose.eye.x(), pose.eye.y(), pose.eye.z());
  return osg::Matrixd::lookAt(eye, eye + osg::Vec3d(dir.x(), dir.y(), dir.z()), osg::Vec3d(up.x(), up.y(), up.z()));
}

const RenderFrameStats& ViewRenderer::render(const ViewPose& pose) {
  const osg::Timer_t t0 = osg::Timer::instance()->tick();
  stats_ = RenderFrameStats{};
  view_ = viewMatrix(pose);
  osg::Camera* camera = viewer_->getCamera();
  camera->setViewMatrix(view_);
  camera->setProjectionMatrix(projection_);
  updateOverlay(pose);
  if (culler_) stats_.cull = culler_->update(frustumLocal());
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
  measureTerrain(pose.eye);
  // Triangles submitted: the terrain levels in view and the instances that survived culling.
  if (parts_.equipment) {
    osg::Polytope osgFrustum;  // what OSG's own culling tests the instances' spheres against
    if (!culler_) {
      osgFrustum.setToUnitFrustum();
      osgFrustum.transformProvidingInverse(localToMap_ * view_ * projection_);
    }
    for (std::size_t i = 0; i < scene_.instances.size(); ++i) {
      const bool drawn =
          culler_ ? culler_->visible(i) : osgFrustum.contains(parts_.equipment->getChild(unsigned(i))->getBound());
      if (drawn) stats_.triangles += scene_.models[scene_.instances[i].model].triangles;
    }
  }
  return stats_;
}

void ViewRenderer::measureTerrain(const Eigen::Vector3d& eyeMap) {
  if (!parts_.terrainMesh) return;
  const terrain::TerrainMesh& mesh = *parts_.terrainMesh;
  // The mesh frame is the map frame less (x, y) of sample (0, 0).
  const osg::Matrixd meshToMap = osg::Matrixd::translate(terrainOffset_.x(), terrainOffset_.y(), 0);
  osg::Polytope frustum;
  frustum.setToUnitFrustum();
  frustum.transformProvidingInverse(meshToMap * view_ * projection_);
  const osg::Vec3d eye(eyeMap.x() - terrainOffset_.x(), eyeMap.y() - terrainOffset_.y(), eyeMap.z());
  for (std::size_t i = 0; i < parts_.terrainTiles.size(); ++i) {
    const osg::LOD* lod = parts_.terrainTiles[i].get();
    if (!lod) continue;
    const osg::BoundingSphere sphere(lod->getCenter(), lod->getRadius());
    if (!frustum.contains(sphere)) continue;
    // The child OSG's LOD picks: the range that holds the eye's distance to the centre.
    const double d = (osg::Vec3d(lod->getCenter()) - eye).length();
    const float df = float(d);
    int level = -1;
    for (unsigned k = 0; k < lod->getNumRanges(); ++k)
      if (lod->getMinRange(k) <= df && df < lod->getMaxRange(k)) {
        level = int(k);
        break;
      }
    if (level < 0) continue;
    const terrain::TerrainTile& tile = mesh.tiles()[i];
    ++stats_.terrainTiles;
    stats_.triangles += tile.triangles[std::size_t(level)];
    const double error = tile.maxError[std::size_t(level)];
    stats_.terrainErrorM = std::max(stats_.terrainErrorM, error);
    const double nearest = std::max(d - lod->getRadius(), near_);
    stats_.terrainErrorPx = std::max(stats_.terrainErrorPx, error * pixelsPerRadian_ / nearest);
  }
}

Frustum ViewRenderer::frustumLocal() const {
  // local -> map is a translation by the origin.
  return Frustum::fromMatrices(localToMap_ * view_, projection_);
}

std::vector<osg::BoundingSphere> ViewRenderer::instanceSpheres() const {
  std::vector<osg::BoundingSphere> spheres;
  if (!parts_.equipment) return spheres;
  for (unsigned i = 0; i < parts_.equipment->getNumChildren(); ++i)
    spheres.push_back(parts_.equipment->getChild(i)->getBound());
  return spheres;
}

std::optional<Eigen::Vector2d> ViewRenderer::project(const Eigen::Vector3d& map) const {
  const osg::Vec4d clip = osg::Vec4d(map.x(), map.y(), map.z(), 1.0) * (view_ * projection_);
  if (clip.w() <= 0) return std::nullopt;
  const double nx = clip.x() / clip.w(), ny = clip.y() / clip.w();
  return Eigen::Vector2d(0.5 * (nx + 1.0) * options_.width, 0.5 * (1.0 - ny) * options_.height);
}

std::pair<Eigen::Vector3d, Eigen::Vector3d> ViewRenderer::pixelRay(double x, double y) const {
  const osg::Matrixd inverse = osg::Matrixd::inverse(view_ * projection_);
  const double nx = 2.0 * x / options_.width - 1.0, ny = 1.0 - 2.0 * y / options_.height;
  const osg::Vec3d a = osg::Vec3d(nx, ny, -1.0) * inverse, b = osg::Vec3d(nx, ny, 1.0) * inverse;
  const osg::Vec3d eye = osg::Vec3d(0, 0, 0) * osg::Matrixd::inverse(view_);
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
