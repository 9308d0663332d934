// The walker's view as an OpenSceneGraph graph (view_graph.h).
#include "nestwalk/render/view_graph.h"

#include "nestwalk/core/angles.h"
#include "nestwalk/core/input_error.h"
#include "nestwalk/core/ui_font.h"
#include "nestwalk/render/view_depth.h"
#include "nestwalk/terrain/lod_rule.h"
#include "nestwalk/terrain/terrain_imagery.h"

#include <osg/Depth>
#include <osg/Fog>
#include <osg/Geode>
#include <osg/Light>
#include <osg/Material>
#include <osg/Program>
#include <osg/Projection>
#include <osgText/Font>
#include <osgText/Text>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace nestwalk {
namespace {

constexpr double kDegree = kRadiansPerDegree;

// Colours: sky from the horizon haze up to the zenith; the fog takes the horizon's colour so far
// terrain fades into the sky.
const osg::Vec4 kSkyHorizon(kSkyHorizonRgb[0], kSkyHorizonRgb[1], kSkyHorizonRgb[2], 1.0f);
const osg::Vec4 kSkyZenith(kSkyZenithRgb[0], kSkyZenithRgb[1], kSkyZenithRgb[2], 1.0f);
const osg::Vec4 kBlockedRed(0.90f, 0.10f, 0.10f, 1.0f);
const osg::Vec4 kBlockedTextHalo(1.0f, 1.0f, 1.0f, 0.85f);
// The sun: from the north-west, about 45 degrees up (the hillshade convention), as a direction
// towards the light in map axes.
const osg::Vec4 kSunDirection(-0.5f, 0.5f, 0.7071f, 0.0f);

// Render bins: sky first, the scene, then the overlays (the offscreen renderer ends its timed
// draw after them, view_renderer.cpp).
constexpr int kSkyBin = -10;
constexpr int kOverlayBin = 1000;

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

ViewGraph::ViewGraph(const Scene& scene, const RenderOptions& options, const TerrainNodeMaker& makeTerrain)
    : scene_(scene), options_(options) {
  if (options_.width < 16 || options_.height < 16)
    throw std::invalid_argument("render size must be at least 16 x 16 pixels");
  if (!scene_.terrain) throw std::invalid_argument("the scene has no terrain to render");
  const ViewDepth depth = viewDepth(scene_);  // view_depth.h: near, far and haze
  near_ = depth.nearM;
  far_ = depth.farM;
  hazeStart_ = depth.hazeStartM;
  hazeEnd_ = depth.hazeEndM;
  const terrain::Heightfield& hf = *scene_.terrain;
  const double aspect = double(options_.width) / double(options_.height);
  projection_ = osg::Matrixd::perspective(options_.fovYDegrees, aspect, near_, far_);
  localToMap_ = osg::Matrixd::translate(scene_.origin.x(), scene_.origin.y(), scene_.origin.z());

  SceneGraphOptions graph;
  graph.terrain = false;  // drawn by the paged terrain below
  graph.volumes = options_.volumes && !options_.idPass;
  terrain::LodRule rule;
  rule.fovYDegrees = options_.fovYDegrees;
  rule.screenHeightPx = options_.height;
  rule.maxPixels = options_.lodMaxPixels;
  pixelsPerRadian_ = rule.pixelsPerRadian();
  root_ = new osg::Group;
  root_->addChild(buildSceneGraph(scene_, graph, &parts_));

  // The terrain: chunks in the mesh frame (metres from sample (0, 0)), placed in the map frame.
  PagedTerrainOptions terrainOptions;
  terrainOptions.chunkCells = options_.terrainChunkCells;
  terrainOptions.pixelsPerRadian = pixelsPerRadian_;
  terrainOptions.maxPixels = options_.lodMaxPixels;
  terrainOptions.budgetBytes = options_.terrainBudgetBytes;
  terrainOptions.loading = options_.terrainLoading;
  terrainOptions.shade = options_.terrainShading && scene_.spec.hillshadeOn();
  terrainOptions.mapOrigin = hf.origin();
  if (options_.terrainChunkCells == terrain::kPyramidTopCells) {
    terrainOptions.pyramid = scene_.terrainPyramid;
    terrainOptions.pyramidHeightShift = scene_.terrainHeightShift;
  }
  if (!scene_.drapedImagery.empty() && !options_.idPass) {
    // Opened here, so a bad file is refused before the first frame; read only by the thread that
    // builds the chunks (paged_terrain.h).
    // A read that fails later (a file truncated on disk) leaves that chunk in its height colours.
    auto imagery = std::make_shared<terrain::TerrainImagery>(scene_.drapedImagery, hf.crsWkt());
    const Eigen::Vector2d first = hf.samplePosition(0, 0), last = hf.samplePosition(hf.cols() - 1, hf.rows() - 1);
    terrain::requireImageryOverlap(*imagery, first.x(), first.y(), last.x(), last.y());
    terrainOptions.imageryPixelM = imagery->pixelSize();  // tiles at its own resolution (imagery_tiles.h)
    terrainOptions.imageryFinestTexelM = options_.imageryFinestTexelM;
    terrainOptions.imageryMipmaps = options_.imageryMipmaps;
    terrainOptions.imagery = [imagery](double x0, double y0, double sx, double sy, int w, int h) {
      try {
        return imagery->read(x0, y0, sx, sy, w, h);
      } catch (const std::exception&) {
        return std::vector<std::uint8_t>();
      }
    };
  }
  osg::ref_ptr<osg::MatrixTransform> terrain =
      new osg::MatrixTransform(osg::Matrixd::translate(hf.origin().x(), hf.origin().y(), 0.0));
  if (makeTerrain) {
    madeTerrain_ = makeTerrain(scene_.terrain, terrainOptions);  // the same chunks and rule
    if (!madeTerrain_) throw std::logic_error("ViewGraph: the terrain maker made no terrain");
    terrain->addChild(madeTerrain_.get());
  } else {
    terrain_ = new PagedTerrain(scene_.terrain, std::move(terrainOptions));
    terrain->addChild(terrain_.get());
  }
  terrain->setName("terrain");
  root_->addChild(terrain);
  parts_.terrain = terrain;
  setUpStates();
  setUpOverlay();
  if (options_.nestedCulling && parts_.equipment) {
    culler_ = std::make_unique<NestedFrustumCuller>(scene_);
    culler_->install(parts_.equipment.get());
  }
}

ViewGraph::~ViewGraph() = default;

void ViewGraph::setViewportSize(int width, int height) {
  if (width <= 0 || height <= 0) return;
  projection_ = osg::Matrixd::perspective(options_.fovYDegrees, double(width) / double(height), near_, far_);
  terrain::LodRule rule;
  rule.fovYDegrees = options_.fovYDegrees;
  rule.screenHeightPx = height;
  pixelsPerRadian_ = rule.pixelsPerRadian();
  if (terrain_) terrain_->setPixelsPerRadian(pixelsPerRadian_);
  if (madeTerrain_) madeTerrain_->setPixelsPerRadian(pixelsPerRadian_);
}

PagedTerrain& ViewGraph::pagedTerrain() const {
  if (!terrain_) throw std::logic_error("ViewGraph::pagedTerrain: the terrain is a made one (terrain_node.h)");
  return *terrain_;
}

PagedTerrainStats ViewGraph::terrainStats() const {
  return terrain_ ? terrain_->lastStats() : madeTerrain_->frameStats();
}

void ViewGraph::attachTo(osg::View& view) const {
  osg::Camera* camera = view.getCamera();
  camera->setComputeNearFarMode(osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);
  camera->setProjectionMatrix(projection_);
  camera->setClearColor(options_.idPass ? osg::Vec4(0, 0, 0, 1) : kSkyHorizon);
  if (options_.idPass) {
    view.setLightingMode(osg::View::NO_LIGHT);
    return;
  }
  // A sun and sky light, positioned in the map frame.
  view.setLightingMode(osg::View::SKY_LIGHT);
  osg::Light* sun = view.getLight();
  sun->setPosition(kSunDirection);
  sun->setAmbient(osg::Vec4(0.30f, 0.30f, 0.32f, 1.0f));
  sun->setDiffuse(osg::Vec4(0.85f, 0.83f, 0.78f, 1.0f));
  sun->setSpecular(osg::Vec4(0, 0, 0, 1));
}

CullCounts ViewGraph::update(osg::Camera& camera, const ViewPose& pose) {
  view_ = viewMatrix(pose);
  camera.setViewMatrix(view_);
  camera.setProjectionMatrix(projection_);
  updateOverlay(pose);
  return culler_ ? culler_->update(frustumLocal()) : CullCounts{};
}

void ViewGraph::setUpStates() {
  osg::StateSet* ss = root_->getOrCreateStateSet();
  if (options_.idPass) {
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
  // Vertex colours (the terrain's colours by height) feed the lit material; the equipment models
  // carry their own materials.
  osg::ref_ptr<osg::Material> material = new osg::Material;
  material->setColorMode(osg::Material::AMBIENT_AND_DIFFUSE);
  ss->setAttributeAndModes(material.get(), osg::StateAttribute::ON);
  // Aerial haze: far terrain fades into the horizon's colour.
  osg::ref_ptr<osg::Fog> fog = new osg::Fog;
  fog->setMode(osg::Fog::LINEAR);
  fog->setColor(kSkyHorizon);
  fog->setStart(float(hazeStart_));
  fog->setEnd(float(hazeEnd_));
  ss->setAttributeAndModes(fog.get(), osg::StateAttribute::ON);
  // The terrain is only ever seen from above: its back faces (slopes turned away, and the skirts'
  // inner sides) are skipped before they are rasterised (measured: a quarter of the frame time on
  // llvmpipe). Its colours carry the hillshade of the same sun: no lighting.
  if (parts_.terrain) {
    osg::StateSet* terrainState = parts_.terrain->getOrCreateStateSet();
    terrainState->setMode(GL_CULL_FACE, osg::StateAttribute::ON);
    terrainState->setMode(GL_LIGHTING, osg::StateAttribute::OFF);
  }
}

void ViewGraph::setUpOverlay() {
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

void ViewGraph::updateOverlay(const ViewPose& pose) {
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

std::string ViewGraph::overlayFontFile() const {
  return blockedText_ && blockedText_->getFont() ? blockedText_->getFont()->getFileName() : std::string();
}

osg::Matrixd walkerViewMatrix(const ViewPose& pose) {
  const Eigen::Vector3d dir = viewDirection(pose.headingDeg, pose.pitchDeg);
  const double h = pose.headingDeg * kDegree, p = pose.pitchDeg * kDegree;
  const Eigen::Vector3d up(-std::sin(h) * std::sin(p), -std::cos(h) * std::sin(p), std::cos(p));
  const osg::Vec3d eye(pose.eye.x(), pose.eye.y(), pose.eye.z());
  return osg::Matrixd::lookAt(eye, eye + osg::Vec3d(dir.x(), dir.y(), dir.z()), osg::Vec3d(up.x(), up.y(), up.z()));
}

Frustum ViewGraph::frustumLocal() const {
  // local -> map is a translation by the origin.
  return Frustum::fromMatrices(localToMap_ * view_, projection_);
}

}  // namespace nestwalk
