// Terrain chunks (terrain/terrain_chunk.h): the layout covers the grid once per level, level 0 is the
// heightfield's surface, the recorded errors and triangle counts equal a brute force over the fine
// samples on grids of square cells and bound a dense brute force on grids whose last cells are
// narrow, a level's surface is the same read through any chunk or the whole level, skirts close
// the gap to every neighbour up to three levels away and face outward, and the baked colours are a
// plane's Lambert shade and the imagery on the level's grid.
#include "nestwalk/terrain/terrain_chunk.h"
#include "nestwalk/terrain/heightfield.h"

#include <Eigen/Geometry>
#include "tests/terrain/rough_heights.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <optional>
#include <random>
#include <set>
#include <vector>

namespace nestwalk::terrain {
namespace {

constexpr double kOriginX = 500000.0, kOriginY = 5200000.0;  // UTM magnitudes

using test::roughHeights;

Heightfield roughField(int cols, int rows, unsigned seed, double holes = 0.0, double dx = 1.0, double dy = 1.0) {
  return Heightfield(cols, rows, roughHeights(cols, rows, seed, holes), kOriginX, kOriginY, dx, dy);
}

std::vector<ChunkKey> chunksOf(const ChunkLayout& l, int level) {
  std::vector<ChunkKey> v;
  for (int y = 0; y < l.chunksY(level); ++y)
    for (int x = 0; x < l.chunksX(level); ++x) v.push_back({level, x, y});
  return v;
}

/// The fine surface at mesh-frame (x, y).
std::optional<double> fineAt(const Heightfield& hf, double x, double y) {
  return hf.groundHeight(hf.origin().x() + x, hf.origin().y() + y);
}

/// The triangles (indices into ChunkMesh::indices / 3) of a quadrant's skirts, or of every quadrant's.
std::vector<std::size_t> skirtFaces(const ChunkMesh& m, int quadrant = -1) {
  std::vector<std::size_t> faces;
  for (int q = 0; q < 4; ++q) {
    if (quadrant >= 0 && q != quadrant) continue;
    const ChunkQuadrant& quad = m.quadrants[std::size_t(q)];
    for (std::size_t f = quad.firstIndex / 3 + quad.surfaceTriangles; f < (quad.firstIndex + quad.indexCount) / 3; ++f)
      faces.push_back(f);
    for (const ChunkSkirt& skirt : quad.midlineSkirts)
      for (std::size_t f = skirt.firstIndex / 3; f < (skirt.firstIndex + skirt.indexCount) / 3; ++f) faces.push_back(f);
  }
  return faces;
}

std::vector<std::size_t> surfaceFaces(const ChunkMesh& m) {
  std::vector<std::size_t> faces;
  for (const ChunkQuadrant& quad : m.quadrants)
    for (std::size_t f = quad.firstIndex / 3; f < quad.firstIndex / 3 + quad.surfaceTriangles; ++f) faces.push_back(f);
  return faces;
}

/// The fine sample range [c0, c1] x [r0, r1] of a chunk's quadrant (a + 2b): its child's cells.
struct PartRange {
  int c0, c1, r0, r1;
  bool empty() const { return c0 >= c1 || r0 >= r1; }
};
PartRange partRange(const ChunkLayout& l, const ChunkKey& k, int q) {
  const std::vector<int> cols = l.columns(k), rows = l.rowsOf(k);
  const std::size_t half = std::size_t(l.chunkCells() / 2);
  const int cm = half < cols.size() ? cols[half] : cols.back(), rm = half < rows.size() ? rows[half] : rows.back();
  return {(q & 1) ? cm : cols.front(), (q & 1) ? cols.back() : cm, (q >> 1) ? rm : rows.front(),
          (q >> 1) ? rows.back() : rm};
}

/// A chunk's grid by brute force, for layouts whose coarse cells are all square: its existing
/// triangles counted cell by cell, and its exact error as the largest |fine - coarse| over its fine
/// samples (square coarse cells follow fine edges, so the maximum lies at fine samples).
struct GridOracle {
  std::size_t triangles = 0;
  double maxError = 0;
};
GridOracle bruteForceGrid(const Heightfield& hf, const ChunkLayout& l, const ChunkKey& k) {
  const std::vector<int> cols = l.columns(k), rows = l.rowsOf(k);
  const int s = 1 << k.level;
  GridOracle o;
  for (std::size_t j = 0; j + 1 < rows.size(); ++j)
    for (std::size_t i = 0; i + 1 < cols.size(); ++i) {
      const int ca = cols[i], ra = rows[j];
      EXPECT_EQ(cols[i + 1] - ca, s);
      EXPECT_EQ(rows[j + 1] - ra, s);
      const bool upper = hf.valid(ca, ra) && hf.valid(ca + s, ra) && hf.valid(ca + s, ra + s);
      const bool lower = hf.valid(ca, ra) && hf.valid(ca + s, ra + s) && hf.valid(ca, ra + s);
      o.triangles += std::size_t(upper) + std::size_t(lower);
      const double ha = hf.sample(ca, ra), hb = hf.sample(ca + s, ra), hc = hf.sample(ca + s, ra + s),
                   hd = hf.sample(ca, ra + s);
      for (int v = 0; v <= s; ++v)
        for (int u = 0; u <= s; ++u) {
          if (!hf.valid(ca + u, ra + v)) continue;
          const double fu = double(u) / s, fv = double(v) / s;
          double coarse;
          if (u >= v && upper)
            coarse = ha + fu * (hb - ha) + fv * (hc - hb);
          else if (v >= u && lower)
            coarse = ha + fv * (hd - ha) + fu * (hc - hd);
          else
            continue;
          o.maxError = std::max(o.maxError, std::abs(double(hf.sample(ca + u, ra + v)) - coarse));
        }
    }
  return o;
}

TEST(ChunkLayout, EveryLevelCoversEachCellOnceAndChildrenTileTheirParent) {
  const ChunkLayout l(203, 150, 16);
  EXPECT_EQ(l.levels(), 5);  // 16 * 2^4 = 256 >= 202 cells > 128
  for (int level = 0; level < l.levels(); ++level) {
    std::vector<int> covered(std::size_t(202) * 149, 0);
    for (const ChunkKey& k : chunksOf(l, level)) {
      ASSERT_TRUE(l.exists(k));
      const std::vector<int> cols = l.columns(k), rows = l.rowsOf(k);
      EXPECT_LE(int(cols.size()), 17 + 1);
      for (std::size_t i = 0; i + 1 < cols.size(); ++i) EXPECT_LE(cols[i + 1] - cols[i], 1 << level);
      for (int r = rows.front(); r < rows.back(); ++r)
        for (int c = cols.front(); c < cols.back(); ++c) ++covered[std::size_t(r) * 202 + std::size_t(c)];
      if (level > 0) {
        int childCells = 0;
        for (const ChunkKey& ch : l.children(k)) {
          const std::vector<int> cc = l.columns(ch), cr = l.rowsOf(ch);
          EXPECT_GE(cc.front(), cols.front());
          EXPECT_LE(cc.back(), cols.back());
          EXPECT_GE(cr.front(), rows.front());
          EXPECT_LE(cr.back(), rows.back());
          childCells += (cc.back() - cc.front()) * (cr.back() - cr.front());
        }
        EXPECT_EQ(childCells, (cols.back() - cols.front()) * (rows.back() - rows.front()));
      }
    }
    EXPECT_TRUE(std::all_of(covered.begin(), covered.end(), [](int n) { return n == 1; })) << "level " << level;
  }
  EXPECT_FALSE(l.exists({0, 13, 0}));  // 13 * 16 = 208 > 202
  EXPECT_TRUE(l.exists({0, 12, 9}));
  EXPECT_EQ(l.root(), (ChunkKey{4, 0, 0}));
  EXPECT_THROW(ChunkLayout(10, 10, 12), std::invalid_argument);
}

TEST(TerrainChunk, LevelZeroIsTheHeightfieldSurface) {
  const Heightfield hf = roughField(70, 45, 3, 0.05);
  const ChunkLayout l(hf.cols(), hf.rows(), 16);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ux(0, 69), uy(-44, 0);
  int compared = 0;
  for (int i = 0; i < 20000; ++i) {
    const double x = ux(rng), y = uy(rng);
    const ChunkKey k{0, std::min(int(x / 16), 4), std::min(int(-y / 16), 2)};
    const std::optional<double> chunk = chunkHeightAt(hf, l, k, x, y);
    if (!chunk) continue;
    const std::optional<double> fine = fineAt(hf, x, y);
    ASSERT_TRUE(fine.has_value());
    // The heightfield is asked at map x, y near 5e5 / 5.2e6 m (positions rounded to ~1e-9 m), the
    // chunk in the mesh frame: on slopes of a few metres per metre they differ by ~1e-9 m.
    EXPECT_NEAR(*chunk, *fine, 1e-8);
    ++compared;
  }
  EXPECT_GT(compared, 15000);
  for (const ChunkKey& k : chunksOf(l, 0)) EXPECT_EQ(buildChunk(hf, l, k).maxError, 0.0);
}

TEST(TerrainChunk, ErrorsAndTrianglesEqualABruteForceOverTheFineSamples) {
  // 129 x 129 samples in chunks of 16 cells: every coarse cell of every level is square.
  for (double holes : {0.0, 0.03}) {
    const Heightfield hf = roughField(129, 129, 11, holes, 1.5, 0.75);
    const ChunkLayout l(hf.cols(), hf.rows(), 16);
    ASSERT_EQ(l.levels(), 4);
    const std::vector<ChunkLevelStats> table = chunkLevelTable(hf, l);
    ASSERT_EQ(table.size(), 4u);
    for (int level = 0; level < l.levels(); ++level) {
      ChunkLevelStats expected{level, 1 << level};
      for (const ChunkKey& k : chunksOf(l, level)) {
        const GridOracle o = bruteForceGrid(hf, l, k);
        const ChunkMesh m = buildChunk(hf, l, k);
        EXPECT_NEAR(m.maxError, o.maxError, 1e-12) << level << " " << k.x << " " << k.y;
        EXPECT_EQ(m.surfaceTriangles, o.triangles);
        expected.chunks += o.triangles > 0;
        expected.triangles += o.triangles;
        expected.maxError = std::max(expected.maxError, o.maxError);
      }
      const ChunkLevelStats& row = table[std::size_t(level)];
      EXPECT_EQ(row.level, level);
      EXPECT_EQ(row.step, 1 << level);
      EXPECT_EQ(row.chunks, expected.chunks);
      EXPECT_EQ(row.triangles, expected.triangles);
      EXPECT_NEAR(row.maxError, expected.maxError, 1e-12);
    }
  }
}

TEST(TerrainChunk, ALevelReadsTheSameThroughAnyChunkOrTheWholeLevel) {
  // levelHeightAt against chunkHeightAt of the chunk holding the point, on a grid with holes and
  // narrow last cells, at every level.
  const Heightfield hf = roughField(78, 54, 23, 0.03, 1.0, 2.0);
  const ChunkLayout l(hf.cols(), hf.rows(), 8);
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> ux(0, 77 * 1.0), uy(-53 * 2.0, 0);
  for (int level = 0; level < l.levels(); ++level) {
    const int side = 8 << level;
    int both = 0;
    for (int i = 0; i < 4000; ++i) {
      const double x = ux(rng), y = uy(rng);
      const ChunkKey k{level, std::min(int(x / hf.dx()) / side, l.chunksX(level) - 1),
                       std::min(int(-y / hf.dy()) / side, l.chunksY(level) - 1)};
      const std::optional<double> chunk = chunkHeightAt(hf, l, k, x, y), whole = levelHeightAt(hf, level, x, y);
      ASSERT_EQ(chunk.has_value(), whole.has_value()) << level << " " << x << " " << y;
      if (!chunk) continue;
      EXPECT_EQ(*chunk, *whole);
      ++both;
    }
    EXPECT_GT(both, 3000) << "level " << level;
  }
  EXPECT_FALSE(levelHeightAt(hf, 0, -0.5, -1.0).has_value());
  EXPECT_FALSE(levelHeightAt(hf, 0, 10.0, 1.0).has_value());
}

TEST(TerrainChunk, ErrorsAreExactOnADegreeGrid) {
  // A geographic DEM (one arc-second, longitude and latitude in degrees, heights in metres) builds
  // the same chunks: its tiny spacing changes nothing of the errors or the triangles.
  const double arcSecond = 1.0 / 3600.0;
  const Heightfield hf(129, 129, roughHeights(129, 129, 37, 0.02), -121.76, 46.85, arcSecond, arcSecond);
  const ChunkLayout l(hf.cols(), hf.rows(), 32);
  for (int level = 0; level < l.levels(); ++level) {
    for (const ChunkKey& k : chunksOf(l, level)) {
      const ChunkMesh m = buildChunk(hf, l, k);
      const GridOracle o = bruteForceGrid(hf, l, k);
      EXPECT_NEAR(m.maxError, o.maxError, 1e-12);
      EXPECT_EQ(m.surfaceTriangles, o.triangles);
      // Vertices relative to the chunk's first sample: the largest is the chunk's own size.
      for (std::size_t v = 0; v < m.surfaceVertices; ++v) {
        EXPECT_LE(std::abs(m.positions[3 * v]), (32 << level) * arcSecond * (1 + 1e-6));
        EXPECT_LE(std::abs(m.positions[3 * v + 1]), (32 << level) * arcSecond * (1 + 1e-6));
      }
    }
  }
}

TEST(TerrainChunk, ErrorIsTheExactMaximumOnNarrowLastCells) {
  // 78 x 54 samples: 77 and 53 cells, so every coarse level ends in narrower cells.
  const Heightfield hf = roughField(78, 54, 17, 0.02, 1.0, 2.0);
  const ChunkLayout l(hf.cols(), hf.rows(), 8);
  for (int level = 1; level < l.levels(); ++level)
    for (const ChunkKey& k : chunksOf(l, level)) {
      const ChunkMesh m = buildChunk(hf, l, k);
      const std::vector<int> cols = l.columns(k), rows = l.rowsOf(k);
      double lattice = 0, diagonals = 0;
      auto diff = [&](double fc, double fr) -> double {
        const double x = fc * hf.dx(), y = -fr * hf.dy();
        const std::optional<double> a = chunkHeightAt(hf, l, k, x, y), b = fineAt(hf, x, y);
        return a && b ? std::abs(*a - *b) : 0.0;
      };
      constexpr int kSub = 8;  // lattice points per fine cell side
      for (int fr = rows.front() * kSub; fr <= rows.back() * kSub; ++fr)
        for (int fc = cols.front() * kSub; fc <= cols.back() * kSub; ++fc)
          lattice = std::max(lattice, diff(double(fc) / kSub, double(fr) / kSub));
      // Along every coarse diagonal at t = n / (w h |w - h|): all its crossings with fine edges.
      for (std::size_t j = 0; j + 1 < rows.size(); ++j)
        for (std::size_t i = 0; i + 1 < cols.size(); ++i) {
          const int w = cols[i + 1] - cols[i], h = rows[j + 1] - rows[j];
          const int n = w * h * std::max(1, std::abs(w - h));
          for (int t = 0; t <= n; ++t)
            diagonals = std::max(diagonals, diff(cols[i] + double(t) * w / n, rows[j] + double(t) * h / n));
        }
      EXPECT_LE(lattice, m.maxError + 1e-9) << "level " << level << " chunk " << k.x << " " << k.y;
      EXPECT_NEAR(m.maxError, std::max(lattice, diagonals), 1e-9) << "level " << level << " chunk " << k.x << " " << k.y;
    }
}

TEST(TerrainChunk, BlocksHoldEveryPointWithItsError) {
  // Every point of a quadrant's coarse surface lies in one of its blocks' boxes whose error is at
  // least its own: the renderer's projected-error bound (terrain_chunk.h, "Blocks").
  const Heightfield hf = roughField(78, 54, 41, 0.02, 1.0, 2.0);
  const ChunkLayout l(hf.cols(), hf.rows(), 16);
  std::mt19937 rng(43);
  std::size_t points = 0;
  for (int level = 0; level < l.levels(); ++level)
    for (const ChunkKey& k : chunksOf(l, level)) {
      const ChunkMesh m = buildChunk(hf, l, k);
      double quadrantsMax = 0;
      for (int q = 0; q < 4; ++q) {
        const ChunkQuadrant& quad = m.quadrants[std::size_t(q)];
        quadrantsMax = std::max(quadrantsMax, quad.maxError);
        const PartRange part = partRange(l, k, q);
        if (part.empty()) {
          EXPECT_TRUE(quad.empty());
          continue;
        }
        std::uniform_real_distribution<double> uc(part.c0, part.c1), ur(part.r0, part.r1);
        for (int i = 0; i < 1000; ++i) {
          const double fc = uc(rng), fr = ur(rng), x = fc * hf.dx(), y = -fr * hf.dy();
          const std::optional<double> coarse = chunkHeightAt(hf, l, k, x, y), fine = fineAt(hf, x, y);
          if (!coarse || !fine) continue;
          const double e = std::abs(*coarse - *fine);
          const Eigen::Vector3d p(x, y, *coarse);
          const bool held = std::any_of(quad.blocks.begin(), quad.blocks.end(), [&](const ChunkBlock& b) {
            return (p.array() >= b.min.array() - 1e-9).all() && (p.array() <= b.max.array() + 1e-9).all() &&
                   b.error >= e - 1e-8;
          });
          EXPECT_TRUE(held) << "level " << level << " quadrant " << q << " point " << fc << " " << fr << " error " << e;
          ++points;
        }
      }
      EXPECT_EQ(quadrantsMax, m.maxError);
    }
  EXPECT_GT(points, 30000u);
}

/// The vertical interval a chunk's skirt covers at position t along a grid line (the line x = line
/// when alongRow is false, y = line otherwise; mesh frame), from its skirt triangles in that plane.
struct Cover {
  double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
};
Cover skirtCover(const ChunkMesh& m, int quadrant, bool alongRow, double line, double t) {
  Cover c;
  for (std::size_t f : skirtFaces(m, quadrant)) {
    double s[3], z[3];
    bool inPlane = true;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = m.indices[3 * f + std::size_t(k)];
      const double x = m.positions[3 * v] + m.offset.x(), y = m.positions[3 * v + 1] + m.offset.y();
      z[k] = m.positions[3 * v + 2] + m.offset.z();
      s[k] = alongRow ? x : y;
      if (std::abs((alongRow ? y : x) - line) > 1e-6) inPlane = false;
    }
    if (!inPlane) continue;
    // The triangle in the (s, z) plane cut by s = t: the z range of its edges there.
    for (int a = 0; a < 3; ++a) {
      const int b = (a + 1) % 3;
      const double s0 = std::min(s[a], s[b]), s1 = std::max(s[a], s[b]);
      if (t < s0 - 1e-9 || t > s1 + 1e-9) continue;
      const double zt = s1 - s0 < 1e-12 ? std::min(z[a], z[b]) : z[a] + (z[b] - z[a]) * (t - s[a]) / (s[b] - s[a]);
      const double zt2 = s1 - s0 < 1e-12 ? std::max(z[a], z[b]) : zt;
      c.lo = std::min(c.lo, std::min(zt, zt2));
      c.hi = std::max(c.hi, std::max(zt, zt2));
    }
  }
  return c;
}

TEST(TerrainChunk, SkirtsCloseTheGapToNeighboursUpToThreeLevelsAway) {
  // Any two quadrants (of any chunks) up to three levels apart that share a stretch of grid line:
  // the higher edge's skirt reaches the lower edge all along it.
  const Heightfield hf = roughField(129, 129, 23, 0.0, 1.0, 1.0);
  const ChunkLayout l(hf.cols(), hf.rows(), 8);
  ASSERT_EQ(l.levels(), 5);
  struct Part {
    ChunkKey key;
    int quadrant;
    PartRange range;
    const ChunkMesh* mesh;
  };
  std::vector<ChunkMesh> meshes;
  for (int level = 0; level < l.levels(); ++level)
    for (const ChunkKey& k : chunksOf(l, level)) meshes.push_back(buildChunk(hf, l, k));
  std::vector<Part> parts;
  for (const ChunkMesh& m : meshes)
    for (int q = 0; q < 4; ++q)
      if (!partRange(l, m.key, q).empty()) parts.push_back({m.key, q, partRange(l, m.key, q), &m});
  std::size_t checked = 0, gaps = 0;
  for (const Part& pa : parts)
    for (const Part& pb : parts) {
      if (std::abs(pa.key.level - pb.key.level) > 3) continue;
      // pb east of pa, sharing the column pa.c1; or south of it, sharing the row pa.r1.
      for (bool alongRow : {false, true}) {
        const bool touches = alongRow ? pb.range.r0 == pa.range.r1 : pb.range.c0 == pa.range.c1;
        if (!touches) continue;
        const int from = alongRow ? std::max(pa.range.c0, pb.range.c0) : std::max(pa.range.r0, pb.range.r0);
        const int to = alongRow ? std::min(pa.range.c1, pb.range.c1) : std::min(pa.range.r1, pb.range.r1);
        if (from >= to) continue;
        const double line = alongRow ? -pa.range.r1 * hf.dy() : pa.range.c1 * hf.dx();
        for (int q = from * 4; q <= to * 4; ++q) {
          const double t = alongRow ? q / 4.0 * hf.dx() : -q / 4.0 * hf.dy();
          const double x = alongRow ? t : line, y = alongRow ? line : t;
          const std::optional<double> ha = chunkHeightAt(hf, l, pa.key, x, y), hb = chunkHeightAt(hf, l, pb.key, x, y);
          ASSERT_TRUE(ha && hb);
          const bool aHigher = *ha >= *hb;
          const Part& higher = aHigher ? pa : pb;
          const Cover c = skirtCover(*higher.mesh, higher.quadrant, alongRow, line, t);
          const double low = std::min(*ha, *hb), high = std::max(*ha, *hb);
          ++checked;
          // Float vertices: 1e-4 m is far below a pixel and above their rounding at 100 m.
          if (!(c.lo <= low + 1e-4 && c.hi >= high - 1e-4)) ++gaps;
        }
      }
    }
  EXPECT_GT(checked, 50000u);
  EXPECT_EQ(gaps, 0u);
}

TEST(TerrainChunk, AQuadrantsSkirtsOnItsChunksMidlinesAreRangesOfTheirOwn) {
  // Holes, and a last column and row of narrower cells: midlines of every kind.
  const Heightfield hf = roughField(100, 70, 31, 0.02);
  const ChunkLayout l(hf.cols(), hf.rows(), 16);
  std::size_t onMidlines = 0, onEdges = 0;
  for (int level = 0; level < l.levels(); ++level)
    for (const ChunkKey& k : chunksOf(l, level)) {
      const ChunkMesh m = buildChunk(hf, l, k);
      std::size_t midlineTriangles = 0;
      for (int quadrant = 0; quadrant < 4; ++quadrant) {
        const PartRange part = partRange(l, k, quadrant);
        if (part.empty()) continue;
        const ChunkQuadrant& quad = m.quadrants[std::size_t(quadrant)];
        // The midlines: the quadrant's east or west column, its south or north row.
        const double midX = ((quadrant & 1) ? part.c0 : part.c1) * hf.dx();
        const double midY = -((quadrant >> 1) ? part.r0 : part.r1) * hf.dy();
        auto allOn = [&](std::size_t f, int axis, double at) {
          for (int i = 0; i < 3; ++i) {
            const std::uint32_t v = m.indices[3 * f + std::size_t(i)];
            if (std::abs(m.positions[3 * v + std::size_t(axis)] + m.offset[axis] - at) > 1e-6) return false;
          }
          return true;
        };
        // Its range's skirts: none on a midline.
        for (std::size_t f = quad.firstIndex / 3 + quad.surfaceTriangles; f < (quad.firstIndex + quad.indexCount) / 3; ++f) {
          EXPECT_FALSE(allOn(f, 0, midX) || allOn(f, 1, midY)) << k.level << " " << k.x << " " << k.y << " " << quadrant;
          ++onEdges;
        }
        // Each midline range: all on its midline, [0] the vertical one, [1] the horizontal.
        for (std::size_t j = 0; j < 2; ++j) {
          const ChunkSkirt& skirt = quad.midlineSkirts[j];
          EXPECT_EQ(skirt.indexCount % 3, 0u);
          for (std::size_t f = skirt.firstIndex / 3; f < (skirt.firstIndex + skirt.indexCount) / 3; ++f) {
            EXPECT_TRUE(j == 0 ? allOn(f, 0, midX) : allOn(f, 1, midY)) << k.level << " " << quadrant << " " << j;
            ++onMidlines;
          }
          midlineTriangles += skirt.indexCount / 3;
        }
      }
      EXPECT_EQ(m.midlineSkirtTriangles, midlineTriangles);
    }
  // Both kinds are many: the midlines carry about as many skirts as the chunks' own edges.
  EXPECT_GT(onMidlines, 1000u);
  EXPECT_GT(onEdges, 1000u);
}

TEST(TerrainChunk, SkirtsFaceOutwardAndOnlyInsideTheGrid) {
  const Heightfield hf = roughField(100, 70, 29, 0.02);
  const ChunkLayout l(hf.cols(), hf.rows(), 16);
  for (int level = 0; level < l.levels(); ++level)
    for (const ChunkKey& k : chunksOf(l, level)) {
      const ChunkMesh m = buildChunk(hf, l, k);
      for (int quadrant = 0; quadrant < 4; ++quadrant) {
      const PartRange part = partRange(l, k, quadrant);
      // Outward: away from the quadrant's centre (its skirts on the chunk's midlines too).
      const Eigen::Vector3d centre(0.5 * (part.c0 + part.c1) * hf.dx(), -0.5 * (part.r0 + part.r1) * hf.dy(), 0);
      for (std::size_t f : skirtFaces(m, quadrant)) {
        Eigen::Vector3d p[3];
        for (int i = 0; i < 3; ++i) {
          const std::uint32_t v = m.indices[3 * f + std::size_t(i)];
          p[i] = Eigen::Vector3d(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]) + m.offset;
        }
        const Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
        const Eigen::Vector3d out = (p[0] + p[1] + p[2]) / 3 - centre;
        EXPECT_GT(n.x() * out.x() + n.y() * out.y(), 0.0);
        EXPECT_NEAR(n.z(), 0.0, 1e-6 * n.norm());  // vertical walls
        // Never a wall on the grid's outer edges (x = 0, x = 99, y = 0, y = -69 m).
        const bool onWest = p[0].x() == 0 && p[1].x() == 0 && p[2].x() == 0;
        const bool onEast = p[0].x() == 99 && p[1].x() == 99 && p[2].x() == 99;
        const bool onNorth = p[0].y() == 0 && p[1].y() == 0 && p[2].y() == 0;
        const bool onSouth = p[0].y() == -69 && p[1].y() == -69 && p[2].y() == -69;
        EXPECT_FALSE(onWest || onEast || onNorth || onSouth);
      }
      }
      // Surface triangles face up (counter-clockwise seen from above).
      for (std::size_t f : surfaceFaces(m)) {
        Eigen::Vector3d p[3];
        for (int i = 0; i < 3; ++i) {
          const std::uint32_t v = m.indices[3 * f + std::size_t(i)];
          p[i] = Eigen::Vector3d(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]);
        }
        EXPECT_GT((p[1] - p[0]).cross(p[2] - p[0]).z(), 0.0);
      }
    }
}

