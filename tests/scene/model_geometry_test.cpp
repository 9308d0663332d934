// Model loading: geometry built in memory with known vertices, transforms and primitive types,
// then collected; expected values are worked out by hand from the construction.
#include "nestwalk/core/input_error.h"
#include "nestwalk/scene/model_geometry.h"
#include "nestwalk/scene/node_geometry.h"

#include "tests/common/temp_folder.h"

#include <gtest/gtest.h>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/MatrixTransform>
#include <osgDB/WriteFile>

#include <algorithm>
#include <filesystem>
#include <set>

namespace nestwalk {
namespace {

osg::ref_ptr<osg::Geometry> quadGeometry(osg::PrimitiveSet* primitives, osg::Vec3Array* vertices) {
  osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
  g->setVertexArray(vertices);
  g->addPrimitiveSet(primitives);
  return g;
}

osg::DrawElementsUShort* elements(GLenum mode, std::initializer_list<unsigned short> indices) {
  auto* e = new osg::DrawElementsUShort(mode);
  for (unsigned short i : indices) e->push_back(i);
  return e;
}

osg::ref_ptr<osg::Vec3Array> unitSquarePlusUnused() {
  osg::ref_ptr<osg::Vec3Array> v = new osg::Vec3Array;
  v->push_back({0, 0, 0});
  v->push_back({1, 0, 0});
  v->push_back({1, 1, 0});
  v->push_back({0, 1, 0});
  v->push_back({100, 100, 100});  // referenced by no primitive: not part of the model
  return v;
}

std::set<std::array<double, 3>> asSet(const std::vector<Vec3<double>>& v) {
  std::set<std::array<double, 3>> s;
  for (const auto& p : v) s.insert({p.x(), p.y(), p.z()});
  return s;
}

TEST(ModelGeometry, QuadIsTwoTrianglesAndUnusedVerticesAreLeftOut) {
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->addDrawable(quadGeometry(new osg::DrawArrays(GL_QUADS, 0, 4), unitSquarePlusUnused()));
  const TriangleMesh m = collectModelGeometry(*geode, "quad");
  EXPECT_EQ(m.triangles.size(), 2u);
  EXPECT_EQ(asSet(m.vertices), (std::set<std::array<double, 3>>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}));
}

TEST(ModelGeometry, TransformsAreAppliedInDouble) {
  // Nested transforms: scale 2, then a translation to UTM magnitudes (which float would round).
  osg::ref_ptr<osg::MatrixTransform> outer = new osg::MatrixTransform(osg::Matrixd::translate(550000.125, 4650000.25, 0));
  osg::ref_ptr<osg::MatrixTransform> inner = new osg::MatrixTransform(osg::Matrixd::scale(2, 2, 2));
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->addDrawable(quadGeometry(new osg::DrawArrays(GL_TRIANGLE_FAN, 0, 4), unitSquarePlusUnused()));
  inner->addChild(geode);
  outer->addChild(inner);
  const TriangleMesh m = collectModelGeometry(*outer, "fan");
  EXPECT_EQ(m.triangles.size(), 2u);
  EXPECT_EQ(asSet(m.vertices), (std::set<std::array<double, 3>>{{550000.125, 4650000.25, 0},
                                                               {550002.125, 4650000.25, 0},
                                                               {550002.125, 4650002.25, 0},
                                                               {550000.125, 4650002.25, 0}}));
}

TEST(ModelGeometry, SharedSubgraphCountsOncePerPath) {
  // One geode under two transforms: an instanced part appears twice, at both places.
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->addDrawable(quadGeometry(elements(GL_TRIANGLES, {0, 1, 2}), unitSquarePlusUnused()));
  osg::ref_ptr<osg::Group> root = new osg::Group;
  for (double dz : {0.0, 5.0}) {
    osg::ref_ptr<osg::MatrixTransform> t = new osg::MatrixTransform(osg::Matrixd::translate(0, 0, dz));
    t->addChild(geode);
    root->addChild(t);
  }
  const TriangleMesh m = collectModelGeometry(*root, "instanced");
  EXPECT_EQ(m.triangles.size(), 2u);
  EXPECT_EQ(m.vertices.size(), 6u);
  for (const auto& t : m.triangles) {
    const double z = m.vertices[t[0]].z();
    EXPECT_TRUE(z == 0.0 || z == 5.0);
    EXPECT_EQ(m.vertices[t[1]].z(), z);
    EXPECT_EQ(m.vertices[t[2]].z(), z);
  }
}

TEST(ModelGeometry, PointsAndLinesGiveVerticesButNoTriangles) {
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->addDrawable(quadGeometry(new osg::DrawArrays(GL_POINTS, 0, 2), unitSquarePlusUnused()));
  geode->addDrawable(quadGeometry(new osg::DrawArrays(GL_LINES, 2, 2), unitSquarePlusUnused()));
  const TriangleMesh m = collectModelGeometry(*geode, "cloud");
  EXPECT_TRUE(m.triangles.empty());
  EXPECT_EQ(asSet(m.vertices), (std::set<std::array<double, 3>>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}));
}

TEST(ModelGeometry, DegenerateTrianglesAreDropped) {
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->addDrawable(quadGeometry(elements(GL_TRIANGLES, {0, 0, 1, 0, 1, 2}), unitSquarePlusUnused()));
  const TriangleMesh m = collectModelGeometry(*geode, "degenerate");
  EXPECT_EQ(m.triangles.size(), 1u);
}

TEST(ModelGeometry, APartialTriangleAtTheEndOfAnIndexListIsLeftOut) {
  // Five indices: one whole triangle and two left over (OSG's own functor reads past them).
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->addDrawable(quadGeometry(elements(GL_TRIANGLES, {0, 1, 2, 2, 3}), unitSquarePlusUnused()));
  const TriangleMesh m = collectModelGeometry(*geode, "partial");
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(asSet(m.vertices), (std::set<std::array<double, 3>>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}));
}

TEST(ModelGeometry, EmptyModelAndMissingFileAreInputErrors) {
  osg::ref_ptr<osg::Group> empty = new osg::Group;
  try {
    collectModelGeometry(*empty, "empty.osgt");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("empty.osgt: the model holds no vertices"), std::string::npos);
  }
  EXPECT_THROW(loadModelGeometry("/nonexistent/folder/model.osgb"), InputError);
}

TEST(ModelGeometry, RoundTripThroughAnOsgFile) {
  // Written with osgDB and read back: the loader sees what OSG's own reader returns.
  osg::ref_ptr<osg::MatrixTransform> t = new osg::MatrixTransform(osg::Matrixd::translate(1, 2, 3));
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->addDrawable(quadGeometry(new osg::DrawArrays(GL_QUADS, 0, 4), unitSquarePlusUnused()));
  t->addChild(geode);
  const test::TempFolder folder;
  const auto path = folder / "model.osgt";
  ASSERT_TRUE(osgDB::writeNodeFile(*t, path.string()));
  const TriangleMesh m = loadModelGeometry(path.string());
  EXPECT_EQ(m.triangles.size(), 2u);
  EXPECT_EQ(asSet(m.vertices), (std::set<std::array<double, 3>>{{1, 2, 3}, {2, 2, 3}, {2, 3, 3}, {1, 3, 3}}));
}

}  // namespace
}  // namespace nestwalk
