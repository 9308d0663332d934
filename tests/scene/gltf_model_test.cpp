// glTF 2.0 models (scene/gltf_model.h) through the one door every model comes through
// (readModelFile, model_file.h: guarded, cached). The files are written here by a test builder
// (gltf_writer.h) and the expected values computed independently: node transforms with Eigen from
// the numbers written, triangulations of strips and fans by their definition, colours by hand,
// texture pixels from a PNG drawn with cairo (whose first row is the picture's top, as glTF's v = 0).
#include "nestwalk/core/input_error.h"
#include "nestwalk/scene/gltf_model.h"
#include "nestwalk/scene/model_catalog.h"
#include "nestwalk/scene/model_file.h"
#include "nestwalk/scene/model_geometry.h"
#include "nestwalk/scene/node_geometry.h"
#include "tests/common/osg_geometries.h"
#include "tests/common/temp_folder.h"
#include "tests/scene/gltf_writer.h"

#include <Eigen/Geometry>
#include <cairo.h>
#include <gtest/gtest.h>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/Material>
#include <osg/NodeVisitor>
#include <osg/Texture2D>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using test::GltfWriter;

constexpr int kFloat = 5126, kUByte = 5121, kUShort = 5123, kUInt = 5125;
constexpr double kFloatTolerance = 1e-5;  // metres: positions pass through float32 in the file

/// A triangle as its three corners, sorted, rounded to 1e-4 (orientation and start vertex aside).
using Corners = std::array<std::array<long, 3>, 3>;
Corners corners(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c) {
  Corners t;
  const Vec3<double> p[3] = {a, b, c};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) t[i][k] = std::lround(p[i][k] * 1e4);
  std::sort(t.begin(), t.end());
  return t;
}
std::multiset<Corners> trianglesOf(const TriangleMesh& m) {
  std::multiset<Corners> out;
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    const Triangle t = m.triangle(i);
    out.insert(corners(t[0], t[1], t[2]));
  }
  return out;
}

GltfWriter oneTriangle() {
  GltfWriter w;
  const int pos = w.addPositions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const int mesh = w.addMesh(Json::array({{{"attributes", {{"POSITION", pos}}}}}));
  w.setScene({w.addNode({{"mesh", mesh}})});
  return w;
}