TEST(TerrainChunk, SkirtSpansAreTheirSegmentsPlusOneTrianglesAndNeverRiseAboveTheEdge) {
  // Skirts hang in spans of kSkirtSpanSegments segments (terrain_chunk.h, "Cracks"). Without holes,
  // every quadrant edge inside the grid of 64-cell chunks has 32 segments: 4 spans of 9 triangles.
  // With holes or without, a skirt triangle lies at or below the chunk's surface along its line
  // (chunkHeightAt, the edge's polyline), within the positions' float rounding, at 17 points across
  // it (every vertex of the edge under it where it spans 1, 2, 4 or 8 segments).
  constexpr double kFloatSlackM = 1e-4;  // positions are floats relative to the chunk's first sample
  for (const double holes : {0.0, 0.01}) {
    const Heightfield hf = roughField(257, 257, 37, holes);
    const ChunkLayout l(hf.cols(), hf.rows(), 64);
    ASSERT_EQ(l.levels(), 3);
    std::size_t checked = 0;
    for (int level = 0; level < l.levels(); ++level)
      for (const ChunkKey& k : chunksOf(l, level)) {
        const ChunkMesh m = buildChunk(hf, l, k);
        for (int quadrant = 0; quadrant < 4; ++quadrant) {
          const PartRange part = partRange(l, k, quadrant);
          const ChunkQuadrant& quad = m.quadrants[std::size_t(quadrant)];
          if (holes == 0.0) {
            const int inside = int(part.c0 > 0) + int(part.c1 < hf.cols() - 1) + int(part.r0 > 0) + int(part.r1 < hf.rows() - 1);
            const std::size_t perEdge = 32 + 32 / kSkirtSpanSegments;
            std::size_t midline = 0;
            for (const ChunkSkirt& skirt : quad.midlineSkirts) midline += skirt.indexCount / 3;
            // The chunk's own edges inside the grid, then its two midlines (always inside).
            const int midlines = 2;
            EXPECT_EQ(quad.skirtTriangles + midline, std::size_t(inside) * perEdge)
                << k.level << "/" << k.x << "/" << k.y << " quadrant " << quadrant;
            EXPECT_EQ(midline, midlines * perEdge) << k.level << "/" << k.x << "/" << k.y << " quadrant " << quadrant;
          }
          for (std::size_t f : skirtFaces(m, quadrant)) {
            Eigen::Vector3d p[3];
            for (int i = 0; i < 3; ++i) {
              const std::uint32_t v = m.indices[3 * f + std::size_t(i)];
              p[i] = Eigen::Vector3d(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]) + m.offset;
            }
            const bool alongRow = p[0].y() == p[1].y() && p[1].y() == p[2].y();  // else along a column
            const int axis = alongRow ? 0 : 1;
            const double s0 = std::min({p[0][axis], p[1][axis], p[2][axis]}), s1 = std::max({p[0][axis], p[1][axis], p[2][axis]});
            for (int step = 0; step <= 16; ++step) {
              const double t = s0 + (s1 - s0) * step / 16.0;
              double top = -std::numeric_limits<double>::infinity();
              for (int a = 0; a < 3; ++a) {  // the triangle's highest point at t: on one of its edges
                const Eigen::Vector3d& u = p[a];
                const Eigen::Vector3d& w = p[(a + 1) % 3];
                const double lo = std::min(u[axis], w[axis]), hi = std::max(u[axis], w[axis]);
                if (t < lo - 1e-9 || t > hi + 1e-9) continue;
                top = std::max(top, hi - lo < 1e-12 ? std::max(u.z(), w.z()) : u.z() + (w.z() - u.z()) * (t - u[axis]) / (w[axis] - u[axis]));
              }
              const double x = alongRow ? t : p[0].x(), y = alongRow ? p[0].y() : t;
              const std::optional<double> edge = chunkHeightAt(hf, l, k, x, y);
              ASSERT_TRUE(edge.has_value()) << "a skirt hangs where the chunk has no surface: " << x << " " << y;
              EXPECT_LE(top, *edge + kFloatSlackM) << k.level << "/" << k.x << "/" << k.y << " at " << x << " " << y;
              ++checked;
            }
          }
        }
      }
    EXPECT_GT(checked, 20000u);
  }
}

