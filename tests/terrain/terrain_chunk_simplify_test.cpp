// Simplified terrain chunks (terrain/terrain_chunk.h, "Simplification"): a simplified quadrant still
// tiles its grid's footprint and keeps every border vertex, its recorded errors are the exact
// maximum of a dense brute force over the simplified triangles, its blocks hold every point with its
// error, level 0 keeps the exact grid beside it, and a terraced surface loses most of its triangles.
// Level 0's refinements ("Refinements") are held to the same checks, and fall in error while they
// rise in triangles, below the grid's.
#include "nestwalk/terrain/terrain_chunk.h"
#include "nestwalk/terrain/heightfield.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>

namespace nestwalk::terrain {
namespace {

constexpr double kOriginX = 500000.0, kOriginY = 5200000.0;  // UTM magnitudes
constexpr double kFraction = 1.5;  // the renderer's default (kTerrainSimplifyFraction)

/// Benches: flat treads 12 m deep, faces rising 6 m over 8 m, around a centre, with centimetre
/// waves (the kind of surface simplification is for); optional holes.
Heightfield terraces(int cols, int rows, double holes = 0.0) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<float> h(std::size_t(cols) * std::size_t(rows));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double d = std::hypot(c - 0.45 * cols, r - 0.55 * rows);
      const double step = std::floor(d / 20.0), within = d - 20.0 * step;
      double v = 200.0 - 6.0 * step - (within > 12.0 ? 6.0 * (within - 12.0) / 8.0 : 0.0);
      v += 0.05 * std::sin(0.8 * c) * std::cos(0.6 * r);
      if (holes > 0 && unit(rng) < holes) v = std::numeric_limits<double>::quiet_NaN();
      h[std::size_t(r) * std::size_t(cols) + std::size_t(c)] = float(v);
    }
  return Heightfield(cols, rows, std::move(h), kOriginX, kOriginY, 1.0, 1.0);
}

std::vector<ChunkKey> allChunks(const ChunkLayout& l) {
  std::vector<ChunkKey> v;
  for (int level = 0; level < l.levels(); ++level)
    for (int y = 0; y < l.chunksY(level); ++y)
      for (int x = 0; x < l.chunksX(level); ++x) v.push_back({level, x, y});
  return v;
}

/// A mesh vertex in the mesh frame.
Eigen::Vector3d vertexAt(const ChunkMesh& m, std::uint32_t v) {
  return Eigen::Vector3d(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]) + m.offset;
}

/// Surface triangles [first, first + count) of the index array as mesh-frame corners.
std::vector<std::array<Eigen::Vector3d, 3>> triangles(const ChunkMesh& m, std::size_t first, std::size_t count) {
  std::vector<std::array<Eigen::Vector3d, 3>> out;
  for (std::size_t t = 0; t < count; ++t)
    out.push_back({vertexAt(m, m.indices[first + 3 * t]), vertexAt(m, m.indices[first + 3 * t + 1]),
                   vertexAt(m, m.indices[first + 3 * t + 2])});
  return out;
}

double area2(const std::array<Eigen::Vector3d, 3>& t) {
  return (t[1].x() - t[0].x()) * (t[2].y() - t[0].y()) - (t[1].y() - t[0].y()) * (t[2].x() - t[0].x());
}

/// The surface of a triangle list at (x, y), by brute force (nullopt outside every triangle).
std::optional<double> heightAt(const std::vector<std::array<Eigen::Vector3d, 3>>& tris, double x, double y) {
  for (const auto& t : tris) {
    const double a = area2(t);
    if (std::abs(a) < 1e-12) continue;
    const double w1 = ((x - t[0].x()) * (t[2].y() - t[0].y()) - (y - t[0].y()) * (t[2].x() - t[0].x())) / a;
    const double w2 = ((t[1].x() - t[0].x()) * (y - t[0].y()) - (t[1].y() - t[0].y()) * (x - t[0].x())) / a;
    const double w0 = 1 - w1 - w2;
    if (w0 < -1e-9 || w1 < -1e-9 || w2 < -1e-9) continue;
    return w0 * t[0].z() + w1 * t[1].z() + w2 * t[2].z();
  }
  return std::nullopt;
}

std::optional<double> fineAt(const Heightfield& hf, double x, double y) {
  return hf.groundHeight(hf.origin().x() + x, hf.origin().y() + y);
}

/// The mesh-frame box of a quadrant's grid surface (its fine sample range).
struct Footprint {
  double x0, x1, y0, y1;
};
Footprint footprintOf(const std::vector<std::array<Eigen::Vector3d, 3>>& tris) {
  Footprint f{1e300, -1e300, 1e300, -1e300};
  for (const auto& t : tris)
    for (const auto& p : t) {
      f.x0 = std::min(f.x0, p.x());
      f.x1 = std::max(f.x1, p.x());
      f.y0 = std::min(f.y0, p.y());
      f.y1 = std::max(f.y1, p.y());
    }
  return f;
}

