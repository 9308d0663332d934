// The OpenSceneGraph graph of a loaded scene (scene.h, buildSceneGraph).
#include "nestwalk/render/scene_graph.h"

#include "nestwalk/render/model_nodes.h"

#include <osg/Geode>
#include <osg/Geometry>
#include <osg/MatrixTransform>
#include <osg/StateSet>

namespace nestwalk {
namespace {

/// Wireframe colours (RGBA): outer AABBs yellow, inner OBBs cyan.
const osg::Vec4 kOuterColour(1.0f, 0.85f, 0.1f, 1.0f);
const osg::Vec4 kInnerColour(0.1f, 0.9f, 1.0f, 1.0f);

/// p -> scale * rotation * p + translation as an OSG matrix (OSG multiplies row vectors: v * M).
osg::Matrixd toMatrix(const Similarity<double>& t) {
  osg::Matrixd m;  // identity
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = t.scale * t.rotation(j, i);
  for (int j = 0; j < 3; ++j) m(3, j) = t.translation[j];
  return m;
}

/// The 12 edges of a box given by its 8 corners (bit k of a corner's index: side along axis k).
void addBoxEdges(osg::Vec3Array& lines, const std::array<Vec3<double>, 8>& corners) {
  for (int i = 0; i < 8; ++i)
    for (int k = 0; k < 3; ++k) {
      const int j = i | (1 << k);
      if (j == i) continue;
      lines.push_back(osg::Vec3(float(corners[i].x()), float(corners[i].y()), float(corners[i].z())));
      lines.push_back(osg::Vec3(float(corners[j].x()), float(corners[j].y()), float(corners[j].z())));
    }
}

osg::ref_ptr<osg::Geometry> lineGeometry(osg::Vec3Array* lines, const osg::Vec4& colour) {
  osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
  g->setVertexArray(lines);
  osg::ref_ptr<osg::Vec4Array> colours = new osg::Vec4Array;
  colours->push_back(colour);
  g->setColorArray(colours, osg::Array::BIND_OVERALL);
  g->addPrimitiveSet(new osg::DrawArrays(GL_LINES, 0, GLsizei(lines->size())));
  return g;
}

osg::ref_ptr<osg::Node> volumeWireframes(const Scene& scene) {
  osg::ref_ptr<osg::Vec3Array> outer = new osg::Vec3Array, inner = new osg::Vec3Array;
  for (const auto& u : scene.units) {
    std::array<Vec3<double>, 8> corners;
    for (int i = 0; i < 8; ++i)
      corners[i] = {(i & 1) ? u.volume.outer.max.x() : u.volume.outer.min.x(),
                    (i & 2) ? u.volume.outer.max.y() : u.volume.outer.min.y(),
                    (i & 4) ? u.volume.outer.max.z() : u.volume.outer.min.z()};
    addBoxEdges(*outer, corners);
    for (int i = 0; i < 8; ++i) corners[i] = u.volume.inner.corner(i);
    addBoxEdges(*inner, corners);
  }
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->setName("volumes");
  geode->addDrawable(lineGeometry(outer, kOuterColour));
  geode->addDrawable(lineGeometry(inner, kInnerColour));
  geode->getOrCreateStateSet()->setMode(GL_LIGHTING, osg::StateAttribute::OFF | osg::StateAttribute::PROTECTED);
  return geode;
}

}  // namespace

osg::ref_ptr<osg::Group> buildSceneGraph(const Scene& scene, const SceneGraphOptions& options, SceneGraphParts* parts) {
  SceneGraphParts local;
  SceneGraphParts& out = parts ? *parts : local;
  out = SceneGraphParts{};
  osg::ref_ptr<osg::Group> root = new osg::Group;
  root->setName("scene");
  osg::ref_ptr<osg::MatrixTransform> localToMap =
      new osg::MatrixTransform(osg::Matrixd::translate(scene.origin.x(), scene.origin.y(), scene.origin.z()));
  localToMap->setName("local_to_map");
  root->addChild(localToMap);

  if (options.terrain && scene.terrain) {
    // Chunk vertices are (col * dx, -row * dy, h): metres from sample (0, 0) with map heights.
    const terrain::Heightfield& hf = *scene.terrain;
    const Eigen::Vector2d sample0 = hf.origin();
    osg::ref_ptr<osg::MatrixTransform> tiles = new osg::MatrixTransform(
        osg::Matrixd::translate(sample0.x() - scene.origin.x(), sample0.y() - scene.origin.y(), -scene.origin.z()));
    tiles->setName("terrain");
    TerrainCutOptions cut = options.terrainCut;
    if (!cut.pyramid) {
      cut.pyramid = scene.terrainPyramid;
      cut.pyramidHeightShift = scene.terrainHeightShift;
    }
    tiles->addChild(buildTerrainCut(hf, cut, &out.terrainCut));
    localToMap->addChild(tiles);
    out.terrain = tiles;
  }

  if (options.equipment) {
    osg::ref_ptr<osg::Group> equipment = new osg::Group;
    equipment->setName("equipment");
    out.modelNodes = buildModelNodes(scene);
    for (const auto& inst : scene.instances) {
      osg::ref_ptr<osg::MatrixTransform> t = new osg::MatrixTransform(toMatrix(inst.toLocal));
      t->setName(scene.spec.equipment[inst.spec].name);
      // Scaled instances: keep lighting right by renormalizing the transformed normals.
      if (inst.toLocal.scale != 1.0) t->getOrCreateStateSet()->setMode(GL_RESCALE_NORMAL, osg::StateAttribute::ON);
      t->addChild(out.modelNodes[inst.model]);
      equipment->addChild(t);
    }
    localToMap->addChild(equipment);
    out.equipment = equipment;
  }

  if (options.volumes) {
    osg::ref_ptr<osg::Group> volumes = new osg::Group;
    volumes->setName("volumes");
    volumes->addChild(volumeWireframes(scene));
    localToMap->addChild(volumes);
    out.volumes = volumes;
  }
  return root;
}

}  // namespace nestwalk
