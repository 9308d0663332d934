// The static cut of the chunk quadtree (render/terrain_cut.h), checked on the triangles it draws,
// read back from its nodes: seen from above they cover the grid exactly once (skirts are vertical);
// at every fine sample under a surface triangle the surface is within the cut's error of the
// sample's height (a brute force over the samples, independent of the chunks' error pass); the
// error reported is the largest drawn; and neighbouring cells are drawn at most three levels apart
// (what the skirts close), also where a flat plain meets rough ground; the same when the chunks take
// their samples and errors from the terrain's pyramid (as a survey-size export does). At UTM
// magnitudes.
#include "nestwalk/render/terrain_cut.h"

#include "nestwalk/terrain/terrain_import.h"
#include "nestwalk/terrain/terrain_pyramid.h"
#include "tests/common/temp_folder.h"
#include "tests/terrain/rough_heights.h"

#include <gtest/gtest.h>
#include <osg/Geometry>
#include <osg/MatrixTransform>
#include <osg/NodeVisitor>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace nestwalk {
namespace {

constexpr double kOriginX = 612000.0, kOriginY = 7012000.0;  // UTM magnitudes
/// Float rounding of the drawn vertices (heights of ~100 m, positions relative to each chunk): metres.
constexpr double kVertexSlack = 1e-4;

/// A surface triangle of the cut in the mesh frame (columns and rows, not metres), with its level.
struct CutTriangle {
  Eigen::Vector3d a, b, c;  // x = column, y = row, z = height
  int level;
};

/// The cut's triangles: each node "chunk L/X/Y" names its level; vertices through the node's matrix.
class TriangleReader : public osg::NodeVisitor {
 public:
  TriangleReader(const terrain::Heightfield& hf) : osg::NodeVisitor(TRAVERSE_ALL_CHILDREN), hf_(hf) {}
  void apply(osg::MatrixTransform& t) override {
    int level = 0, x = 0, y = 0;
    if (std::sscanf(t.getName().c_str(), "chunk %d/%d/%d", &level, &x, &y) == 3) level_ = level;
    matrix_ = t.getMatrix();
    traverse(t);
  }
  void apply(osg::Geometry& g) override {
    const auto* v = dynamic_cast<const osg::Vec3Array*>(g.getVertexArray());
    ASSERT_NE(v, nullptr);
    for (unsigned s = 0; s < g.getNumPrimitiveSets(); ++s) {
      const osg::PrimitiveSet* set = g.getPrimitiveSet(s);
      for (unsigned i = 0; i + 2 < set->getNumIndices(); i += 3) {
        CutTriangle t{point((*v)[set->index(i)]), point((*v)[set->index(i + 1)]), point((*v)[set->index(i + 2)]), level_};
        const double area = (t.b.x() - t.a.x()) * (t.c.y() - t.a.y()) - (t.c.x() - t.a.x()) * (t.b.y() - t.a.y());
        ++triangles;
        if (std::abs(area) > 1e-9) surface.push_back(t);  // skirts are vertical: no area from above
      }
    }
  }
  std::vector<CutTriangle> surface;  // those with an area seen from above
  std::size_t triangles = 0;         // all, skirts and zero-area slivers included