/// A simplified surface of a quadrant: its own, or one of its refinements.
struct SurfaceRange {
  std::size_t firstIndex, surfaceTriangles;
  double maxError;
  const std::vector<ChunkBlock>* blocks;
  std::string name;
};
std::vector<SurfaceRange> surfacesOf(const ChunkQuadrant& q) {
  std::vector<SurfaceRange> v{{q.firstIndex, q.surfaceTriangles, q.maxError, &q.blocks, "own"}};
  for (std::size_t r = 0; r < q.refinements.size(); ++r)
    v.push_back({q.refinements[r].firstIndex, q.refinements[r].surfaceTriangles, q.refinements[r].maxError,
                 &q.refinements[r].blocks, "refinement " + std::to_string(r)});
  return v;
}

/// Calls visit(key, quadrant, mesh, surface) for every simplified surface (own and refinements) of
/// every chunk quadrant of the layout, the chunks simplified at kFraction.
template <class Visit>
void forEachSimplifiedSurface(const Heightfield& hf, const ChunkLayout& l, Visit&& visit) {
  for (const ChunkKey& k : allChunks(l)) {
    const ChunkMesh m = buildChunk(hf, l, k, {}, kFraction);
    for (std::size_t q = 0; q < 4; ++q) {
      if (m.quadrants[q].empty()) continue;
      for (const SurfaceRange& quad : surfacesOf(m.quadrants[q])) {
        SCOPED_TRACE(quad.name);
        visit(k, q, m, quad);
      }
    }
  }
}

TEST(TerrainChunkSimplify, QuadrantsTileTheirGridAndKeepEveryBorderVertex) {
  for (const double holes : {0.0, 0.01}) {
    const Heightfield hf = terraces(131, 97, holes);
    const ChunkLayout l(hf.cols(), hf.rows(), 16);
    std::size_t gridTriangles = 0, simplifiedTriangles = 0;
    for (const ChunkKey& k : allChunks(l)) {
      const ChunkMesh grid = buildChunk(hf, l, k), simple = buildChunk(hf, l, k, {}, kFraction);
      for (std::size_t q = 0; q < 4; ++q) {
        const ChunkQuadrant &gq = grid.quadrants[q], &sq = simple.quadrants[q];
        gridTriangles += gq.surfaceTriangles;
        simplifiedTriangles += sq.surfaceTriangles;
        const auto gt = triangles(grid, gq.firstIndex, gq.surfaceTriangles);
        for (const SurfaceRange& range : surfacesOf(sq)) {
          SCOPED_TRACE(range.name);
          EXPECT_LE(range.surfaceTriangles, gq.surfaceTriangles);
          const auto st = triangles(simple, range.firstIndex, range.surfaceTriangles);
          // Same footprint: every triangle faces up (counter-clockwise from above, or a border sliver)
          // and the areas add up to the grid's.
          double ga = 0, sa = 0;
          for (const auto& t : gt) ga += area2(t);
          for (const auto& t : st) {
            EXPECT_GE(area2(t), -1e-9) << "level " << k.level;
            sa += area2(t);
          }
          EXPECT_NEAR(sa, ga, 1e-6 * std::max(1.0, ga));
          // Every grid vertex on the quadrant's outline or next to a hole (a vertex of a grid edge
          // with one triangle) is still a vertex.
          std::map<std::pair<std::tuple<double, double>, std::tuple<double, double>>, int> edgeUse;
          auto keyOf = [](const Eigen::Vector3d& p) { return std::tuple(p.x(), p.y()); };
          for (const auto& t : gt)
            for (int e = 0; e < 3; ++e) {
              auto a = keyOf(t[std::size_t(e)]), b = keyOf(t[std::size_t((e + 1) % 3)]);
              if (b < a) std::swap(a, b);
              ++edgeUse[{a, b}];
            }
          std::set<std::tuple<double, double>> kept;
          for (const auto& t : st)
            for (const auto& p : t) kept.insert(keyOf(p));
          for (const auto& [edge, uses] : edgeUse)
            if (uses == 1) {
              EXPECT_TRUE(kept.count(edge.first)) << "level " << k.level << " quadrant " << q;
              EXPECT_TRUE(kept.count(edge.second)) << "level " << k.level << " quadrant " << q;
            }
        }
        // The skirts are the grid's.
        EXPECT_EQ(sq.skirtTriangles, gq.skirtTriangles);
      }
    }
    EXPECT_LT(double(simplifiedTriangles), 0.6 * double(gridTriangles)) << "holes " << holes;
  }
}

