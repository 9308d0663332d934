// Terrain meshes (terrain/terrain_mesh.h): level 0 is the heightfield's triangulation, the recorded
// per-level errors equal a brute-force computation, planes have no error, holes propagate to the
// coarse levels. (The tiles as OSG nodes: tests/render/terrain_tile_nodes_test.cpp.)
#include "nestwalk/terrain/terrain_mesh.h"
#include "nestwalk/terrain/heightfield.h"

#include "tests/terrain/rough_heights.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <set>
#include <tuple>
#include <vector>

namespace nestwalk::terrain {
namespace {

constexpr double kOriginX = 500000.0, kOriginY = 5200000.0;

using test::roughHeights;

/// The tile containing local (x, y) (the first one when on a shared border).
const TerrainTile* tileAt(const TerrainMesh& m, double x, double y) {
  const double fx = x / m.grid().dx, fy = -y / m.grid().dy;
  for (const TerrainTile& t : m.tiles())
    if (fx >= t.col0 && fx <= t.col0 + t.cellsX && fy >= t.row0 && fy <= t.row0 + t.cellsY) return &t;
  return nullptr;
}

TEST(TerrainMesh, TilesCoverTheGridAndShareBorders) {
  const int cols = 101, rows = 70;  // 100 x 69 cells: tiles of 32 leave narrower last tiles
  const TerrainMesh m(TerrainGrid::fromHeights(cols, rows, roughHeights(cols, rows, 1), 1.0, 1.0),
                      TerrainMeshOptions{32, 0});
  EXPECT_EQ(m.tilesX(), 4);
  EXPECT_EQ(m.tilesY(), 3);
  const TerrainTile& last = m.tile(3, 2);
  EXPECT_EQ(last.col0, 96);
  EXPECT_EQ(last.cellsX, 4);
  EXPECT_EQ(last.cellsY, 5);
  EXPECT_EQ(last.levels, 1);  // 5 cells: only the full resolution
  EXPECT_EQ(m.tile(0, 0).levels, 6);  // 32 cells: steps 1 .. 32
  EXPECT_EQ(m.tile(3, 0).levels, 3);  // 4 cells: steps 1, 2, 4
  std::size_t cells = 0;
  for (const TerrainTile& t : m.tiles()) cells += std::size_t(t.cellsX) * std::size_t(t.cellsY);
  EXPECT_EQ(cells, std::size_t(cols - 1) * std::size_t(rows - 1));
  ASSERT_EQ(m.levelTable().size(), 6u);
  EXPECT_EQ(m.levelTable()[0].triangles, 2 * cells);
  EXPECT_EQ(m.levelTable()[0].maxError, 0.0);
}

TEST(TerrainMesh, LevelZeroIsTheHeightfieldTriangulation) {
  const int cols = 53, rows = 41;
  const std::vector<float> h = roughHeights(cols, rows, 2, 0.05);
  const Heightfield hf(cols, rows, h, kOriginX, kOriginY, 2.0, 1.5);
  const TerrainMesh m(hf, TerrainMeshOptions{16, 0});
  // Every triangle of level 0, over all tiles, is a heightfield triangle with three valid samples,
  // and every such heightfield triangle appears exactly once.
  std::multiset<std::tuple<int, int, int>> got;  // (col, row, half) of the cell
  for (const TerrainTile& t : m.tiles())
    for (const GridTriangle& g : m.triangles(t, 0)) {
      const int c = g.col[0], r = g.row[0];
      const bool upper = g.col[1] == c + 1 && g.row[1] == r;
      if (upper) {
        EXPECT_TRUE(g.col[2] == c + 1 && g.row[2] == r + 1);
      } else {
        EXPECT_TRUE(g.col[1] == c + 1 && g.row[1] == r + 1 && g.col[2] == c && g.row[2] == r + 1);
      }
      got.insert({c, r, upper ? 0 : 1});
    }
  std::size_t expected = 0;
  for (int r = 0; r + 1 < rows; ++r)
    for (int c = 0; c + 1 < cols; ++c) {
      const bool upper = hf.valid(c, r) && hf.valid(c + 1, r) && hf.valid(c + 1, r + 1);
      const bool lower = hf.valid(c, r) && hf.valid(c + 1, r + 1) && hf.valid(c, r + 1);
      EXPECT_EQ(got.count({c, r, 0}), upper ? 1u : 0u) << c << "," << r;
      EXPECT_EQ(got.count({c, r, 1}), lower ? 1u : 0u) << c << "," << r;
      expected += (upper ? 1 : 0) + (lower ? 1 : 0);
    }
  EXPECT_EQ(got.size(), expected);
  EXPECT_EQ(m.levelTable()[0].triangles, expected);

  // The level-0 surface is the heightfield's: same heights at random points where both exist.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ux(0, (cols - 1) * 2.0), uy(-(rows - 1) * 1.5, 0);
  int compared = 0;
  for (int i = 0; i < 20000; ++i) {
    const double x = ux(rng), y = uy(rng);
    const TerrainTile* t = tileAt(m, x, y);
    ASSERT_NE(t, nullptr);
    const std::optional<double> mine = m.heightAt(*t, 0, x, y);
    const std::optional<double> ground = hf.groundHeight(kOriginX + x, kOriginY + y);
    if (mine) {
      ASSERT_TRUE(ground.has_value()) << x << "," << y;
      EXPECT_NEAR(*mine, *ground, 1e-6);
      ++compared;
    }
  }
  EXPECT_GT(compared, 10000);
}

TEST(TerrainMesh, RecordedErrorsEqualBruteForce) {
  for (const double holes : {0.0, 0.03}) {
    SCOPED_TRACE(holes);
    const int cols = 97, rows = 66;  // tiles of 32: full ones and narrower last ones
    const double dx = 1.25, dy = 0.75;
    const TerrainMesh m(TerrainGrid::fromHeights(cols, rows, roughHeights(cols, rows, 4, holes), dx, dy),
                        TerrainMeshOptions{32, 0});
    const TerrainGrid& g = m.grid();
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> unit(0, 1);
    std::size_t positiveLevels = 0;
    for (const TerrainTile& t : m.tiles())
      for (int k = 1; k < t.levels; ++k) {
        // The coarse surface at every fine sample of the tile, against the sample's height.
        double atSamples = 0;
        for (int r = t.row0; r <= t.row0 + t.cellsY; ++r)
          for (int c = t.col0; c <= t.col0 + t.cellsX; ++c) {
            if (!g.isValid(c, r)) continue;
            const std::optional<double> coarse = m.heightAt(t, k, c * dx, -r * dy);
            if (coarse) atSamples = std::max(atSamples, std::abs(double(g.height(c, r)) - *coarse));
          }
        EXPECT_DOUBLE_EQ(atSamples, t.maxError[std::size_t(k)]) << "tile " << t.col0 << "," << t.row0 << " level " << k;
        positiveLevels += atSamples > 0 ? 1 : 0;
        // Random points in the tile never exceed it.
        for (int i = 0; i < 2000; ++i) {
          const double x = (t.col0 + unit(rng) * t.cellsX) * dx, y = -(t.row0 + unit(rng) * t.cellsY) * dy;
          const std::optional<double> fine = m.heightAt(t, 0, x, y), coarse = m.heightAt(t, k, x, y);
          if (fine && coarse) {
            EXPECT_LE(std::abs(*fine - *coarse), t.maxError[std::size_t(k)] + 1e-9) << x << "," << y << " level " << k;
          }
        }
      }
    EXPECT_GT(positiveLevels, 10u);
    // The table's rows are the maxima over the tiles.
    for (const TerrainLevelStats& row : m.levelTable()) {
      double e = 0;
      for (const TerrainTile& t : m.tiles())
        if (row.level < t.levels) e = std::max(e, t.maxError[std::size_t(row.level)]);
      EXPECT_EQ(row.maxError, e);
    }
  }
}

TEST(TerrainMesh, PlanesHaveNoErrorAtAnyLevel) {
  const int cols = 129, rows = 65;
  // Integer heights: exact in float, and the coarse interpolation (steps 2^k) is exact in double.
  std::vector<float> exact(std::size_t(cols) * std::size_t(rows)), tilted(exact.size());
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      exact[std::size_t(r) * std::size_t(cols) + std::size_t(c)] = float(2 * c - 3 * r + 100);
      tilted[std::size_t(r) * std::size_t(cols) + std::size_t(c)] = float(812.37 + 0.173 * c * 2.5 + 0.291 * r * 2.5);
    }
  const TerrainMesh a(TerrainGrid::fromHeights(cols, rows, exact, 1.0, 1.0), TerrainMeshOptions{64, 0});
  ASSERT_EQ(a.levelTable().size(), 7u);
  for (const TerrainLevelStats& row : a.levelTable()) EXPECT_EQ(row.maxError, 0.0) << "level " << row.level;
  // A general plane: zero up to the float rounding of the stored heights.
  const TerrainMesh b(TerrainGrid::fromHeights(cols, rows, tilted, 2.5, 2.5), TerrainMeshOptions{64, 0});
  for (const TerrainLevelStats& row : b.levelTable()) EXPECT_LE(row.maxError, 1e-4) << "level " << row.level;
  // A plane's LOD shows the coarsest level from distance 0.
  const std::vector<double> d = a.switchDistances(a.tile(0, 0));
  for (double v : d) EXPECT_EQ(v, 0.0);
}

TEST(TerrainMesh, HolesPropagateToCoarseLevels) {
  const int cols = 65, rows = 65;
  std::vector<float> h = roughHeights(cols, rows, 6);
  const float noData = -9999.0f;
  h[32 * 65 + 32] = noData;  // a sample every level keeps (steps up to 32)
  h[10 * 65 + 17] = std::numeric_limits<float>::quiet_NaN();  // kept by level 0 only
  const TerrainMesh m(TerrainGrid::fromHeights(cols, rows, h, 1.0, 1.0, noData), TerrainMeshOptions{64, 0});
  const TerrainTile& t = m.tile(0, 0);
  ASSERT_EQ(t.levels, 7);
  for (int k = 0; k < t.levels; ++k) {
    const int s = 1 << k, n = 64 / s;
    std::size_t expected = 2 * std::size_t(n) * std::size_t(n);
    if (k < 6) expected -= 6;  // the six triangles around the interior sample (32, 32)
    // (level 6: one cell; (32, 32) is not one of its samples)
    if (k == 0) expected -= 6;  // and the six around (17, 10)
    EXPECT_EQ(t.triangles[std::size_t(k)], expected) << "level " << k;
    for (const GridTriangle& g : m.triangles(t, k))
      for (int v = 0; v < 3; ++v) EXPECT_FALSE(g.col[v] == 32 && g.row[v] == 32);
    if (k < 6) {
      // No ground around the hole at this level.
      EXPECT_FALSE(m.heightAt(t, k, 32 + 0.3 * s, -(32 + 0.1 * s)).has_value());
      EXPECT_FALSE(m.heightAt(t, k, 32 - 0.3 * s, -(32 - 0.1 * s)).has_value());
    }
  }
  // Level 6 has a single cell whose corners (0,0), (64,0), (64,64), (0,64) are all valid.
  EXPECT_TRUE(m.heightAt(t, 6, 32.0, -32.0).has_value());
  // The errors skip the holes (no NaN).
  for (const TerrainLevelStats& row : m.levelTable()) EXPECT_TRUE(std::isfinite(row.maxError));
}

}  // namespace
}  // namespace nestwalk::terrain