 private:
  Eigen::Vector3d point(const osg::Vec3& p) const {
    const osg::Vec3d m = osg::Vec3d(p) * matrix_;  // the mesh frame, metres
    return {m.x() / hf_.dx(), -m.y() / hf_.dy(), m.z()};
  }
  const terrain::Heightfield& hf_;
  osg::Matrixd matrix_;
  int level_ = -1;
};

/// Barycentric weights of (x, y) in the triangle seen from above, or false when outside (with slack).
bool weights(const CutTriangle& t, double x, double y, double w[3]) {
  const double d = (t.b.y() - t.c.y()) * (t.a.x() - t.c.x()) + (t.c.x() - t.b.x()) * (t.a.y() - t.c.y());
  w[0] = ((t.b.y() - t.c.y()) * (x - t.c.x()) + (t.c.x() - t.b.x()) * (y - t.c.y())) / d;
  w[1] = ((t.c.y() - t.a.y()) * (x - t.c.x()) + (t.a.x() - t.c.x()) * (y - t.c.y())) / d;
  w[2] = 1 - w[0] - w[1];
  return w[0] >= -1e-9 && w[1] >= -1e-9 && w[2] >= -1e-9;
}

struct CutCheck {
  double area = 0;         // cells, summed from above
  double worstError = 0;   // the largest |surface - sample| at fine samples under surface triangles, m
  int worstLevelGap = 0;   // between cells sharing an edge
  std::size_t uncovered = 0;
};

CutCheck check(const terrain::Heightfield& hf, const TriangleReader& reader) {
  CutCheck out;
  const int cellsX = hf.cols() - 1, cellsY = hf.rows() - 1;
  std::vector<int> cellLevel(std::size_t(cellsX) * std::size_t(cellsY), -1);
  for (const CutTriangle& t : reader.surface) {
    out.area += 0.5 * std::abs((t.b.x() - t.a.x()) * (t.c.y() - t.a.y()) - (t.c.x() - t.a.x()) * (t.b.y() - t.a.y()));
    const int c0 = int(std::floor(std::min({t.a.x(), t.b.x(), t.c.x()}) + 1e-6));
    const int c1 = int(std::ceil(std::max({t.a.x(), t.b.x(), t.c.x()}) - 1e-6));
    const int r0 = int(std::floor(std::min({t.a.y(), t.b.y(), t.c.y()}) + 1e-6));
    const int r1 = int(std::ceil(std::max({t.a.y(), t.b.y(), t.c.y()}) - 1e-6));
    double w[3];
    for (int r = r0; r <= r1; ++r)
      for (int c = c0; c <= c1; ++c) {
        if (weights(t, c, r, w) && hf.valid(c, r)) {
          const double z = w[0] * t.a.z() + w[1] * t.b.z() + w[2] * t.c.z();
          out.worstError = std::max(out.worstError, std::abs(z - double(hf.sample(c, r))));
        }
        if (c < cellsX && r < cellsY && weights(t, c + 0.5, r + 0.5, w))
          cellLevel[std::size_t(r) * std::size_t(cellsX) + std::size_t(c)] = t.level;
      }
  }
  for (int r = 0; r < cellsY; ++r)
    for (int c = 0; c < cellsX; ++c) {
      const int here = cellLevel[std::size_t(r) * std::size_t(cellsX) + std::size_t(c)];
      if (here < 0) {
        ++out.uncovered;
        continue;
      }
      if (c + 1 < cellsX) {
        const int east = cellLevel[std::size_t(r) * std::size_t(cellsX) + std::size_t(c + 1)];
        if (east >= 0) out.worstLevelGap = std::max(out.worstLevelGap, std::abs(here - east));
      }
      if (r + 1 < cellsY) {
        const int south = cellLevel[std::size_t(r + 1) * std::size_t(cellsX) + std::size_t(c)];
        if (south >= 0) out.worstLevelGap = std::max(out.worstLevelGap, std::abs(here - south));
      }
    }
  return out;
}

/// A cut of `hf` at `maxError` in chunks of 16 cells, its statistics, the triangles drawn and
/// their check.
struct CheckedCut {
  TerrainCutStats stats;
  std::size_t triangles = 0;         // drawn: surface and skirts
  std::size_t surfaceTriangles = 0;  // drawn surface triangles
  CutCheck check;
};
CheckedCut cutAndCheck(const terrain::Heightfield& hf, double maxError, TerrainCutOptions o = {}) {
  o.maxErrorM = maxError;
  if (!o.pyramid) o.chunkCells = 16;
  CheckedCut out;
  const osg::ref_ptr<osg::Group> cut = buildTerrainCut(hf, o, &out.stats);
  TriangleReader reader(hf);
  cut->accept(reader);
  out.triangles = reader.triangles;
  out.surfaceTriangles = reader.surface.size();
  out.check = check(hf, reader);
  return out;
}

TEST(TerrainCut, StaysWithinItsErrorAndCoversTheGridOnce) {
  // 129 x 97 samples, 1.5 m by 0.75 m cells: narrow last cells at every coarse level.
  const terrain::Heightfield hf(129, 97, test::roughHeights(129, 97, 7), kOriginX, kOriginY, 1.5, 0.75);
  std::size_t previousTriangles = 0;
  for (const double maxError : {4.0, 1.0, 0.25, 0.0}) {
    const CheckedCut cut = cutAndCheck(hf, maxError);
    const TerrainCutStats& stats = cut.stats;
    const CutCheck& c = cut.check;
    EXPECT_NEAR(c.area, 128.0 * 96.0, 1e-6) << maxError;
    EXPECT_EQ(c.uncovered, 0u) << maxError;
    EXPECT_LE(stats.maxErrorM, maxError) << maxError;
    EXPECT_LE(c.worstError, maxError + kVertexSlack) << maxError;
    EXPECT_LE(c.worstError, stats.maxErrorM + kVertexSlack) << maxError;
    EXPECT_LE(c.worstLevelGap, 3) << maxError;
    EXPECT_EQ(stats.surfaceTriangles + stats.skirtTriangles, cut.triangles) << maxError;
    EXPECT_GE(stats.surfaceTriangles, previousTriangles) << "a smaller error never draws fewer triangles";
    if (maxError == 4.0) previousTriangles = stats.surfaceTriangles;
    if (maxError == 0.0) {
      EXPECT_EQ(stats.coarsestLevel, 0);
      EXPECT_GT(stats.surfaceTriangles, previousTriangles);
      EXPECT_EQ(cut.surfaceTriangles, 2u * 128 * 96) << "the full grid";
    }
  }
}

TEST(TerrainCut, AFlatPlainBesideRoughGroundIsBalancedForTheSkirts) {
  // 513 x 513 samples in chunks of 16 cells (6 levels): the west half exactly flat (every level
  // exact), the east half rough. By error alone the plain would be drawn 5 levels coarser than the
  // ground beside it; the skirts close 3.
  const int n = 513;
  std::vector<float> heights = test::roughHeights(n, n, 3);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n / 2 + 1; ++c) heights[std::size_t(r) * n + std::size_t(c)] = 250.0f;
  const terrain::Heightfield hf(n, n, std::move(heights), kOriginX, kOriginY, 1.0, 1.0);
  const CheckedCut cut = cutAndCheck(hf, 0.5);
  const TerrainCutStats& stats = cut.stats;
  const CutCheck& c = cut.check;
  EXPECT_GT(stats.balancingRounds, 0);
  EXPECT_EQ(c.uncovered, 0u);
  EXPECT_NEAR(c.area, 512.0 * 512.0, 1e-6);
  EXPECT_LE(c.worstLevelGap, 3);
  EXPECT_LE(c.worstError, 0.5 + kVertexSlack);
  // The rough ground at level 0; the plain's west, 4 levels up (128 cells a quadrant), next to
  // regions of 64 cells beside the rough ground's 8.
  EXPECT_EQ(stats.finestLevel, 0);
  EXPECT_EQ(stats.coarsestLevel, 4);
}