TEST(TerrainChunkSimplify, ErrorsAreTheExactMaximumAndBlocksHoldEveryPoint) {
  // The recorded error is the maximum over the candidates of terrain_chunk.h; a dense brute force
  // (every fine sample and 32 points along every fine column, row and diagonal edge) can only find
  // less, and at most the difference's slope times half the spacing less. Random points of the
  // simplified surface lie in a block whose box holds them and whose error is at least theirs.
  const Heightfield hf = terraces(97, 81);
  const ChunkLayout l(hf.cols(), hf.rows(), 16);
  constexpr int kPerEdge = 32;
  constexpr double kSpacingSlackM = 0.05;  // |slope| <= 1.5 of the difference times 1/64 m, rounded up
  std::mt19937 rng(3);
  std::size_t checked = 0, points = 0;
  forEachSimplifiedSurface(hf, l, [&](const ChunkKey& k, std::size_t q, const ChunkMesh& m, const SurfaceRange& quad) {
    const auto tris = triangles(m, quad.firstIndex, quad.surfaceTriangles);
    const Footprint f = footprintOf(tris);
    double brute = 0;
    auto visit = [&](double x, double y) {
      const std::optional<double> s = heightAt(tris, x, y), fine = fineAt(hf, x, y);
      if (s && fine) brute = std::max(brute, std::abs(*s - *fine));
    };
    for (double y = f.y1; y >= f.y0 - 1e-9; y -= 1.0)
      for (double x = f.x0; x <= f.x1 + 1e-9; x += 1.0)
        for (int i = 0; i < kPerEdge; ++i) {
          const double t = double(i) / kPerEdge;
          visit(x + t, y);      // along the row
          visit(x, y - t);      // along the column
          visit(x + t, y - t);  // along the north-west to south-east diagonal
        }
    EXPECT_GE(quad.maxError, brute - 1e-9) << "level " << k.level << " quadrant " << q;
    EXPECT_LE(quad.maxError, brute + kSpacingSlackM) << "level " << k.level << " quadrant " << q;
    ++checked;
    std::uniform_real_distribution<double> ux(f.x0, f.x1), uy(f.y0, f.y1);
    for (int i = 0; i < 200; ++i) {
      const double x = ux(rng), y = uy(rng);
      const std::optional<double> s = heightAt(tris, x, y), fine = fineAt(hf, x, y);
      if (!s || !fine) continue;
      const Eigen::Vector3d p(x, y, *s);
      const double e = std::abs(*s - *fine);
      const bool held = std::any_of(quad.blocks->begin(), quad.blocks->end(), [&](const ChunkBlock& b) {
        return (p.array() >= b.min.array() - 1e-9).all() && (p.array() <= b.max.array() + 1e-9).all() &&
               b.error >= e - 1e-8;
      });
      EXPECT_TRUE(held) << "level " << k.level << " quadrant " << q << " at " << x << " " << y;
      ++points;
    }
  });
  EXPECT_GT(checked, 40u);
  EXPECT_GT(points, 8000u);
}

TEST(TerrainChunkSimplify, ErrorsAreTheMaximumOverTheCandidatesReadThroughTheGroundQuery) {
  // terrain_chunk.h's candidates, found here independently: every fine sample inside each simplified
  // triangle and every crossing of its edges with a fine column, row or diagonal, the fine surface
  // read through Heightfield::groundHeight (the chunk reads its samples directly) and the triangle's
  // own plane by barycentric weights. Their maximum is the recorded error, to rounding.
  const Heightfield hf = terraces(97, 81);  // 1 m cells: fine (column, row) = (x, -y) in the mesh frame
  const ChunkLayout l(hf.cols(), hf.rows(), 16);
  std::size_t surfaces = 0, crossings = 0;
  forEachSimplifiedSurface(hf, l, [&](const ChunkKey& k, std::size_t q, const ChunkMesh& m, const SurfaceRange& quad) {
    double worst = 0;
    for (const auto& t : triangles(m, quad.firstIndex, quad.surfaceTriangles)) {
      const double a = area2(t);
      if (a == 0) continue;  // a border sliver: no area, no surface of its own
      auto plane = [&](double x, double y) {
        const double w1 = ((x - t[0].x()) * (t[2].y() - t[0].y()) - (y - t[0].y()) * (t[2].x() - t[0].x())) / a;
        const double w2 = ((t[1].x() - t[0].x()) * (y - t[0].y()) - (t[1].y() - t[0].y()) * (x - t[0].x())) / a;
        return (1 - w1 - w2) * t[0].z() + w1 * t[1].z() + w2 * t[2].z();
      };
      auto candidate = [&](double x, double y) {
        if (const std::optional<double> fine = fineAt(hf, x, y)) worst = std::max(worst, std::abs(*fine - plane(x, y)));
      };
      const Footprint f = footprintOf({t});
      for (double y = std::ceil(f.y0); y <= f.y1; y += 1.0)
        for (double x = std::ceil(f.x0); x <= f.x1; x += 1.0)
          if (heightAt({t}, x, y)) candidate(x, y);
      for (int e = 0; e < 3; ++e) {
        const Eigen::Vector3d &p = t[std::size_t(e)], &r = t[std::size_t((e + 1) % 3)];
        // Along the edge, s in (0, 1): where x, y or x + y (column - row) is a whole number.
        for (const auto& [from, to] : {std::pair(p.x(), r.x()), std::pair(p.y(), r.y()), std::pair(p.x() + p.y(), r.x() + r.y())})
          for (double v = std::floor(std::min(from, to)) + 1; v < std::max(from, to); v += 1.0) {
            const double s = (v - from) / (to - from);
            candidate(p.x() + s * (r.x() - p.x()), p.y() + s * (r.y() - p.y()));
            ++crossings;
          }
      }
    }
    EXPECT_NEAR(quad.maxError, worst, 1e-9) << "level " << k.level << " quadrant " << q;
    ++surfaces;
  });
  EXPECT_GT(surfaces, 100u);
  EXPECT_GT(crossings, 10000u);
}