TEST(GltfModel, NodeTransformsApplyDownTheTree) {
  GltfWriter w;
  const int pos = w.addPositions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const int mesh = w.addMesh(Json::array({{{"attributes", {{"POSITION", pos}}}}}));
  // The child: a matrix (column-major) that turns 90 degrees about x and moves by (1, 2, 3).
  const std::vector<double> childMatrix = {1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 1, 2, 3, 1};
  const int child = w.addNode({{"mesh", mesh}, {"matrix", childMatrix}});
  const double h = std::sqrt(0.5);
  const int parent = w.addNode({{"translation", {10, 20, 30}},
                                {"rotation", {0, 0, h, h}},
                                {"scale", {2, 3, 4}},
                                {"children", {child}},
                                {"mesh", mesh}});
  w.setScene({parent});
  const test::TempFolder dir;
  test::writeFile((dir / "tree.glb").string(), w.glb());

  Eigen::Affine3d parentT =
      Eigen::Translation3d(10, 20, 30) * Eigen::Quaterniond(h, 0, 0, h) * Eigen::Scaling(2.0, 3.0, 4.0);
  Eigen::Matrix4d childM = Eigen::Map<const Eigen::Matrix4d>(childMatrix.data());  // column-major, as glTF
  const Eigen::Vector3d tri[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  std::multiset<Corners> expected;
  for (const Eigen::Affine3d& m : {parentT, Eigen::Affine3d(parentT.matrix() * childM)})
    expected.insert(corners(m * tri[0], m * tri[1], m * tri[2]));

  const TriangleMesh got = loadModelGeometry((dir / "tree.glb").string());
  EXPECT_EQ(got.triangles.size(), 2u);
  EXPECT_EQ(trianglesOf(got), expected);
  // And within float precision, not only after rounding.
  for (const Vec3<double>& v : got.vertices) {
    double nearest = 1e9;
    for (const Eigen::Affine3d& m : {parentT, Eigen::Affine3d(parentT.matrix() * childM)})
      for (const Eigen::Vector3d& p : tri) nearest = std::min(nearest, (m * p - v).norm());
    EXPECT_LE(nearest, kFloatTolerance);
  }
}

TEST(GltfModel, IndexedStripsFansAndPlainTrianglesAllBecomeTriangles) {
  GltfWriter w;
  // Six points on a circle of radius 2 around (0, 0, 1), and a centre: the shared vertices.
  std::vector<float> xyz;
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i < 6; ++i) {
    const double a = i * M_PI / 3;
    p.emplace_back(2 * std::cos(a), 2 * std::sin(a), 1.0 + 0.25 * i);
  }
  p.emplace_back(0, 0, 1);
  for (const Eigen::Vector3d& v : p)
    for (int k = 0; k < 3; ++k) xyz.push_back(static_cast<float>(v[k]));
  const int pos = w.addPositions(xyz);
  const int u8 = w.addAccessor(std::vector<std::uint8_t>{0, 1, 6}, kUByte, "SCALAR", 3);
  const int u16 = w.addAccessor(std::vector<std::uint16_t>{1, 2, 6}, kUShort, "SCALAR", 3);
  const int u32 = w.addAccessor(std::vector<std::uint32_t>{2, 3, 6, 3, 4, 6}, kUInt, "SCALAR", 6);
  const int fan = w.addAccessor(std::vector<std::uint16_t>{6, 0, 1, 2, 3, 4, 5}, kUShort, "SCALAR", 7);
  const int line = w.addAccessor(std::vector<std::uint8_t>{0, 1}, kUByte, "SCALAR", 2);
  Json prims = Json::array();
  prims.push_back({{"attributes", {{"POSITION", pos}}}, {"indices", u8}});
  prims.push_back({{"attributes", {{"POSITION", pos}}}, {"indices", u16}, {"mode", 4}});
  prims.push_back({{"attributes", {{"POSITION", pos}}}, {"indices", u32}});
  prims.push_back({{"attributes", {{"POSITION", pos}}}, {"mode", 5}});  // strip over all 7 vertices
  prims.push_back({{"attributes", {{"POSITION", pos}}}, {"indices", fan}, {"mode", 6}});
  prims.push_back({{"attributes", {{"POSITION", pos}}}, {"indices", line}, {"mode", 1}});  // skipped
  w.setScene({w.addNode({{"mesh", w.addMesh(prims)}})});

  std::multiset<Corners> expected;
  auto add = [&](int a, int b, int c) { expected.insert(corners(p[a], p[b], p[c])); };
  add(0, 1, 6);
  add(1, 2, 6);
  add(2, 3, 6);
  add(3, 4, 6);
  for (int i = 0; i + 2 < 7; ++i) add(i, i + 1, i + 2);  // strip: every three consecutive vertices
  const int fanOrder[] = {6, 0, 1, 2, 3, 4, 5};
  for (int i = 1; i + 1 < 7; ++i) add(fanOrder[0], fanOrder[i], fanOrder[i + 1]);  // fan: the first and each pair

  const test::TempFolder dir;
  const std::string file = (dir / "modes.gltf").string();
  test::writeFile(file, w.gltfWithDataUri());
  testing::internal::CaptureStderr();
  const TriangleMesh got = loadModelGeometry(file);
  const std::string said = testing::internal::GetCapturedStderr();
  EXPECT_EQ(got.triangles.size(), 4u + 5u + 5u);
  EXPECT_EQ(trianglesOf(got), expected);
  EXPECT_NE(said.find(file + ": meshes[0].primitives[5]: LINES skipped"), std::string::npos) << said;
}