TEST(TerrainChunk, APlaneIsShadedWithItsLambertShadeAtEveryLevel) {
  const int cols = 65, rows = 49;
  const double a = 0.31, b = -0.47;  // dz/dx, dz/dy (y north)
  std::vector<float> h(std::size_t(cols) * rows);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) h[std::size_t(r) * cols + std::size_t(c)] = float(200 + a * c * 2.0 + b * (-r * 2.0));
  const Heightfield hf(cols, rows, h, kOriginX, kOriginY, 2.0, 2.0);
  const ChunkLayout l(cols, rows, 8);
  ChunkShading shading;
  shading.imagery = [](double, double, double, double, int w, int hgt) {
    return std::vector<std::uint8_t>(std::size_t(w) * std::size_t(hgt) * 4, 255);  // opaque white
  };
  const Eigen::Vector3d n = Eigen::Vector3d(-a, -b, 1).normalized();
  const double light = std::min(1.0, kAmbientLight + kSunLight * std::max(0.0, n.dot(shading.sun)));
  for (int level = 0; level < l.levels(); ++level)
    for (const ChunkKey& k : chunksOf(l, level)) {
      const ChunkMesh m = buildChunk(hf, l, k, shading);
      EXPECT_LT(m.maxError, 1e-4);  // a plane (float heights)
      for (std::size_t v = 0; v < m.vertexCount(); ++v)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(m.colours[4 * v + std::size_t(c)], 255 * light, 1.0);
    }
}

