// The scene graph written as glTF (render/gltf_scene_writer.h), read back by nestwalk's glTF reader
// (scene/gltf_model.h: a different program path, checked itself against hand-made files and assimp's
// copies) and checked by the Khronos validator. A hand-built graph: a textured quad with a material,
// coloured lines drawn unlit, and one strip geode shared by two transforms. Expected values come from
// the graph itself: its triangles collected from the OSG graph, its texture sampled at its own
// texture coordinates, its material's colour.
#include "nestwalk/render/gltf_scene_writer.h"
#include "nestwalk/scene/gltf_model.h"
#include "nestwalk/scene/node_geometry.h"
#include "tests/common/gltf_validator.h"
#include "tests/common/osg_geometries.h"
#include "tests/common/temp_folder.h"

#include <gtest/gtest.h>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/Material>
#include <osg/MatrixTransform>
#include <osg/NodeVisitor>
#include <osg/Texture2D>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <set>

namespace nestwalk {
namespace {

/// A triangle's corners, sorted and rounded to 0.1 mm.
using Corners = std::array<std::array<long, 3>, 3>;
std::multiset<Corners> trianglesOf(const TriangleMesh& m) {
  std::multiset<Corners> out;
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    Corners t;
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) t[c][k] = std::lround(m.vertices[m.triangles[i][c]][k] * 1e4);
    std::sort(t.begin(), t.end());
    out.insert(t);
  }
  return out;
}

/// An OSG array of the given elements (OSG 3.6's arrays take no initializer list).
template <class Array>
osg::ref_ptr<Array> arrayOf(std::initializer_list<typename Array::ElementDataType> elements) {
  osg::ref_ptr<Array> a = new Array;
  for (const auto& e : elements) a->push_back(e);
  return a;
}

struct TestGraph {
  osg::ref_ptr<osg::Group> root = new osg::Group;
  osg::ref_ptr<osg::Image> image = new osg::Image;
  osg::ref_ptr<osg::Vec2Array> uv = new osg::Vec2Array;
};

TestGraph makeGraph() {
  TestGraph t;
  // A textured quad, 2 x 1 m, at height 3, with a 4 x 2 RGBA texture (one texel half transparent,
  // so the image is written as PNG, losslessly).
  t.image->allocateImage(4, 2, 1, GL_RGBA, GL_UNSIGNED_BYTE);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) {
      unsigned char* p = t.image->data(x, y);
      p[0] = static_cast<unsigned char>(60 * x);
      p[1] = static_cast<unsigned char>(200 * y);
      p[2] = 77;
      p[3] = (x == 3 && y == 1) ? 128 : 255;
    }
  osg::ref_ptr<osg::Geometry> quad = new osg::Geometry;
  osg::ref_ptr<osg::Vec3Array> qv = arrayOf<osg::Vec3Array>({{0, 0, 3}, {2, 0, 3}, {2, 1, 3}, {0, 1, 3}});
  quad->setVertexArray(qv.get());
  t.uv = arrayOf<osg::Vec2Array>({{0.1f, 0.2f}, {0.9f, 0.2f}, {0.9f, 0.8f}, {0.1f, 0.8f}});
  quad->setTexCoordArray(0, t.uv.get(), osg::Array::BIND_PER_VERTEX);
  quad->addPrimitiveSet(new osg::DrawArrays(GL_QUADS, 0, 4));
  osg::ref_ptr<osg::Geode> quadGeode = new osg::Geode;
  quadGeode->addDrawable(quad.get());
  osg::StateSet* ss = quadGeode->getOrCreateStateSet();
  osg::ref_ptr<osg::Material> material = new osg::Material;
  material->setDiffuse(osg::Material::FRONT_AND_BACK, osg::Vec4(0.2f, 0.4f, 0.6f, 1.0f));
  ss->setAttributeAndModes(material.get());
  ss->setTextureAttributeAndModes(0, new osg::Texture2D(t.image.get()));
  t.root->addChild(quadGeode.get());

  // Lines with per-vertex colours, lighting off (wireframes).
  osg::ref_ptr<osg::Geometry> lines = new osg::Geometry;
  lines->setVertexArray(arrayOf<osg::Vec3Array>({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}));
  osg::ref_ptr<osg::Vec4ubArray> colours =
      arrayOf<osg::Vec4ubArray>({{255, 255, 0, 255}, {0, 255, 255, 255}, {255, 0, 0, 255}});
  colours->setNormalize(true);
  lines->setColorArray(colours.get(), osg::Array::BIND_PER_VERTEX);
  lines->addPrimitiveSet(new osg::DrawArrays(GL_LINE_STRIP, 0, 3));
  osg::ref_ptr<osg::Geode> lineGeode = new osg::Geode;
  lineGeode->addDrawable(lines.get());
  lineGeode->getOrCreateStateSet()->setMode(GL_LIGHTING, osg::StateAttribute::OFF);
  t.root->addChild(lineGeode.get());

  // A strip geode shared by two transforms (instances of one model).
  osg::ref_ptr<osg::Geometry> strip = new osg::Geometry;
  strip->setVertexArray(arrayOf<osg::Vec3Array>({{0, 0, 0}, {1, 0, 0}, {0, 1, 0.5}, {1, 1, 0.25}, {0, 2, 1}}));
  strip->setNormalArray(arrayOf<osg::Vec3Array>({{0, 0, 2}, {0, 0, 1}, {0, 0, 0}, {0, 1, 1}, {0, 0, 1}}),
                        osg::Array::BIND_PER_VERTEX);
  strip->addPrimitiveSet(new osg::DrawArrays(GL_TRIANGLE_STRIP, 0, 5));
  osg::ref_ptr<osg::Geode> shared = new osg::Geode;
  shared->addDrawable(strip.get());
  for (const osg::Matrixd& m : {osg::Matrixd::rotate(0.5, osg::Vec3d(0, 0, 1)) * osg::Matrixd::translate(10, 20, 1),
                                osg::Matrixd::scale(2, 2, 2) * osg::Matrixd::translate(-5, 3, 0)}) {
    osg::ref_ptr<osg::MatrixTransform> instance = new osg::MatrixTransform(m);
    instance->addChild(shared.get());
    t.root->addChild(instance.get());
  }
  return t;
}

