// The static terrain tiles as OSG nodes (render/terrain_tile_nodes.h): neighbouring tiles share
// bit-identical border vertices at every level, a level's geometry holds the mesh's triangles
// counter-clockwise from above with upward normals, and a tile's LOD switches at the mesh's own
// distances around the box of its samples.
#include "nestwalk/render/terrain_tile_nodes.h"

#include "tests/terrain/rough_heights.h"

#include <gtest/gtest.h>
#include <osg/Geode>

#include <cmath>
#include <numbers>
#include <set>
#include <tuple>
#include <vector>

namespace nestwalk {
namespace {

using namespace terrain;
using test::roughHeights;

TEST(TerrainTileNodes, NeighbouringTilesShareIdenticalBorderVertices) {
  const int cols = 129, rows = 129;
  const TerrainMesh m(TerrainGrid::fromHeights(cols, rows, roughHeights(cols, rows, 7), 0.7, 1.3),
                      TerrainMeshOptions{64, 0});
  auto positions = [&](const TerrainTile& t, int level) {
    std::set<std::tuple<float, float, float>> s;
    osg::ref_ptr<osg::Geometry> g = terrainTileGeometry(m, t, level);
    const auto* v = static_cast<const osg::Vec3Array*>(g->getVertexArray());
    for (const osg::Vec3& p : *v) s.insert({p.x(), p.y(), p.z()});
    return s;
  };
  for (int k = 0; k < 7; ++k) {
    SCOPED_TRACE(k);
    const auto a = positions(m.tile(0, 0), k), b = positions(m.tile(1, 0), k), c = positions(m.tile(0, 1), k);
    // The shared column (col 64) and row (row 64), every 2^k-th sample, are bit-identical.
    for (int i = 0; i <= 64; i += 1 << k) {
      const TerrainGrid& g = m.grid();
      const std::tuple<float, float, float> east{float(64 * g.dx), float(-i * g.dy), g.height(64, i)};
      EXPECT_TRUE(a.count(east) && b.count(east)) << "row " << i;
      const std::tuple<float, float, float> south{float(i * g.dx), float(-64 * g.dy), g.height(i, 64)};
      EXPECT_TRUE(a.count(south) && c.count(south)) << "col " << i;
    }
  }
}

TEST(TerrainTileNodes, GeometryAndLod) {
  const int cols = 129, rows = 129;
  const TerrainMesh m(TerrainGrid::fromHeights(cols, rows, roughHeights(cols, rows, 8, 0.01), 1.0, 1.0),
                      TerrainMeshOptions{64, 0});
  const TerrainTile& t = m.tile(1, 1);
  for (int k = 0; k < t.levels; ++k) {
    osg::ref_ptr<osg::Geometry> g = terrainTileGeometry(m, t, k);
    ASSERT_TRUE(g.valid());
    ASSERT_EQ(g->getNumPrimitiveSets(), 1u);
    const auto* e = dynamic_cast<const osg::DrawElementsUInt*>(g->getPrimitiveSet(0));
    ASSERT_NE(e, nullptr);
    EXPECT_EQ(e->size(), 3 * t.triangles[std::size_t(k)]);
    const auto* v = static_cast<const osg::Vec3Array*>(g->getVertexArray());
    const auto* n = static_cast<const osg::Vec3Array*>(g->getNormalArray());
    ASSERT_EQ(v->size(), n->size());
    for (const osg::Vec3& nn : *n) EXPECT_GT(nn.z(), 0.0f);
    // Counter-clockwise seen from above.
    for (std::size_t i = 0; i < e->size(); i += 3) {
      const osg::Vec3 a = (*v)[(*e)[i]], b = (*v)[(*e)[i + 1]], c = (*v)[(*e)[i + 2]];
      EXPECT_GT(((b - a) ^ (c - a)).z(), 0.0f);
    }
    ASSERT_NE(g->getColorArray(), nullptr);
  }
  const LodRule rule;
  EXPECT_NEAR(rule.pixelsPerRadian(), 720.0 / (2 * std::tan(std::numbers::pi / 6)), 1e-9);
  EXPECT_NEAR(rule.distanceFor(0.1), 62.35, 0.01);
  osg::ref_ptr<osg::LOD> lod = terrainTileLod(m, t, rule);
  ASSERT_EQ(lod->getNumChildren(), unsigned(t.levels));
  const std::vector<double> d = m.switchDistances(t, rule);
  EXPECT_EQ(lod->getMinRange(0), 0.0f);
  // The LOD's centre and radius: the box of the tile's samples, brute force.
  osg::BoundingBox box;
  for (int r = t.row0; r <= t.row0 + t.cellsY; ++r)
    for (int c = t.col0; c <= t.col0 + t.cellsX; ++c)
      if (m.grid().isValid(c, r)) box.expandBy(osg::Vec3(float(c), float(-r), m.grid().height(c, r)));
  EXPECT_EQ(lod->getCenter(), box.center());
  EXPECT_FLOAT_EQ(lod->getRadius(), 0.5f * (box._max - box._min).length());
  for (int k = 1; k < t.levels; ++k) {
    EXPECT_GE(d[std::size_t(k)], d[std::size_t(k) - 1]);
    EXPECT_EQ(lod->getMinRange(unsigned(k)), lod->getMaxRange(unsigned(k) - 1));
    if (t.maxError[std::size_t(k)] > 0) {
      EXPECT_GE(d[std::size_t(k)], rule.distanceFor(t.maxError[std::size_t(k)]));
    }
  }
}

}  // namespace
}  // namespace nestwalk