TEST(TerrainChunk, ImageryIsReadOnTheLevelsGridAtMapPositions) {
  const Heightfield hf = roughField(53, 41, 31, 0.0, 2.0, 3.0);
  const ChunkLayout l(hf.cols(), hf.rows(), 8);
  ChunkShading shading;
  shading.shade = false;
  shading.mapOrigin = hf.origin();
  // Colour from the map position: red with x, green with y (each wraps every 256 units).
  auto colourAt = [](double x, double y) {
    return std::array<double, 2>{std::fmod(x - kOriginX, 256.0), std::fmod(kOriginY - y, 256.0)};
  };
  int calls = 0;
  shading.imagery = [&](double x0, double y0, double sx, double sy, int w, int hgt) {
    ++calls;
    std::vector<std::uint8_t> rgba(std::size_t(w) * std::size_t(hgt) * 4);
    for (int j = 0; j < hgt; ++j)
      for (int i = 0; i < w; ++i) {
        const auto c = colourAt(x0 + i * sx, y0 - j * sy);
        std::uint8_t* p = &rgba[(std::size_t(j) * std::size_t(w) + std::size_t(i)) * 4];
        p[0] = std::uint8_t(std::lround(c[0]));
        p[1] = std::uint8_t(std::lround(c[1]));
        p[2] = 0;
        p[3] = 255;
      }
    return rgba;
  };
  for (int level = 0; level < l.levels(); ++level)
    for (const ChunkKey& k : chunksOf(l, level)) {
      const ChunkMesh m = buildChunk(hf, l, k, shading);
      for (std::size_t v = 0; v < m.surfaceVertices; ++v) {
        const double x = m.positions[3 * v] + m.offset.x() + kOriginX, y = m.positions[3 * v + 1] + m.offset.y() + kOriginY;
        const auto c = colourAt(x, y);
        // The last, narrower column or row is blended between regular ones: colours linear in x, y
        // blend to their own value there, up to rounding.
        EXPECT_NEAR(m.colours[4 * v], c[0], 1.01) << x;
        EXPECT_NEAR(m.colours[4 * v + 1], c[1], 1.01) << y;
      }
    }
  EXPECT_GT(calls, 0);
}

