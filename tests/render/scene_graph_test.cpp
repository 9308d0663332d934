// The scene's drawing graph (render/scene_graph.h): a small scene on a planar GeoTIFF terrain
// written with GDAL, at the origin and at UTM magnitudes, loaded and drawn. Expected values come
// from the scene's own transforms (Similarity::apply, in double), from the plane's formula for the
// terrain's vertices and from OSG's matrix stack for the graph; the models' nodes are read back
// into meshes and compared with the scene's.
#include "nestwalk/render/scene_graph.h"
#include "nestwalk/scene/node_geometry.h"
#include "nestwalk/scene/scene_loader.h"
#include "tests/common/box_model.h"
#include "tests/scene/scene_test_util.h"

#include <nlohmann/json.hpp>
#include <osg/Geometry>
#include <osg/MatrixTransform>
#include <osg/NodeVisitor>

#include <cmath>
#include <map>

namespace nestwalk {
namespace {

using test::weatherStation;
using Json = nlohmann::json;


/// Every Geometry under a node with its local-to-world matrix (all paths).
class GeometryFinder : public osg::NodeVisitor {
 public:
  GeometryFinder() : osg::NodeVisitor(TRAVERSE_ALL_CHILDREN) {}
  void apply(osg::Geometry& g) override { found.push_back({&g, osg::computeLocalToWorld(getNodePath())}); }
  std::vector<std::pair<osg::Geometry*, osg::Matrixd>> found;
};

/// Named MatrixTransforms under a node.
class TransformFinder : public osg::NodeVisitor {
 public:
  TransformFinder() : osg::NodeVisitor(TRAVERSE_ALL_CHILDREN) {}
  void apply(osg::MatrixTransform& t) override {
    byName[t.getName()].push_back(&t);
    traverse(t);
  }
  std::map<std::string, std::vector<osg::MatrixTransform*>> byName;
};

osg::Node* childNamed(osg::Group& g, const std::string& name) {
  for (unsigned i = 0; i < g.getNumChildren(); ++i)
    if (g.getChild(i)->getName() == name) return g.getChild(i);
  return nullptr;
}

class SceneGraph : public test::PlaneTerrainTest {
 protected:
  /// Writes scene.json (terrain.tif beside it) with these equipment entries and loads it.
  Scene load(const Json& equipment) {
    test::writeText(dir() / "scene.json", Json{{"terrain", "terrain.tif"}, {"equipment", equipment}}.dump(2));
    return loadScene((dir() / "scene.json").string());
  }
};

TEST_P(SceneGraph, SharedNodeAndTerrainCoincideInTheGraph) {
  test::writeBoxModel(dir() / "box.osgt", {0, 0, 0}, {2, 1, 0.5});  // 2 x 1 x 0.5 m, corner at the origin
  const Json eq = Json::array({{{"name", "ws1"}, {"model", weatherStation()}, {"position", at(20.3, 30.7)}, {"heading", 30}},
                               {{"name", "box"}, {"model", "box.osgt"}, {"position", at(10, 10)}, {"scale", 2}},
                               {{"name", "ws2"}, {"model", weatherStation()}, {"position", at(40.2, 8.9)}}});
  const Scene s = load(eq);
  ASSERT_EQ(s.models.size(), 2u);
  EXPECT_EQ(s.models[1].mesh.triangles.size(), 12u);
  SceneGraphOptions go;
  go.volumes = true;
  go.terrainCut.chunkCells = 16;  // 64 cells: 4 x 4 chunks at level 0
  go.terrainCut.maxErrorM = 0;    // a plane: every level is exact, so the cut is the coarsest
  SceneGraphParts parts;
  const osg::ref_ptr<osg::Group> root = buildSceneGraph(s, go, &parts);
  TransformFinder transforms;
  root->accept(transforms);
  for (const char* n : {"ws1", "ws2", "box"}) ASSERT_EQ(transforms.byName[n].size(), 1u) << n;
  osg::MatrixTransform* ws1 = transforms.byName["ws1"][0];
  osg::MatrixTransform* ws2 = transforms.byName["ws2"][0];
  ASSERT_EQ(ws1->getNumChildren(), 1u);
  EXPECT_EQ(ws1->getChild(0), ws2->getChild(0)) << "every instance of a model shares its node";
  ASSERT_EQ(parts.modelNodes.size(), 2u);
  EXPECT_EQ(ws1->getChild(0), parts.modelNodes[0].get());
  // The nodes, rebuilt from the scene's .osgb bytes, hold the geometry the scene measured.
  for (std::size_t k = 0; k < 2; ++k) {
    const TriangleMesh drawn = collectModelGeometry(*parts.modelNodes[k], s.models[k].path);
    EXPECT_EQ(drawn.vertices, s.models[k].mesh.vertices) << k;
    EXPECT_EQ(drawn.triangles, s.models[k].mesh.triangles) << k;
  }
  EXPECT_NE(transforms.byName["box"][0]->getChild(0), ws1->getChild(0));

  // Equipment: a model vertex through the graph's matrices lands at toMap(toLocal(v)); the
  // station's foot stands on the ground.
  for (std::size_t i = 0; i < 3; ++i) {
    osg::MatrixTransform* t = transforms.byName[s.spec.equipment[i].name][0];
    const osg::Matrixd world = osg::computeLocalToWorld(t->getParentalNodePaths()[0]);  // the path ends at t
    for (const auto& p : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.3, 1.1, 2.5)}) {
      const osg::Vec3d got = osg::Vec3d(p.x(), p.y(), p.z()) * world;
      const Eigen::Vector3d want = s.toMap(s.instances[i].toLocal.apply(p));
      EXPECT_NEAR(got.x(), want.x(), 1e-8);
      EXPECT_NEAR(got.y(), want.y(), 1e-8);
      EXPECT_NEAR(got.z(), want.z(), 1e-8);
    }
  }