TEST(GltfModel, APartialTriangleIsDroppedWithANote) {
  GltfWriter w;
  const int pos = w.addPositions({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
  const int idx = w.addAccessor(std::vector<std::uint32_t>{0, 1, 2, 1, 3}, kUInt, "SCALAR", 5);
  w.setScene(
      {w.addNode({{"mesh", w.addMesh(Json::array({{{"attributes", {{"POSITION", pos}}}, {"indices", idx}}}))}})});
  const test::TempFolder dir;
  const std::string file = (dir / "partial.glb").string();
  test::writeFile(file, w.glb());
  testing::internal::CaptureStderr();
  const TriangleMesh got = loadModelGeometry(file);
  const std::string said = testing::internal::GetCapturedStderr();
  EXPECT_EQ(trianglesOf(got), std::multiset<Corners>{corners({0, 0, 0}, {1, 0, 0}, {0, 1, 0})});
  EXPECT_NE(said.find("meshes[0].primitives[0]: 5 indices, not whole triangles; the last 2 ignored"), std::string::npos)
      << said;
}

TEST(GltfModel, ExternalBufferAndEmbeddedFormsReadTheSame) {
  GltfWriter w = oneTriangle();
  const test::TempFolder dir;
  test::writeFile((dir / "a.glb").string(), w.glb());
  test::writeFile((dir / "b.gltf").string(), w.gltf("b%20data.bin"));  // a URI-encoded space
  test::writeFile((dir / "b data.bin").string(), w.bin);
  test::writeFile((dir / "c.gltf").string(), w.gltfWithDataUri());
  const std::multiset<Corners> expected = {corners({0, 0, 0}, {1, 0, 0}, {0, 1, 0})};
  for (const char* name : {"a.glb", "b.gltf", "c.gltf"}) {
    SCOPED_TRACE(name);
    EXPECT_EQ(trianglesOf(loadModelGeometry((dir / name).string())), expected);
  }
}

/// A 2x2 PNG drawn with cairo: top-left red, top-right green, bottom-left blue, bottom-right white.
std::string fourPixelPng(const fs::path& file) {
  cairo_surface_t* s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, 2, 2);
  unsigned char* data = cairo_image_surface_get_data(s);
  const int stride = cairo_image_surface_get_stride(s);
  const std::uint32_t px[2][2] = {{0xFF0000, 0x00FF00}, {0x0000FF, 0xFFFFFF}};  // rows from the top
  cairo_surface_flush(s);
  for (int y = 0; y < 2; ++y) std::memcpy(data + y * stride, px[y], sizeof(px[y]));
  cairo_surface_mark_dirty(s);
  cairo_surface_write_to_png(s, file.c_str());
  cairo_surface_destroy(s);
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(GltfModel, ColoursAndTexturesAreTheFilesOwn) {
  const test::TempFolder dir;
  const std::string png = fourPixelPng(dir / "four.png");
  GltfWriter w;
  const int pos = w.addPositions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const int colours =
      w.addAccessor(std::vector<std::uint8_t>{255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 51}, kUByte, "VEC4", 3, true);
  const int uv = w.addAccessor(std::vector<float>{0, 0, 1, 0, 0, 1}, kFloat, "VEC2", 3);
  w.doc["materials"] = Json::array({
      {{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 1.0, 1.0, 1.0}}}}},
      {{"pbrMetallicRoughness", {{"baseColorFactor", {0.25, 0.5, 0.75, 1.0}}, {"baseColorTexture", {{"index", 0}}}}}},
      {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 1}}}}}, {"alphaMode", "BLEND"}},
  });
  w.doc["images"] = Json::array({{{"uri", "four.png"}}, {{"uri", "data:image/png;base64," + test::base64(png)}}});
  w.doc["samplers"] = Json::array({{{"wrapS", 33071}, {"wrapT", 33648}}});
  w.doc["textures"] = Json::array({{{"source", 0}, {"sampler", 0}}, {{"source", 1}}});
  Json prims = Json::array();
  prims.push_back({{"attributes", {{"POSITION", pos}, {"COLOR_0", colours}}}, {"material", 0}});
  prims.push_back({{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}}}, {"material", 1}});
  prims.push_back({{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}}}, {"material", 2}});
  w.setScene({w.addNode({{"mesh", w.addMesh(prims)}})});
  const std::string file = (dir / "coloured.glb").string();
  test::writeFile(file, w.glb());

  const ModelFile read = readModelFile(file);
  ASSERT_TRUE(read.node) << read.problem;
  const std::vector<const osg::Geometry*> g = test::geometriesUnder(*read.node);
  ASSERT_EQ(g.size(), 3u);
  // Vertex colours times the base colour factor.
  const auto* c0 = dynamic_cast<const osg::Vec4Array*>(g[0]->getColorArray());
  ASSERT_TRUE(c0);
  ASSERT_EQ(c0->size(), 3u);
  EXPECT_EQ(g[0]->getColorArray()->getBinding(), osg::Array::BIND_PER_VERTEX);
  const osg::Vec4 want[3] = {{0.5f, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 0.2f}};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 4; ++k) EXPECT_NEAR((*c0)[i][k], want[i][k], 1e-6) << i << " " << k;
  // No vertex colours: the factor is the colour.
  const auto* c1 = dynamic_cast<const osg::Vec4Array*>(g[1]->getColorArray());
  ASSERT_TRUE(c1);
  EXPECT_EQ(g[1]->getColorArray()->getBinding(), osg::Array::BIND_OVERALL);
  EXPECT_EQ((*c1)[0], osg::Vec4(0.25f, 0.5f, 0.75f, 1.0f));
  // Both textures hold the PNG's pixels with its top row first (glTF's v = 0), with the sampler's
  // wrap modes (the default sampler repeats).
  for (int k : {1, 2}) {
    SCOPED_TRACE(k);
    const auto* t =
        dynamic_cast<const osg::Texture2D*>(g[k]->getStateSet()->getTextureAttribute(0, osg::StateAttribute::TEXTURE));
    ASSERT_TRUE(t);
    const osg::Image* image = t->getImage();
    ASSERT_TRUE(image);
    ASSERT_EQ(image->s(), 2);
    ASSERT_EQ(image->t(), 2);
    const std::array<unsigned, 3> rgb[2][2] = {{{255, 0, 0}, {0, 255, 0}}, {{0, 0, 255}, {255, 255, 255}}};
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x) {
        const osg::Vec4 c = image->getColor(x, y);
        for (int ch = 0; ch < 3; ++ch)
          EXPECT_NEAR(c[ch] * 255, rgb[y][x][ch], 0.5) << x << "," << y << " channel " << ch;
      }
    EXPECT_EQ(t->getWrap(osg::Texture::WRAP_S), k == 1 ? osg::Texture::CLAMP_TO_EDGE : osg::Texture::REPEAT);
    EXPECT_EQ(t->getWrap(osg::Texture::WRAP_T), k == 1 ? osg::Texture::MIRROR : osg::Texture::REPEAT);
    const auto* uvs = dynamic_cast<const osg::Vec2Array*>(g[k]->getTexCoordArray(0));
    ASSERT_TRUE(uvs);
    EXPECT_EQ((*uvs)[1], osg::Vec2(1, 0));
  }
  EXPECT_EQ(g[2]->getStateSet()->getRenderingHint(), osg::StateSet::TRANSPARENT_BIN);
}