TEST(TerrainChunk, TheTextureHoldsEverySamplesColourAndFillsHolesFromNeighbours) {
  // Texel (i, j) is the colour of the vertex at kept sample (i, j); a hole's texel repeats a texel
  // next to it, so every hole texel's colour is that of some valid sample of the chunk.
  const Heightfield hf = roughField(70, 53, 11, 0.2);
  const ChunkLayout l(hf.cols(), hf.rows(), 16);
  std::size_t holes = 0;
  for (const ChunkKey k : {ChunkKey{0, 1, 2}, ChunkKey{1, 0, 1}, ChunkKey{2, 0, 0}}) {
    const ChunkMesh m = buildChunk(hf, l, k);
    const std::vector<int> cols = l.columns(k), rows = l.rowsOf(k);
    ASSERT_EQ(m.textureWidth, int(cols.size()));
    ASSERT_EQ(m.textureHeight, int(rows.size()));
    ASSERT_EQ(m.texture.size(), 4 * cols.size() * rows.size());
    ASSERT_EQ(m.texCoords.size(), 2 * m.vertexCount());
    std::set<std::array<std::uint8_t, 4>> valid;
    for (std::size_t v = 0; v < m.surfaceVertices; ++v) {
      const std::size_t i = std::size_t(m.texCoords[2 * v] * float(cols.size()));
      const std::size_t j = std::size_t(m.texCoords[2 * v + 1] * float(rows.size()));
      // The vertex lies at kept sample (i, j).
      EXPECT_NEAR(m.positions[3 * v] + m.offset.x(), cols[i] * hf.dx(), 1e-3);
      EXPECT_NEAR(m.positions[3 * v + 1] + m.offset.y(), -rows[j] * hf.dy(), 1e-3);
      std::array<std::uint8_t, 4> texel;
      for (std::size_t c = 0; c < 4; ++c) {
        texel[c] = m.texture[4 * (j * cols.size() + i) + c];
        EXPECT_EQ(texel[c], m.colours[4 * v + c]);
      }
      valid.insert(texel);
    }
    for (std::size_t j = 0; j < rows.size(); ++j)
      for (std::size_t i = 0; i < cols.size(); ++i) {
        if (hf.valid(cols[i], rows[j])) continue;
        ++holes;
        std::array<std::uint8_t, 4> texel;
        for (std::size_t c = 0; c < 4; ++c) texel[c] = m.texture[4 * (j * cols.size() + i) + c];
        EXPECT_TRUE(valid.count(texel)) << "hole texel " << i << " " << j << " of chunk " << k.level;
      }
  }
  EXPECT_GT(holes, 20u);
}

}  // namespace
}  // namespace nestwalk::terrain