/// The texel under a texture coordinate, as GL_NEAREST picks it (t counts from the first stored row).
osg::Vec4 texel(const osg::Image& image, const osg::Vec2& st) {
  const int x = std::clamp(int(std::floor(st.x() * image.s())), 0, image.s() - 1);
  const int y = std::clamp(int(std::floor(st.y() * image.t())), 0, image.t() - 1);
  return image.getColor(x, y);
}

/// A mesh read back from glTF (+y up) in the local frame it was written from (z up): (x, -z, y).
TriangleMesh toLocalFrame(TriangleMesh m) {
  for (Vec3<double>& v : m.vertices) v = Vec3<double>(v.x(), -v.z(), v.y());
  return m;
}

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(GltfSceneWriter, ReadsBackAsTheGraphItWasWrittenFrom) {
  TestGraph graph = makeGraph();
  const test::TempFolder dir;
  const std::string file = (dir / "graph.glb").string();
  GltfSceneInfo info;
  info.mapOrigin = {550000.5, 4650000.25, 12.0};
  info.crsName = "WGS 84 / UTM zone 51N";
  const GltfWriteStats stats = writeGltfScene(*graph.root, info, file, true);
  EXPECT_EQ(stats.triangles, 2u + 3u + 3u);  // the quad's two, the strip's three per instance
  EXPECT_EQ(stats.lineSegments, 2u);
  EXPECT_EQ(stats.images, 1u);
  EXPECT_EQ(stats.bytes, std::filesystem::file_size(file));

  // The Khronos validator: no error, no warning (zero normals are written as unit ones).
  const nlohmann::json report = test::validateGltf(file);
  ASSERT_FALSE(report.is_null());
  EXPECT_EQ(report["errors"], 0) << report.dump(1);
  EXPECT_EQ(report["warnings"], 0) << report.dump(1);

  // The structure: one mesh per geode, the shared one referred to by both instances; the map
  // origin and CRS in the asset's extras; the lines unlit.
  const nlohmann::json doc = test::glbJson(readAll(file));
  EXPECT_EQ(doc["meshes"].size(), 3u);
  std::map<int, int> uses;
  for (const auto& n : doc["nodes"])
    if (n.contains("mesh")) ++uses[n["mesh"].get<int>()];
  EXPECT_EQ(uses.size(), 3u);
  EXPECT_EQ(std::count_if(uses.begin(), uses.end(), [](const auto& u) { return u.second == 2; }), 1);
  EXPECT_EQ(doc["asset"]["extras"]["nestwalk"]["map_origin"], nlohmann::json({550000.5, 4650000.25, 12.0}));
  EXPECT_EQ(doc["asset"]["extras"]["nestwalk"]["crs_name"], "WGS 84 / UTM zone 51N");
  EXPECT_EQ(doc["extensionsUsed"], nlohmann::json({"KHR_materials_unlit"}));

  // Read back (in glTF's frame, +y up): the same triangles, in the local frame they came from.
  const GltfModel back = readGltfModel(file);
  ASSERT_TRUE(back.node) << back.problem;
  EXPECT_EQ(trianglesOf(toLocalFrame(collectModelGeometry(*back.node, file))),
            trianglesOf(collectModelGeometry(*graph.root, "graph")));
  EXPECT_EQ(back.notes, std::vector<std::string>{"meshes[1].primitives[0]: LINES skipped (nestwalk reads triangles)"});

  // The quad: its material's colour, and its texture showing the same texel at each corner.
  std::vector<const osg::Geometry*> g = test::geometriesUnder(*back.node);
  const auto quad = std::find_if(g.begin(), g.end(), [](const osg::Geometry* x) { return x->getTexCoordArray(0); });
  ASSERT_NE(quad, g.end());
  const auto* colour = dynamic_cast<const osg::Vec4Array*>((*quad)->getColorArray());
  ASSERT_TRUE(colour);
  EXPECT_EQ((*colour)[0], osg::Vec4(0.2f, 0.4f, 0.6f, 1.0f));
  const auto* texture =
      dynamic_cast<const osg::Texture2D*>((*quad)->getStateSet()->getTextureAttribute(0, osg::StateAttribute::TEXTURE));
  ASSERT_TRUE(texture && texture->getImage());
  const auto* uvBack = dynamic_cast<const osg::Vec2Array*>((*quad)->getTexCoordArray(0));
  const auto* vBack = dynamic_cast<const osg::Vec3Array*>((*quad)->getVertexArray());
  ASSERT_TRUE(uvBack && vBack);
  const auto* vOriginal = dynamic_cast<const osg::Vec3Array*>(test::geometriesUnder(*graph.root)[0]->getVertexArray());
  for (std::size_t i = 0; i < vBack->size(); ++i) {
    // The original vertex at the same place, and its texture coordinate.
    std::size_t j = 0;  // (a geometry's own vertices: the frame turn is the root node's)
    while (j < vOriginal->size() && ((*vOriginal)[j] - (*vBack)[i]).length() > 1e-6f) ++j;
    ASSERT_LT(j, vOriginal->size());
    const osg::Vec4 want = texel(*graph.image, (*graph.uv)[j]), got = texel(*texture->getImage(), (*uvBack)[i]);
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(got[k], want[k], 0.5 / 255) << "corner " << i << " channel " << k;
  }
}