TEST(GltfModel, CatalogDefaultsStandAGltfAssetUpright) {
  const std::map<std::string, ModelType> types = parseModelTypes(
      Json::parse(
          R"({"a": {"model": "m.glb"}, "b": {"model": "m.GLTF"}, "c": {"model": "m.glb", "up": "z", "forward": "+x"}})"),
      "catalog.json", "/models", "types");
  for (const char* name : {"a", "b"}) {
    const ModelType& t = types.at(name);
    EXPECT_EQ(t.up, ModelUp::Y) << name;
    EXPECT_EQ(t.forward, ModelForward::MinusY) << name;
    // glTF's +y (up) becomes z, its +z (the asset's front) becomes +y (forward, heading 0).
    const Mat3<double> r = modelTypeRotation(t);
    EXPECT_TRUE((r * Vec3<double>(0, 1, 0)).isApprox(Vec3<double>(0, 0, 1))) << name;
    EXPECT_TRUE((r * Vec3<double>(0, 0, 1)).isApprox(Vec3<double>(0, 1, 0))) << name;
    EXPECT_TRUE((r * Vec3<double>(1, 0, 0)).isApprox(Vec3<double>(-1, 0, 0))) << name;  // a right-handed turn
  }
  EXPECT_EQ(types.at("c").up, ModelUp::Z);
  EXPECT_EQ(types.at("c").forward, ModelForward::PlusX);
}

TEST(GltfModel, GuardedReadIsCachedAndTheSameAsTheDirectOne) {
  const test::TempFolder dir;
  const std::string file = (dir / "tri.glb").string();
  test::writeFile(file, oneTriangle().glb());
  const ModelFile first = readModelFile(file);
  ASSERT_TRUE(first.node) << first.problem;
  ASSERT_FALSE(first.osgb.empty());
  const ModelFile again = readModelFile(file);  // from the validated-model cache
  ASSERT_TRUE(again.node) << again.problem;
  EXPECT_EQ(again.osgb, first.osgb);
  const GltfModel direct = readGltfModel(file);
  ASSERT_TRUE(direct.node) << direct.problem;
  const TriangleMesh a = collectModelGeometry(*again.node, file), b = collectModelGeometry(*direct.node, file);
  EXPECT_EQ(trianglesOf(a), trianglesOf(b));
}