TEST(TerrainChunkSimplify, LevelZeroKeepsItsExactGridBesideTheSimplifiedOne) {
  const Heightfield hf = terraces(97, 81, 0.01);
  const ChunkLayout l(hf.cols(), hf.rows(), 16);
  std::size_t simplifiedQuadrants = 0, refinements = 0;
  for (int y = 0; y < l.chunksY(0); ++y)
    for (int x = 0; x < l.chunksX(0); ++x) {
      const ChunkKey k{0, x, y};
      const ChunkMesh grid = buildChunk(hf, l, k), simple = buildChunk(hf, l, k, {}, kFraction);
      for (std::size_t q = 0; q < 4; ++q) {
        const ChunkQuadrant &gq = grid.quadrants[q], &sq = simple.quadrants[q];
        if (sq.exactIndexCount == 0) {
          EXPECT_EQ(sq.surfaceTriangles, gq.surfaceTriangles);
          continue;
        }
        ++simplifiedQuadrants;
        EXPECT_LT(sq.surfaceTriangles, gq.surfaceTriangles);
        EXPECT_GT(sq.maxError, 0.0);
        // The exact range draws the grid's very triangles and skirts (by position).
        auto positions = [](const ChunkMesh& m, std::size_t first, std::size_t count) {
          std::multiset<std::array<float, 9>> s;
          for (std::size_t t = 0; t < count; ++t) {
            std::array<float, 9> c;
            for (std::size_t v = 0; v < 3; ++v)
              for (std::size_t i = 0; i < 3; ++i) {
                const std::uint32_t idx = m.indices[first + 3 * t + v];
                c[3 * v + i] = float(double(m.positions[3 * idx + i]) + m.offset[Eigen::Index(i)]);
              }
            s.insert(c);
          }
          return s;
        };
        EXPECT_EQ(positions(simple, sq.exactFirstIndex, sq.exactIndexCount / 3),
                  positions(grid, gq.firstIndex, gq.indexCount / 3));
        EXPECT_EQ(sq.exactSurfaceTriangles, gq.surfaceTriangles);
        // Refinements: errors falling and triangles rising from the quadrant's own, all below the
        // grid's triangles; each range ends with the quadrant's very skirts.
        double error = sq.maxError;
        std::size_t triangles = sq.surfaceTriangles;
        const auto skirtsOf = [&](std::size_t first, std::size_t surface) {
          const auto from = simple.indices.begin() + std::ptrdiff_t(first + 3 * surface);
          return std::vector<std::uint32_t>(from, from + std::ptrdiff_t(3 * sq.skirtTriangles));
        };
        for (const ChunkRefinement& r : sq.refinements) {
          ++refinements;
          EXPECT_LT(r.maxError, error);
          EXPECT_GT(r.surfaceTriangles, triangles);
          EXPECT_LE(double(r.surfaceTriangles), kRefinementMaxGridShare * double(gq.surfaceTriangles));
          EXPECT_EQ(r.indexCount, 3 * (r.surfaceTriangles + sq.skirtTriangles));
          EXPECT_EQ(skirtsOf(r.firstIndex, r.surfaceTriangles), skirtsOf(sq.firstIndex, sq.surfaceTriangles));
          error = r.maxError;
          triangles = r.surfaceTriangles;
        }
        EXPECT_LE(sq.refinements.size(), std::size_t(kMaxRefinements));
      }
    }
  EXPECT_GT(simplifiedQuadrants, 10u);
  EXPECT_GT(refinements, 10u);
}

}  // namespace
}  // namespace nestwalk::terrain
