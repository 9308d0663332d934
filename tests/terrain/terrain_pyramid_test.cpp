// terrain/terrain_pyramid: the pyramid a terrain file gets at import, checked against the in-memory
// heightfield read from the same file: every level's samples bit for bit, every block's bounds
// against the fine samples under it and its error against a brute force over the fine samples
// (and a dense walk along the narrow last cells' diagonals), the chunks' own errors, stripes of any
// height giving the same file; GDAL reads it as a multi-page GeoTIFF; bad pyramids (missing, stale,
// from a future version, truncated, corrupt) are refused with the file's name.
#include "nestwalk/core/input_error.h"
#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/terrain/height_tiles.h"
#include "nestwalk/terrain/paged_heightfield.h"
#include "nestwalk/terrain/terrain_chunk.h"
#include "nestwalk/terrain/terrain_import.h"
#include "nestwalk/terrain/terrain_pyramid.h"
#include "nestwalk/terrain/terrain_pyramid_writer.h"
#include "tests/common/input_error_of.h"
#include "tests/common/temp_folder.h"
#include "tests/terrain/rough_heights.h"

#include <cpl_string.h>
#include <gdal.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <optional>
#include <array>
#include <random>
#include <set>
#include <string>
#include <utility>

namespace nestwalk::test {
namespace {

using terrain::PyramidBlock;
using terrain::PyramidLayout;
using terrain::TerrainPyramid;

/// A terrain file at UTM magnitudes, 70 degrees north (EPSG:32633), with holes; its size is odd in
/// both directions so every level has a narrow last column and row.
struct PyramidCase {
  TempFolder dir;
  std::string terrain;
  terrain::Heightfield hf;
  PyramidCase(int cols, int rows, unsigned seed, double holes)
      : PyramidCase(cols, rows, roughHeights(cols, rows, seed, holes)) {}
  PyramidCase(int cols, int rows, const std::vector<float>& heights)
      : terrain((dir / "dump.tif").string()), hf(write(terrain, cols, rows, heights)) {}
  static terrain::Heightfield write(const std::string& path, int cols, int rows, const std::vector<float>& heights) {
    terrain::writeTerrainCog(path, cols, rows, heights, 512345.5, 7765432.5, 0.5, 0.5, "EPSG:32633", false);
    return terrain::readDem(path);
  }
  static terrain::Heightfield write(const std::string& path, int cols, int rows, unsigned seed, double holes) {
    return write(path, cols, rows, roughHeights(cols, rows, seed, holes));
  }
};

bool sameFloat(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// A chunk built with the pyramid's page against the one built from the heightfield alone: the same
/// surface vertices, triangles, colours and texture; skirt bottoms in the same place, at or below the
/// lowest fine sample of their line's reach (the pyramid's block lows). Returns the skirt bottoms.
int expectSameSurfaceDeeperSkirts(const terrain::ChunkMesh& plain, const terrain::ChunkMesh& fromPage,
                                  const std::string& where) {
  EXPECT_EQ(plain.surfaceVertices, fromPage.surfaceVertices) << where;
  if (plain.positions.size() != fromPage.positions.size()) {
    ADD_FAILURE() << where << ": " << plain.positions.size() << " positions against " << fromPage.positions.size();
    return 0;
  }
  const std::size_t n = 3 * plain.surfaceVertices;
  const auto surfaceEnd = plain.positions.begin() + std::ptrdiff_t(n);
  EXPECT_TRUE(std::equal(plain.positions.begin(), surfaceEnd, fromPage.positions.begin())) << where;
  EXPECT_EQ(plain.colours, fromPage.colours) << where;
  EXPECT_EQ(plain.texture, fromPage.texture) << where;
  EXPECT_EQ(plain.indices, fromPage.indices) << where;
  int skirts = 0;
  for (std::size_t k = n; k < plain.positions.size(); k += 3, ++skirts) {
    EXPECT_EQ(plain.positions[k], fromPage.positions[k]) << where;
    EXPECT_EQ(plain.positions[k + 1], fromPage.positions[k + 1]) << where;
    EXPECT_LE(fromPage.positions[k + 2], plain.positions[k + 2]) << where;
  }
  return skirts;
}


TEST(TerrainPyramid, EveryLevelHoldsTheDemsOwnSamplesAtTheChunkLayoutsColumnsAndRows) {
  PyramidCase c(301, 237, 11, 0.03);
  const TerrainPyramid pyramid(c.terrain);
  const PyramidLayout& layout = pyramid.layout();
  const terrain::ChunkLayout chunks(c.hf.cols(), c.hf.rows(), terrain::kPyramidTopCells);
  ASSERT_EQ(layout.levels, chunks.levels());
  ASSERT_EQ(pyramid.noData(), std::optional<float>(terrain::kTerrainNoData));
  for (int level = 0; level < layout.levels; ++level) {
    // The kept columns and rows of the chunk layout's chunks of this level, together.
    std::set<int> cols, rows;
    for (int y = 0; y < chunks.chunksY(level); ++y)
      for (int x = 0; x < chunks.chunksX(level); ++x) {
        for (int col : chunks.columns({level, x, y})) cols.insert(col);
        for (int row : chunks.rowsOf({level, x, y})) rows.insert(row);
      }
    ASSERT_EQ(int(cols.size()), layout.levelCols(level)) << "level " << level;
    ASSERT_EQ(int(rows.size()), layout.levelRows(level)) << "level " << level;
    const std::vector<float> h = pyramid.readHeights(level, 0, 0, layout.levelCols(level), layout.levelRows(level));
    int j = 0;
    for (int row : rows) {
      int i = 0;
      for (int col : cols) {
        const float got = h[std::size_t(j) * std::size_t(layout.levelCols(level)) + std::size_t(i)];
        if (c.hf.valid(col, row))
          ASSERT_TRUE(sameFloat(got, c.hf.sample(col, row))) << "level " << level << " sample " << col << ", " << row;
        else
          ASSERT_EQ(got, terrain::kTerrainNoData) << "level " << level << " hole " << col << ", " << row;
        ++i;
      }
      ++j;
    }
  }
}

/// A block's bounds and error by brute force: every fine sample of its closed region, each compared
/// with the level's surface (levelHeightAt) where it lies in an existing triangle of one of the
/// block's own cells, and the narrow cells' diagonals walked densely.
struct BruteBlock {
  float lo = INFINITY, hi = -INFINITY;
  double error = 0;
  bool narrow = false;  // holds a narrow last cell (the dense walk is then a lower bound)
};

BruteBlock bruteBlock(const terrain::Heightfield& hf, const PyramidLayout& layout, int level, int bx, int by) {
  BruteBlock b;
  const int s = PyramidLayout::step(level);
  const int i0 = bx * terrain::kPyramidBlockCells, j0 = by * terrain::kPyramidBlockCells;
  const int i1 = std::min(i0 + terrain::kPyramidBlockCells, layout.levelCols(level) - 1);
  const int j1 = std::min(j0 + terrain::kPyramidBlockCells, layout.levelRows(level) - 1);
  const int cLo = std::min(i0 * s, hf.cols() - 1), cHi = std::min(i1 * s, hf.cols() - 1);
  const int rLo = std::min(j0 * s, hf.rows() - 1), rHi = std::min(j1 * s, hf.rows() - 1);
  for (int r = rLo; r <= rHi; ++r)
    for (int col = cLo; col <= cHi; ++col)
      if (hf.valid(col, r)) {
        b.lo = std::min(b.lo, hf.sample(col, r));
        b.hi = std::max(b.hi, hf.sample(col, r));
      }
  if (level == 0) return b;
  for (int j = j0; j < j1; ++j)
    for (int i = i0; i < i1; ++i) {
      const int ca = i * s, cb = std::min(ca + s, hf.cols() - 1), ra = j * s, rb = std::min(ra + s, hf.rows() - 1);
      const int w = cb - ca, h = rb - ra;
      const bool up = hf.valid(ca, ra) && hf.valid(cb, ra) && hf.valid(cb, rb);
      const bool low = hf.valid(ca, ra) && hf.valid(cb, rb) && hf.valid(ca, rb);
      for (int v = 0; v <= h; ++v)
        for (int u = 0; u <= w; ++u) {
          if (!hf.valid(ca + u, ra + v)) continue;
          const long side = long(u) * h - long(v) * w;  // >= 0: upper triangle, <= 0: lower
          if (!((side >= 0 && up) || (side <= 0 && low))) continue;
          const auto coarse = terrain::levelHeightAt(hf, level, (ca + u) * hf.dx(), -(ra + v) * hf.dy());
          if (coarse) b.error = std::max(b.error, std::abs(double(hf.sample(ca + u, ra + v)) - *coarse));
        }
      if (w != h && (up || low)) {
        b.narrow = true;
        const int steps = 256 * std::max(w, h);
        for (int k = 1; k < steps; ++k) {
          const double t = double(k) / steps, fc = ca + t * w, fr = ra + t * h;
          const Eigen::Vector2d o = hf.origin();
          const auto fine = hf.groundHeight(o.x() + fc * hf.dx(), o.y() - fr * hf.dy());
          const auto coarse = terrain::levelHeightAt(hf, level, fc * hf.dx(), -fr * hf.dy());
          if (fine && coarse) b.error = std::max(b.error, std::abs(*fine - *coarse));
        }
      }
    }
  return b;
}

TEST(TerrainPyramid, BlocksHoldTheirFineBoundsAndTheExactErrorOfTheirCells) {
  PyramidCase c(301, 237, 12, 0.03);
  const TerrainPyramid pyramid(c.terrain);
  const PyramidLayout& layout = pyramid.layout();
  int narrowBlocks = 0, emptyBlocks = 0;
  for (int level = 0; level < layout.levels; ++level) {
    const int bw = layout.blocksX(level), bh = layout.blocksY(level);
    const std::vector<PyramidBlock> blocks = pyramid.readBlocks(level, 0, 0, bw, bh);
    for (int by = 0; by < bh; ++by)
      for (int bx = 0; bx < bw; ++bx) {
        const PyramidBlock& got = blocks[std::size_t(by) * std::size_t(bw) + std::size_t(bx)];
        const BruteBlock want = bruteBlock(c.hf, layout, level, bx, by);
        const std::string where = "level " + std::to_string(level) + " block " + std::to_string(bx) + ", " +
                                  std::to_string(by);
        if (want.lo > want.hi) {
          EXPECT_TRUE(got.empty()) << where;
          ++emptyBlocks;
        } else {
          EXPECT_EQ(got.lo, want.lo) << where;
          EXPECT_EQ(got.hi, want.hi) << where;
        }
        // Stored as the float at or above the exact error; the dense walk along a narrow cell's
        // diagonal undershoots its maximum by at most (slope difference) x (walk step): here below
        // 6 m of relief change per fine cell over 1/256 of a cell.
        EXPECT_GE(double(got.error), want.error - 1e-9) << where;
        EXPECT_LE(double(got.error), want.error + (want.narrow ? 0.025 : 1e-5)) << where;
        if (level == 0) {
          EXPECT_EQ(got.error, 0.0f) << where;
        }
        narrowBlocks += want.narrow;
      }
  }
  EXPECT_GT(narrowBlocks, 0);  // the case has narrow last cells
}

TEST(TerrainPyramid, AChunksErrorIsTheLargestOfItsBlocks) {
  PyramidCase c(301, 237, 13, 0.02);
  const TerrainPyramid pyramid(c.terrain);
  const PyramidLayout& layout = pyramid.layout();
  const terrain::ChunkLayout chunks(c.hf.cols(), c.hf.rows(), terrain::kPyramidTopCells);
  constexpr int kBlocksPerChunk = terrain::kPyramidTopCells / terrain::kPyramidBlockCells;
  for (int level = 1; level < layout.levels; ++level)
    for (int y = 0; y < chunks.chunksY(level); ++y)
      for (int x = 0; x < chunks.chunksX(level); ++x) {
        const terrain::ChunkMesh mesh = terrain::buildChunk(c.hf, chunks, {level, x, y});
        const int bx0 = x * kBlocksPerChunk, by0 = y * kBlocksPerChunk;
        const int w = std::min(kBlocksPerChunk, layout.blocksX(level) - bx0);
        const int h = std::min(kBlocksPerChunk, layout.blocksY(level) - by0);
        float largest = 0;
        for (const PyramidBlock& b : pyramid.readBlocks(level, bx0, by0, w, h)) largest = std::max(largest, b.error);
        float chunkError = float(mesh.maxError);
        if (double(chunkError) < mesh.maxError) chunkError = std::nextafter(chunkError, INFINITY);
        EXPECT_EQ(largest, chunkError) << "chunk " << level << "/" << x << "/" << y;
      }
}

TEST(TerrainPyramid, ItsLevelTableIsTheChunksOwnWithoutHolesAndBoundsItWithThem) {
  // Every chunk of every level built (chunkLevelTable over the samples) against the table read from
  // the blocks pages alone.
  for (const double holes : {0.0, 0.03}) {
    PyramidCase c(1201, 777, 29, holes);
    const TerrainPyramid pyramid(c.terrain);
    const auto exact = terrain::chunkLevelTable(c.hf, terrain::ChunkLayout(c.hf.cols(), c.hf.rows(), terrain::kPyramidTopCells));
    const auto read = terrain::chunkLevelTable(pyramid);
    ASSERT_EQ(read.size(), exact.size());
    for (std::size_t l = 0; l < exact.size(); ++l) {
      SCOPED_TRACE("level " + std::to_string(l) + (holes > 0 ? " with holes" : ""));
      EXPECT_EQ(read[l].level, exact[l].level);
      EXPECT_EQ(read[l].step, exact[l].step);
      float rounded = float(exact[l].maxError);
      if (double(rounded) < exact[l].maxError) rounded = std::nextafter(rounded, INFINITY);
      EXPECT_EQ(read[l].maxError, double(rounded));
      if (holes == 0) {
        EXPECT_EQ(read[l].chunks, exact[l].chunks);
        EXPECT_EQ(read[l].triangles, exact[l].triangles);
      } else {
        EXPECT_GE(read[l].chunks, exact[l].chunks);
        EXPECT_GT(read[l].triangles, exact[l].triangles);
      }
    }
  }
}

/// A mesh's surface triangles [first, first + count) as mesh-frame corners, with their boxes.
struct MeshTriangle {
  std::array<Eigen::Vector3d, 3> p;
  Eigen::Vector2d lo, hi;
};
std::vector<MeshTriangle> surfaceTriangles(const terrain::ChunkMesh& m, std::size_t first, std::size_t count) {
  std::vector<MeshTriangle> out;
  for (std::size_t t = 0; t < count; ++t) {
    MeshTriangle tri;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t v = m.indices[first + 3 * t + k];
      tri.p[k] = Eigen::Vector3d(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]) + m.offset;
    }
    tri.lo = tri.p[0].head<2>().cwiseMin(tri.p[1].head<2>()).cwiseMin(tri.p[2].head<2>());
    tri.hi = tri.p[0].head<2>().cwiseMax(tri.p[1].head<2>()).cwiseMax(tri.p[2].head<2>());
    out.push_back(tri);
  }
  return out;
}
/// The drawn surface at mesh-frame (x, y), by brute force over the triangles.
std::optional<double> drawnAt(const std::vector<MeshTriangle>& tris, double x, double y) {
  for (const MeshTriangle& t : tris) {
    if (x < t.lo.x() - 1e-9 || x > t.hi.x() + 1e-9 || y < t.lo.y() - 1e-9 || y > t.hi.y() + 1e-9) continue;
    const auto& a = t.p;
    const double d = (a[1].x() - a[0].x()) * (a[2].y() - a[0].y()) - (a[1].y() - a[0].y()) * (a[2].x() - a[0].x());
    if (std::abs(d) < 1e-12) continue;
    const double w1 = ((x - a[0].x()) * (a[2].y() - a[0].y()) - (y - a[0].y()) * (a[2].x() - a[0].x())) / d;
    const double w2 = ((a[1].x() - a[0].x()) * (y - a[0].y()) - (a[1].y() - a[0].y()) * (x - a[0].x())) / d;
    if (w1 < -1e-9 || w2 < -1e-9 || 1 - w1 - w2 < -1e-9) continue;
    return (1 - w1 - w2) * a[0].z() + w1 * a[1].z() + w2 * a[2].z();
  }
  return std::nullopt;
}

TEST(TerrainPyramid, ChunksBuiltFromItsErrorsBoundTheirExactErrorsAndHoldEveryPoint) {
  // Coarse chunks built with the pyramid's grid errors (terrain_chunk.h, "Errors from the
  // pyramid"): unsimplified, their blocks' errors are the exact ones rounded up to float; simplified
  // (the renderer's 1.5), a dense brute force of |fine - drawn| (every fine sample and 8 points along
  // every fine edge) never exceeds a quadrant's error, which exceeds it by at most the level grid's
  // largest block error there (plus the brute force's spacing: 1/16 cell of slopes below 2); random
  // points of the drawn surface lie in a block whose box holds them and whose error is theirs or more.
  // Benches around a centre (flat treads, 6 m faces) with centimetre waves and a few holes: the kind
  // of surface simplification is for.
  std::vector<float> heights(161 * 131);
  std::mt19937 holes(9);
  for (int r = 0; r < 131; ++r)
    for (int col = 0; col < 161; ++col) {
      const double d = std::hypot(col - 70.0, r - 60.0), step = std::floor(d / 20.0), within = d - 20.0 * step;
      double v = 200.0 - 6.0 * step - (within > 12.0 ? 0.75 * (within - 12.0) : 0.0) + 0.05 * std::sin(0.8 * col);
      if (holes() % 200 == 0) v = NAN;
      heights[std::size_t(r) * 161 + std::size_t(col)] = float(v);
    }
  PyramidCase c(161, 131, heights);
  const TerrainPyramid pyramid(c.terrain);
  const terrain::ChunkLayout l(c.hf.cols(), c.hf.rows(), terrain::kPyramidTopCells);
  ASSERT_EQ(l.levels(), 3);
  constexpr int kPerEdge = 8;
  constexpr double kSpacingSlackM = 0.13;  // the rough heights' slopes (below 2) over 1/16 cell
  std::mt19937 rng(5);
  int checked = 0, points = 0;
  for (int level = 1; level < l.levels(); ++level)
    for (int y = 0; y < l.chunksY(level); ++y)
      for (int x = 0; x < l.chunksX(level); ++x) {
        const terrain::ChunkKey key{level, x, y};
        const terrain::ChunkPyramidData errors = pyramid.chunkPyramidData(key);
        const terrain::ChunkMesh plainExact = terrain::buildChunk(c.hf, l, key);
        const terrain::ChunkMesh plainPyramid = terrain::buildChunk(c.hf, l, key, {}, 0, &errors);
        for (std::size_t q = 0; q < 4; ++q) {
          const auto& a = plainExact.quadrants[q].blocks;
          const auto& b = plainPyramid.quadrants[q].blocks;
          ASSERT_EQ(a.size(), b.size());
          for (std::size_t k = 0; k < a.size(); ++k) {
            float up = float(a[k].error);
            if (double(up) < a[k].error) up = std::nextafter(up, INFINITY);
            EXPECT_EQ(b[k].error, double(up)) << "chunk " << level << "/" << x << "/" << y << " quadrant " << q;
          }
        }
        const terrain::ChunkMesh m = terrain::buildChunk(c.hf, l, key, {}, 1.5, &errors);
        for (std::size_t q = 0; q < 4; ++q) {
          const terrain::ChunkQuadrant& quad = m.quadrants[q];
          if (quad.empty()) continue;
          const auto tris = surfaceTriangles(m, quad.firstIndex, quad.surfaceTriangles);
          double gridMax = 0;
          for (const terrain::ChunkBlock& b : plainPyramid.quadrants[q].blocks) gridMax = std::max(gridMax, b.error);
          Eigen::Vector2d lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
          for (const MeshTriangle& t : tris) lo = lo.cwiseMin(t.lo), hi = hi.cwiseMax(t.hi);
          double brute = 0;
          for (double yy = hi.y(); yy >= lo.y() - 1e-9; yy -= c.hf.dy())
            for (double xx = lo.x(); xx <= hi.x() + 1e-9; xx += c.hf.dx())
              for (int i = 0; i < kPerEdge; ++i) {
                const double t = double(i) / kPerEdge;
                for (const auto& [px, py] : {std::pair(xx + t * c.hf.dx(), yy), std::pair(xx, yy - t * c.hf.dy()),
                                             std::pair(xx + t * c.hf.dx(), yy - t * c.hf.dy())}) {
                  const auto drawn = drawnAt(tris, px, py);
                  const auto fine = c.hf.groundHeight(c.hf.origin().x() + px, c.hf.origin().y() + py);
                  if (drawn && fine) brute = std::max(brute, std::abs(*drawn - *fine));
                }
              }
          const std::string where = "chunk " + std::to_string(level) + "/" + std::to_string(x) + "/" +
                                    std::to_string(y) + " quadrant " + std::to_string(q);
          EXPECT_GE(quad.maxError, brute - 1e-9) << where;
          EXPECT_LE(quad.maxError, brute + gridMax + kSpacingSlackM) << where;
          ++checked;
          std::uniform_real_distribution<double> ux(lo.x(), hi.x()), uy(lo.y(), hi.y());
          for (int i = 0; i < 300; ++i) {
            const double px = ux(rng), py = uy(rng);
            const auto drawn = drawnAt(tris, px, py);
            const auto fine = c.hf.groundHeight(c.hf.origin().x() + px, c.hf.origin().y() + py);
            if (!drawn || !fine) continue;
            const Eigen::Vector3d p(px, py, *drawn);
            const double e = std::abs(*drawn - *fine);
            const bool held = std::any_of(quad.blocks.begin(), quad.blocks.end(), [&](const terrain::ChunkBlock& b) {
              return (p.array() >= b.min.array() - 1e-9).all() && (p.array() <= b.max.array() + 1e-9).all() &&
                     b.error >= e - 1e-8;
            });
            EXPECT_TRUE(held) << where << " at " << px << " " << py;
            ++points;
          }
        }
      }
  EXPECT_GE(checked, 8);
  EXPECT_GT(points, 1500);
}

/// The header's values of page 1 (version, sizes, fingerprint, CRC-32s).
std::vector<std::string> headerOf(const std::string& pyramid) {
  GDALDatasetH ds = GDALOpen(("GTIFF_DIR:1:" + pyramid).c_str(), GA_ReadOnly);
  EXPECT_NE(ds, nullptr);
  std::vector<std::string> items;
  if (!ds) return items;
  for (char** md = GDALGetMetadata(ds, nullptr); md && *md; ++md)
    if (std::strncmp(*md, "NESTWALK_", 9) == 0) items.emplace_back(*md);
  GDALClose(ds);
  return items;
}

TEST(TerrainPyramid, ACoarseChunkFromItsPageHasTheHeightfieldsSurfaceAndColoursDeeperSkirtsAndReadsNoFineSample) {
  // 2,000 x 1,500 (odd sizes: a narrow last column and row at every level), holes; also with the
  // heights moved as the scene loader's map shift moves them (the pages hold the file's own).
  PyramidCase c(2001, 1501, 19, 0.01);
  const auto pyramid = std::make_shared<const TerrainPyramid>(c.terrain);
  for (const double dz : {0.0, 3.5}) {
    SCOPED_TRACE("height shift " + std::to_string(dz));
    std::vector<float> moved;
    for (int r = 0; r < c.hf.rows(); ++r)
      for (int col = 0; col < c.hf.cols(); ++col) moved.push_back(float(c.hf.sample(col, r) + dz));
    const terrain::Heightfield resident(c.hf.cols(), c.hf.rows(), std::move(moved), c.hf.origin().x(),
                                        c.hf.origin().y(), c.hf.dx(), c.hf.dy(), c.hf.noData(), c.hf.crsWkt());
    const terrain::Heightfield paged = terrain::openPagedHeightfield(
        pyramid, {.budgetBytes = std::size_t(64) << 20, .shift = Eigen::Vector3d(0, 0, dz)});
    const terrain::ChunkLayout l(c.hf.cols(), c.hf.rows(), terrain::kPyramidTopCells);
    terrain::ChunkShading shading;
    shading.heightLo = 80;
    shading.heightHi = 160;
    int interior = 0, edges = 0, skirts = 0;
    for (int level = 1; level < l.levels(); ++level)
      for (int y = 0; y < l.chunksY(level); ++y)
        for (int x = 0; x < l.chunksX(level); ++x) {
          const terrain::ChunkKey key{level, x, y};
          const std::string where = "chunk " + std::to_string(level) + "/" + std::to_string(x) + "/" + std::to_string(y);
          const terrain::ChunkPyramidData data = pyramid->chunkPyramidData(key, dz);
          const terrain::ChunkMesh plain = terrain::buildChunk(resident, l, key, shading);
          const std::uint64_t readsBefore = paged.tiles()->stats().reads;
          const terrain::ChunkMesh fromPage = terrain::buildChunk(paged, l, key, shading, 0, &data);
          // No chunk reads a fine sample, at the grid's irregular last column and row neither.
          EXPECT_EQ(paged.tiles()->stats().reads, readsBefore) << where;
          const bool edge = l.columns(key).back() == c.hf.cols() - 1 || l.rowsOf(key).back() == c.hf.rows() - 1;
          interior += edge ? 0 : 1;
          edges += edge ? 1 : 0;
          skirts += expectSameSurfaceDeeperSkirts(plain, fromPage, where);
        }
    EXPECT_GT(interior, 20);
    EXPECT_GT(edges, 10);
    EXPECT_GT(skirts, 1000);
  }
}

TEST(TerrainPyramid, AFineChunkWithItsPageAndExactErrorsIsTheHeightfieldsChunkAndReadsOnlyTheTilesUnderIt) {
  // Levels 1 to 3 (paged_terrain.h's kPyramidErrorsFromLevel): the level page and the blocks' lows
  // from the pyramid, the errors evaluated at the fine samples. Simplified as the renderer does.
  PyramidCase c(2001, 1501, 23, 0.01);
  const auto pyramid = std::make_shared<const TerrainPyramid>(c.terrain);
  const terrain::ChunkLayout l(c.hf.cols(), c.hf.rows(), terrain::kPyramidTopCells);
  terrain::ChunkShading shading;
  shading.heightLo = 80;
  shading.heightHi = 160;
  constexpr double kSimplify = 1.5;
  const terrain::Heightfield shared = terrain::openPagedHeightfield(pyramid, {.budgetBytes = std::size_t(64) << 20});
  int chunks = 0, simplified = 0, checkedTiles = 0;
  for (int level = 1; level <= 3; ++level)
    for (int y = 0; y < l.chunksY(level); ++y)
      for (int x = 0; x < l.chunksX(level); ++x) {
        const terrain::ChunkKey key{level, x, y};
        const std::string where = "chunk " + std::to_string(level) + "/" + std::to_string(x) + "/" + std::to_string(y);
        terrain::ChunkPyramidData data = pyramid->chunkPyramidData(key);
        data.error.clear();
        data.blocksX = data.blocksY = 0;
        const terrain::ChunkMesh plain = terrain::buildChunk(c.hf, l, key, shading, kSimplify);
        // On a paged heightfield of its own (level 2 and 3 chunks): which tiles the build reads.
        const bool own = level >= 2;
        std::optional<terrain::Heightfield> fresh;
        if (own) fresh.emplace(terrain::openPagedHeightfield(pyramid, {.budgetBytes = std::size_t(64) << 20}));
        const terrain::Heightfield& paged = own ? *fresh : shared;
        const terrain::ChunkMesh m = terrain::buildChunk(paged, l, key, shading, kSimplify, &data);
        expectSameSurfaceDeeperSkirts(plain, m, where);
        // The errors are the exact ones, bit for bit.
        EXPECT_EQ(plain.maxError, m.maxError) << where;
        for (std::size_t q = 0; q < 4; ++q) {
          ASSERT_EQ(plain.quadrants[q].blocks.size(), m.quadrants[q].blocks.size()) << where;
          EXPECT_EQ(plain.quadrants[q].maxError, m.quadrants[q].maxError) << where;
          for (std::size_t b = 0; b < plain.quadrants[q].blocks.size(); ++b)
            EXPECT_EQ(plain.quadrants[q].blocks[b].error, m.quadrants[q].blocks[b].error) << where;
          simplified += plain.quadrants[q].surfaceTriangles < 2 * 32 * 32 ? 1 : 0;
        }
        ++chunks;
        if (!own) continue;
        // Only the tiles holding the chunk's cells: not the neighbours' for its last row and column,
        // the hillshade's neighbours or the skirts' reach.
        const std::vector<int> cols = l.columns(key), rows = l.rowsOf(key);
        const terrain::HeightTileCache& tiles = *paged.tiles();
        for (int ty = 0; ty < tiles.tilesY(); ++ty)
          for (int tx = 0; tx < tiles.tilesX(); ++tx) {
            const bool under = tx * terrain::kHeightTileCells < cols.back() &&
                               (tx + 1) * terrain::kHeightTileCells > cols.front() &&
                               ty * terrain::kHeightTileCells < rows.back() &&
                               (ty + 1) * terrain::kHeightTileCells > rows.front();
            EXPECT_TRUE(under || !tiles.holds(tx, ty)) << where << " read tile " << tx << ", " << ty;
            checkedTiles += under && tiles.holds(tx, ty) ? 1 : 0;
          }
      }
  EXPECT_GT(chunks, 200);
  EXPECT_GT(simplified, 100);
  EXPECT_GT(checkedTiles, 60);
}

TEST(TerrainPyramid, StripesOfAnyHeightWriteTheSamePyramid) {
  // 700 rows: the default stripes (256 rows) and stripes of one top-level step (8 rows here: 16
  // would be the top step, minStripeRows 8 < 16) split the block rows of every level differently.
  PyramidCase c(157, 700, 14, 0.02);
  const std::string defaultPyramid = terrain::pyramidPathOf(c.terrain);
  const std::string thin = (c.dir / "thin.pyramid.tif").string();
  terrain::PyramidWriteOptions options;
  options.minStripeRows = 8;
  terrain::writeTerrainPyramid(c.terrain, thin, options);
  // 24 rows: not a multiple of the top step (16), rounded up to 32.
  const std::string odd = (c.dir / "odd.pyramid.tif").string();
  options.minStripeRows = 24;
  terrain::writeTerrainPyramid(c.terrain, odd, options);
  const std::vector<std::string> a = headerOf(defaultPyramid), b = headerOf(thin), d = headerOf(odd);
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(a, b);  // same CRC-32 for every page
  EXPECT_EQ(a, d);
  EXPECT_GT(PyramidLayout(157, 700).levels, 3);
}

TEST(TerrainPyramid, GdalReadsItAsAMultiPageGeoTiffOnTheTerrainsMap) {
  PyramidCase c(301, 237, 15, 0.0);
  const std::string path = terrain::pyramidPathOf(c.terrain);
  EXPECT_EQ(path, (c.dir / "dump.pyramid.tif").string());
  GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
  ASSERT_NE(ds, nullptr);
  const PyramidLayout layout(301, 237);
  EXPECT_EQ(CSLCount(GDALGetMetadata(ds, "SUBDATASETS")), 2 * layout.pages());
  GDALClose(ds);
  // Level 2's pixel (i, j) is centred on fine sample (4 i, 4 j); block pixels start at sample (0, 0).
  GDALDatasetH level2 = GDALOpen(("GTIFF_DIR:2:" + path).c_str(), GA_ReadOnly);
  ASSERT_NE(level2, nullptr);
  double gt[6];
  ASSERT_EQ(GDALGetGeoTransform(level2, gt), CE_None);
  const Eigen::Vector2d o = c.hf.origin();
  EXPECT_DOUBLE_EQ(gt[0] + 3.5 * gt[1], o.x() + 3 * 4 * c.hf.dx());
  EXPECT_DOUBLE_EQ(gt[3] + 5.5 * gt[5], o.y() - 5 * 4 * c.hf.dy());
  EXPECT_NE(std::string(GDALGetProjectionRef(level2)).find("32633"), std::string::npos);
  GDALClose(level2);
  GDALDatasetH blocks1 = GDALOpen(("GTIFF_DIR:" + std::to_string(layout.blocksPage(1)) + ":" + path).c_str(), GA_ReadOnly);
  ASSERT_NE(blocks1, nullptr);
  ASSERT_EQ(GDALGetGeoTransform(blocks1, gt), CE_None);
  EXPECT_DOUBLE_EQ(gt[0], o.x());
  EXPECT_DOUBLE_EQ(gt[1], 16 * c.hf.dx());
  EXPECT_EQ(GDALGetRasterCount(blocks1), 3);
  GDALClose(blocks1);
}

/// Opening the pyramid of `terrain` (dump.tif) is refused with a message naming its pyramid and `why`.
void expectRefused(const std::string& terrain, const std::string& why) {
  const std::string e = inputError([&] { TerrainPyramid p(terrain); });
  EXPECT_NE(e.find("dump.pyramid.tif"), std::string::npos) << e;
  EXPECT_NE(e.find(why), std::string::npos) << e;
}

TEST(TerrainPyramid, ATerrainWithoutItsPyramidIsNamedWithTheMissingFile) {
  PyramidCase c(40, 30, 16, 0.0);
  std::filesystem::remove(terrain::pyramidPathOf(c.terrain));
  expectRefused(c.terrain, "no terrain pyramid");
}

TEST(TerrainPyramid, ATerrainChangedSinceItsPyramidIsRefused) {
  PyramidCase c(301, 237, 17, 0.0);
  // Another terrain of the same size in its place, its old pyramid kept.
  const std::string other = (c.dir / "other.tif").string();
  PyramidCase::write(other, 301, 237, 18, 0.0);
  std::filesystem::copy_file(other, c.terrain, std::filesystem::copy_options::overwrite_existing);
  expectRefused(c.terrain, "changed since");
}

TEST(TerrainPyramid, APyramidFromAFutureVersionIsRefused) {
  PyramidCase c(40, 30, 19, 0.0);
  const std::string path = terrain::pyramidPathOf(c.terrain);
  GDALDatasetH ds = GDALOpen(("GTIFF_DIR:1:" + path).c_str(), GA_Update);
  ASSERT_NE(ds, nullptr);
  GDALSetMetadataItem(ds, terrain::kPyramidKeyVersion, "2", nullptr);
  GDALClose(ds);
  expectRefused(c.terrain, "newer");
}

TEST(TerrainPyramid, ATruncatedOrCorruptPyramidIsRefusedNeverRead) {
  PyramidCase c(301, 237, 20, 0.0);
  const std::string path = terrain::pyramidPathOf(c.terrain);
  const std::string whole = readText(path);
  ASSERT_GT(whole.size(), 4096u);
  // Cut at several places: every cut is refused with the pyramid's name.
  for (const double keep : {0.1, 0.5, 0.9, 0.99}) {
    {
      std::ofstream out(path, std::ios::binary | std::ios::trunc);
      out.write(whole.data(), std::streamsize(double(whole.size()) * keep));
    }
    const std::string e = inputError([&] { TerrainPyramid p(c.terrain); });
    EXPECT_NE(e.find("dump.pyramid.tif"), std::string::npos) << keep << ": " << e;
  }
  // One byte flipped in every 64th position of the data: each copy is refused or reads its CRC.
  int refused = 0, tries = 0;
  for (std::size_t at = 2048; at < whole.size(); at += whole.size() / 64, ++tries) {
    std::string bad = whole;
    bad[at] = char(bad[at] ^ 0x5a);
    {
      std::ofstream out(path, std::ios::binary | std::ios::trunc);
      out.write(bad.data(), std::streamsize(bad.size()));
    }
    try {
      TerrainPyramid p(c.terrain);
      p.verify();  // whatever opened reads as it was written, or is refused below
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("dump.pyramid.tif"), std::string::npos) << e.what();
      ++refused;
    }
  }
  EXPECT_GT(refused, 0) << tries;
}