TEST(TerrainCut, ChunksFromThePyramidStayWithinTheErrorAndTheShift) {
  // 577 x 449 samples written as a terrain file with its pyramid; the cut's chunks from level 1 up
  // take their samples and errors from it. The heightfield is the file's heights moved 3.5 m up,
  // as a scene loader's height shift moves them: the pyramid's pages are moved by as much.
  const int cols = 577, rows = 449;
  const std::vector<float> heights = test::roughHeights(cols, rows, 11);
  test::TempFolder dir;
  const std::string file = (dir / "rough.tif").string();
  terrain::writeTerrainCog(file, cols, rows, heights, kOriginX, kOriginY, 1.0, 1.0, "EPSG:32633", false);
  constexpr double kShift = 3.5;
  std::vector<float> shifted = heights;
  for (float& h : shifted) h = float(double(h) + kShift);
  const terrain::Heightfield hf(cols, rows, std::move(shifted), kOriginX, kOriginY, 1.0, 1.0);
  TerrainCutOptions o;
  o.pyramid = std::make_shared<const terrain::TerrainPyramid>(file);
  o.pyramidErrorsFromLevel = 1;
  o.pyramidHeightShift = kShift;
  for (const double maxError : {8.0, 3.0, 0.5}) {
    const CheckedCut cut = cutAndCheck(hf, maxError, o);
    if (maxError == 8.0) {
      EXPECT_GE(cut.stats.coarsestLevel, 1) << "chunks from the pyramid drawn";
    }
    EXPECT_NEAR(cut.check.area, double(cols - 1) * (rows - 1), 1e-6) << maxError;
    EXPECT_EQ(cut.check.uncovered, 0u) << maxError;
    EXPECT_LE(cut.stats.maxErrorM, maxError) << maxError;
    EXPECT_LE(cut.check.worstError, maxError + kVertexSlack) << maxError;
    EXPECT_LE(cut.check.worstLevelGap, 3) << maxError;
    EXPECT_EQ(cut.stats.surfaceTriangles + cut.stats.skirtTriangles, cut.triangles) << maxError;
  }
  // The coarse chunks' samples are the pyramid's: told the wrong shift, they sit 40 m off the
  // heightfield's, which the brute force sees.
  o.pyramidHeightShift = kShift + 40;
  EXPECT_GT(cutAndCheck(hf, 8.0, o).check.worstError, 30.0);
  // A pyramid of another grid is refused.
  const terrain::Heightfield smaller(cols - 1, rows, std::vector<float>(std::size_t(cols - 1) * rows, 100.0f), kOriginX,
                                     kOriginY, 1.0, 1.0);
  EXPECT_THROW(buildTerrainCut(smaller, o), std::invalid_argument);
}

TEST(TerrainCut, RefusesANegativeErrorAndABadChunkSize) {
  const terrain::Heightfield hf(33, 33, test::roughHeights(33, 33, 1), kOriginX, kOriginY, 1.0, 1.0);
  TerrainCutOptions o;
  o.maxErrorM = -1;
  EXPECT_THROW(buildTerrainCut(hf, o), std::invalid_argument);
  o.maxErrorM = 0.1;
  o.chunkCells = 12;
  EXPECT_THROW(buildTerrainCut(hf, o), std::invalid_argument);
}

}  // namespace
}  // namespace nestwalk