struct BadFile {
  const char* name;
  std::string bytes;
  std::string expected;  // part of the message
};

TEST(GltfModel, BadFilesAreRefusedNamingTheObject) {
  const test::TempFolder dir;
  std::vector<BadFile> cases;
  {
    std::string glb = oneTriangle().glb();
    const std::uint32_t tooLong = 1u << 30;
    std::memcpy(&glb[12], &tooLong, 4);  // the JSON chunk's length
    cases.push_back({"chunk.glb", glb, "the JSON chunk's length 1073741824 runs past the end of the file"});
  }
  {
    std::string glb = oneTriangle().glb();
    glb.resize(glb.size() - 8);  // cut short
    cases.push_back(
        {"cut.glb", glb, "the .glb header's length " + std::to_string(glb.size() + 8) + " is not the file's"});
  }
  {
    const std::string glb = oneTriangle().glb(1000);  // buffer 0 claims more than the BIN chunk holds
    cases.push_back({"buffer.glb", glb, "not a valid .glb file"});
  }
  {
    GltfWriter w = oneTriangle();
    w.doc["accessors"][0]["count"] = 4;
    cases.push_back(
        {"past.glb", w.glb(), "meshes[0].primitives[0]: POSITION: accessor 0 reads past the end of buffer view 0"});
  }
  {
    GltfWriter w = oneTriangle();
    w.doc["bufferViews"][0]["byteLength"] = 4000;
    cases.push_back(
        {"view.glb", w.glb(), "meshes[0].primitives[0]: POSITION: buffer view 0 reads past the end of buffer 0"});
  }
  {
    GltfWriter w = oneTriangle();
    w.doc["accessors"][0]["count"] = 2000000000;
    cases.push_back({"claim.glb", w.glb(), "the nodes instance more than 67108864 vertices"});
  }
  {
    GltfWriter w = oneTriangle();
    w.doc["meshes"][0]["primitives"][0]["indices"] =
        w.addAccessor(std::vector<std::uint8_t>{0, 1, 9}, kUByte, "SCALAR", 3);
    cases.push_back(
        {"index.glb", w.glb(), "meshes[0].primitives[0]: index 9 (element 2 of accessor 1) is past the 3 vertices"});
  }
  {
    GltfWriter w = oneTriangle();
    w.doc["nodes"][0]["children"] = {0};
    cases.push_back({"cycle.glb", w.glb(), "nodes[0]: has two parents, or is its own ancestor"});
  }
  {
    GltfWriter w = oneTriangle();
    w.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
    w.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    cases.push_back({"draco.glb", w.glb(), "extensionsRequired: KHR_draco_mesh_compression is not read by nestwalk"});
  }
  {
    GltfWriter w = oneTriangle();
    w.doc["materials"] = Json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
    w.doc["textures"] = Json::array({{{"source", 0}}});
    w.doc["images"] = Json::array({{{"uri", "missing.png"}}});
    w.doc["meshes"][0]["primitives"][0]["material"] = 0;
    cases.push_back({"image.glb", w.glb(), "images[0]: 'missing.png' could not be read"});
  }
  {
    GltfWriter w = oneTriangle();
    cases.push_back(
        {"base64.gltf", w.gltf("data:application/octet-stream;base64,@@not base64@@"), "not a valid glTF file"});
  }
  {
    GltfWriter w = oneTriangle();
    cases.push_back({"nobuffer.gltf", w.gltf("nowhere.bin"), "not a valid glTF file"});
  }
  cases.push_back({"text.gltf", "{\"asset\": {\"version\": \"2.0\"", "not a valid glTF file"});
  cases.push_back({"empty.glb", "", "not a valid glTF file"});

  for (const BadFile& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string file = (dir / c.name).string();
    test::writeFile(file, c.bytes);
    try {
      loadModelGeometry(file);
      ADD_FAILURE() << "read without complaint";
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(file + ": could not be read as a model (", 0), 0u) << message;
      EXPECT_NE(message.find(c.expected), std::string::npos) << message;
    }
  }
}

}  // namespace
}  // namespace nestwalk