  // Terrain: every vertex of the cut, through the graph, is a sample of the plane at its map
  // position (the mesh's frame is metres from sample (0, 0); the graph must place it), or a skirt's
  // bottom below it; and the triangles' areas seen from above add up to the grid's (skirts are
  // vertical): the cut covers the terrain once.
  osg::Group* localToMap = root->getChild(0)->asGroup();
  ASSERT_NE(localToMap, nullptr);
  osg::Node* terrainNode = childNamed(*localToMap, "terrain");
  ASSERT_NE(terrainNode, nullptr);
  GeometryFinder geometries;
  terrainNode->accept(geometries);
  EXPECT_GE(geometries.found.size(), 1u);
  EXPECT_EQ(parts.terrainCut.maxErrorM, 0.0);
  std::size_t checked = 0;
  double area = 0;
  for (const auto& [g, m] : geometries.found) {
    // accept() started at the terrain node (its matrix is in m): then the path above it (OSG
    // multiplies row vectors, so the parent's matrix comes last).
    const osg::Matrixd world = m * osg::computeLocalToWorld(localToMap->getParentalNodePaths()[0]);
    const auto* v = dynamic_cast<const osg::Vec3Array*>(g->getVertexArray());
    ASSERT_NE(v, nullptr);
    for (const osg::Vec3& p : *v) {
      const osg::Vec3d w = osg::Vec3d(p) * world;
      // On the sample grid to float rounding of the chunk vertices (< 1e-5 m over 64 m).
      const double c = (w.x() - terrain_.sampleX(0)) / terrain_.cell, r = (terrain_.sampleY(0) - w.y()) / terrain_.cell;
      ASSERT_NEAR(c, std::round(c), 1e-5);
      ASSERT_NEAR(r, std::round(r), 1e-5);
      const double plane = terrain_.height(w.x(), w.y());
      if (w.z() < plane - 1e-4) continue;  // a skirt's bottom
      ASSERT_NEAR(w.z(), plane, 1e-4);
      ++checked;
    }
    for (unsigned s = 0; s < g->getNumPrimitiveSets(); ++s) {
      const osg::PrimitiveSet* set = g->getPrimitiveSet(s);
      ASSERT_EQ(set->getMode(), GLenum(GL_TRIANGLES));
      for (unsigned t = 0; t + 2 < set->getNumIndices(); t += 3) {
        const osg::Vec3d a = (*v)[set->index(t)], b = (*v)[set->index(t + 1)], c = (*v)[set->index(t + 2)];
        area += 0.5 * std::abs((b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y()));
      }
    }
  }
  EXPECT_GE(checked, 4u);
  const double gridArea = double(terrain_.cols - 1) * double(terrain_.rows - 1) * terrain_.cell * terrain_.cell;
  EXPECT_NEAR(area, gridArea, 1e-6 * gridArea);

  // Volumes: one outer and one inner wireframe, 12 edges per unit each.
  osg::Node* volumes = childNamed(*localToMap, "volumes");
  ASSERT_NE(volumes, nullptr);
  GeometryFinder lines;
  volumes->accept(lines);
  ASSERT_EQ(lines.found.size(), 2u);
  for (const auto& [g, m] : lines.found) EXPECT_EQ(g->getVertexArray()->getNumElements(), 24u * s.units.size());

  // Without terrain and volumes: equipment only.
  go.terrain = false;
  go.volumes = false;
  const osg::ref_ptr<osg::Group> bare = buildSceneGraph(s, go);
  EXPECT_EQ(childNamed(*bare->getChild(0)->asGroup(), "terrain"), nullptr);
  EXPECT_EQ(childNamed(*bare->getChild(0)->asGroup(), "volumes"), nullptr);
  EXPECT_NE(childNamed(*bare->getChild(0)->asGroup(), "equipment"), nullptr);

  // Each graph has nodes of its own: graphs built from one scene may be drawn from two threads.
  SceneGraphParts other;
  buildSceneGraph(s, go, &other);
  ASSERT_EQ(other.modelNodes.size(), 2u);
  EXPECT_NE(other.modelNodes[0].get(), parts.modelNodes[0].get());
}

INSTANTIATE_TEST_SUITE_P(Places, SceneGraph, ::testing::ValuesIn(test::kTerrainPlaces),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace nestwalk