TEST(GltfSceneWriter, TextFormHoldsTheSameScene) {
  TestGraph graph = makeGraph();
  const test::TempFolder dir;
  const std::string glb = (dir / "graph.glb").string(), gltf = (dir / "graph.gltf").string();
  writeGltfScene(*graph.root, {}, glb, true);
  writeGltfScene(*graph.root, {}, gltf, false);
  const nlohmann::json report = test::validateGltf(gltf);
  ASSERT_FALSE(report.is_null());
  EXPECT_EQ(report["errors"], 0) << report.dump(1);
  const GltfModel a = readGltfModel(glb), b = readGltfModel(gltf);
  ASSERT_TRUE(a.node && b.node) << a.problem << b.problem;
  EXPECT_EQ(trianglesOf(collectModelGeometry(*a.node, glb)), trianglesOf(collectModelGeometry(*b.node, gltf)));
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"graph.glb", "graph.gltf"}));
}

TEST(GltfSceneWriter, InstancedFormDrawsTheSameTriangles) {
  // The shared strip's two transforms become one node with EXT_mesh_gpu_instancing (two instances);
  // read back, every instance is drawn where its transform puts it.
  TestGraph graph = makeGraph();
  const test::TempFolder dir;
  const std::string plain = (dir / "plain.glb").string(), instanced = (dir / "instanced.glb").string();
  writeGltfScene(*graph.root, {}, plain, true);
  GltfSceneInfo info;
  info.instancing = true;
  const GltfWriteStats stats = writeGltfScene(*graph.root, info, instanced, true);
  EXPECT_EQ(stats.triangles, 2u + 3u + 3u);
  const nlohmann::json report = test::validateGltf(instanced);
  ASSERT_FALSE(report.is_null());
  EXPECT_EQ(report["errors"], 0) << report.dump(1);
  const nlohmann::json doc = test::glbJson(readAll(instanced));
  EXPECT_EQ(doc["extensionsRequired"], nlohmann::json({"EXT_mesh_gpu_instancing"}));
  int instancedNodes = 0;
  for (const auto& n : doc["nodes"])
    if (n.contains("extensions") && n["extensions"].contains("EXT_mesh_gpu_instancing")) {
      ++instancedNodes;
      const int translations = n["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["TRANSLATION"];
      EXPECT_EQ(doc["accessors"][translations]["count"], 2);
    }
  EXPECT_EQ(instancedNodes, 1);
  const GltfModel a = readGltfModel(plain), b = readGltfModel(instanced);
  ASSERT_TRUE(a.node && b.node) << a.problem << b.problem;
  EXPECT_EQ(trianglesOf(collectModelGeometry(*b.node, instanced)), trianglesOf(collectModelGeometry(*a.node, plain)));
}

}  // namespace
}  // namespace nestwalk