TEST(TerrainPyramid, ARasterStoredSouthUpGetsNoPyramidOfItsRows) {
  // Its rows are the heightfield's upside down: the writer refuses it (import makes it north-up).
  TempFolder dir;
  const std::string path = (dir / "south_up.tif").string();
  terrain::initGdal();
  GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), path.c_str(), 20, 15, 1, GDT_Float32, nullptr);
  ASSERT_NE(ds, nullptr);
  double gt[6] = {500000.0, 1.0, 0.0, 7000000.0, 0.0, 1.0};  // rows run north
  GDALSetGeoTransform(ds, gt);
  std::vector<float> v(20 * 15, 5.0f);
  ASSERT_EQ(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Write, 0, 0, 20, 15, v.data(), 20, 15, GDT_Float32, 0, 0), CE_None);
  GDALClose(ds);
  const std::string e =
      inputError([&] { terrain::writeTerrainPyramid(path, terrain::pyramidPathOf(path)); });
  EXPECT_NE(e.find("south-up"), std::string::npos) << e;
  EXPECT_FALSE(std::filesystem::exists(terrain::pyramidPathOf(path)));
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"south_up.tif"});  // no staging file left
}

TEST(TerrainPyramid, ImportWritesThePyramidAndReplacesItOnlyWhenAsked) {
  TempFolder dir;
  const std::string in = (dir / "in.tif").string(), out = (dir / "out.tif").string();
  PyramidCase::write(in, 90, 70, 21, 0.0);
  terrain::importTerrain(in, out, {});
  EXPECT_TRUE(std::filesystem::exists(dir / "out.pyramid.tif"));
  EXPECT_NO_THROW(TerrainPyramid(out).verify());
  // The terrain gone, its pyramid left: a new import does not replace it unasked.
  std::filesystem::remove(out);
  const std::string e = inputError([&] { terrain::importTerrain(in, out, {}); });
  EXPECT_NE(e.find("out.pyramid.tif"), std::string::npos) << e;
  terrain::ImportOptions again;
  again.overwrite = true;
  terrain::importTerrain(in, out, again);
  EXPECT_NO_THROW(TerrainPyramid(out).verify());
  // Nothing else left behind: the input (and its own pyramid), the output and its pyramid.
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"in.pyramid.tif", "in.tif", "out.pyramid.tif", "out.tif"}));
}

}  // namespace
}  // namespace nestwalk::test
