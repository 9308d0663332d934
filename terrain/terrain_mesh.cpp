// Terrain meshes: tiles and levels of detail with exact errors (terrain_mesh.h).
//
// Why the maximum of |fine - coarse| over a tile is attained at fine samples:
// Level k keeps the samples (col0 + i s, row0 + j s), s = 2^k, and splits every coarse cell along
// its north-west to south-east diagonal, the same direction as the fine rule. Every coarse edge
// therefore runs along fine edges: horizontal and vertical coarse edges lie on fine grid lines, and
// the coarse diagonal from (c, r) to (c+s, r+s) is the chain of fine diagonals through the fine
// samples (c+i, r+i), each of which is a fine cell's own diagonal since the directions agree. So
// the fine triangulation refines the coarse one: every fine triangle lies inside one coarse
// triangle (the fine triangles of the coarse upper triangle are the fine cells above its diagonal
// plus the upper halves of the fine cells on it, the same for the lower). On a fine triangle both
// surfaces are linear (the fine one by construction, the coarse one because the fine triangle sits
// inside a single coarse triangle), so their difference is linear there and |difference| reaches
// its maximum over the (closed) fine triangle at one of its three vertices, which are fine samples.
// The surfaces' common domain is the union of such fine triangles, plus fine edges and isolated
// valid samples (heightfield.h counts valid edges and samples as ground), on which the same
// argument holds with segments and points. Hence the maximum over the tile equals the maximum
// over the valid fine samples that lie in an existing coarse triangle (closed), which is what
// computeLevel evaluates, exactly in double from the float heights. (With the other diagonal
// direction the coarse diagonal would cut through fine cells and the maximum could fall inside a
// fine triangle; with a step that does not divide the tile the coarse cells would not be square
// and their diagonals would not follow fine diagonals: hence the power-of-two levels per tile.)
#include "nestwalk/terrain/terrain_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace nestwalk::terrain {

TerrainGrid TerrainGrid::fromHeightfield(const Heightfield& hf) {
  TerrainGrid g;
  g.cols = hf.cols();
  g.rows = hf.rows();
  g.dx = hf.dx();
  g.dy = hf.dy();
  const std::size_t n = std::size_t(g.cols) * std::size_t(g.rows);
  g.heights.resize(n);
  g.valid.resize(n);
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      const std::size_t i = std::size_t(r) * std::size_t(g.cols) + std::size_t(c);
      g.heights[i] = hf.sample(c, r);
      g.valid[i] = hf.valid(c, r) ? 1 : 0;
    }
  return g;
}

TerrainGrid TerrainGrid::fromHeights(int cols, int rows, std::vector<float> heights, double dx, double dy,
                                     std::optional<float> noData) {
  if (cols < 2 || rows < 2 || heights.size() != std::size_t(cols) * std::size_t(rows) || !(dx > 0) || !(dy > 0))
    throw std::invalid_argument("TerrainGrid: inconsistent sizes or spacing");
  TerrainGrid g;
  g.cols = cols;
  g.rows = rows;
  g.dx = dx;
  g.dy = dy;
  g.heights = std::move(heights);
  g.valid.resize(g.heights.size());
  for (std::size_t i = 0; i < g.heights.size(); ++i) {
    const float h = g.heights[i];
    g.valid[i] = (std::isfinite(h) && !(noData && h == *noData)) ? 1 : 0;
  }
  return g;
}

double LodRule::pixelsPerRadian() const {
  return screenHeightPx / (2.0 * std::tan(0.5 * fovYDegrees * std::numbers::pi / 180.0));
}

double LodRule::distanceFor(double error) const {
  if (!(error > 0)) return 0.0;
  return error * pixelsPerRadian() / maxPixels;
}

TerrainMesh::TerrainMesh(const Heightfield& hf, TerrainMeshOptions opts)
    : TerrainMesh(TerrainGrid::fromHeightfield(hf), opts) {}

TerrainMesh::TerrainMesh(TerrainGrid grid, TerrainMeshOptions opts) : grid_(std::move(grid)), opts_(opts) {
  const int t = opts_.tileCells;
  if (t < 1 || (t & (t - 1)) != 0) throw std::invalid_argument("TerrainMesh: tileCells must be a power of two");
  if (grid_.cols < 2 || grid_.rows < 2) throw std::invalid_argument("TerrainMesh: the grid needs 2 x 2 samples");
  if (grid_.heights.size() != std::size_t(grid_.cols) * std::size_t(grid_.rows) ||
      grid_.valid.size() != grid_.heights.size())
    throw std::invalid_argument("TerrainMesh: inconsistent grid");
  build();
}

namespace {

/// Max |fine - coarse| over valid fine samples inside existing coarse triangles, and the number of
/// existing coarse triangles, for one tile level (see the comment at the top).
std::pair<double, std::size_t> computeLevel(const TerrainGrid& g, const TerrainTile& t, int level) {
  const int s = 1 << level;
  const int nx = t.cellsX / s, ny = t.cellsY / s;
  double err = 0;
  std::size_t tris = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int c = t.col0 + i * s, r = t.row0 + j * s;
      const bool va = g.isValid(c, r), vb = g.isValid(c + s, r), vc = g.isValid(c + s, r + s),
                 vd = g.isValid(c, r + s);
      const bool upper = va && vb && vc, lower = va && vc && vd;
      tris += (upper ? 1 : 0) + (lower ? 1 : 0);
      if (level == 0 || (!upper && !lower)) continue;
      const double ha = g.height(c, r), hb = g.height(c + s, r), hc = g.height(c + s, r + s), hd = g.height(c, r + s);
      const double inv = 1.0 / s;
      for (int v = 0; v <= s; ++v)
        for (int u = 0; u <= s; ++u) {
          if (!g.isValid(c + u, r + v)) continue;
          double coarse;
          if (u >= v && upper)
            coarse = ha + (u * inv) * (hb - ha) + (v * inv) * (hc - hb);
          else if (v >= u && lower)
            coarse = ha + (v * inv) * (hd - ha) + (u * inv) * (hc - hd);
          else
            continue;
          err = std::max(err, std::abs(double(g.height(c + u, r + v)) - coarse));
        }
    }
  return {err, tris};
}

int trailingLevels(int cells) {
  int l = 0;
  while ((cells % (2 << l)) == 0) ++l;
  return l;  // 2^l divides cells, 2^(l+1) does not
}

}  // namespace

void TerrainMesh::build() {
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (std::size_t k = 0; k < grid_.heights.size(); ++k)
    if (grid_.valid[k]) {
      lo = std::min(lo, grid_.heights[k]);
      hi = std::max(hi, grid_.heights[k]);
    }
  heightLo_ = lo <= hi ? lo : 0.0f;
  heightHi_ = lo <= hi ? hi : 0.0f;
  const int tc = opts_.tileCells;
  const int cellsX = grid_.cols - 1, cellsY = grid_.rows - 1;
  tilesX_ = (cellsX + tc - 1) / tc;
  tilesY_ = (cellsY + tc - 1) / tc;
  tiles_.clear();
  tiles_.reserve(std::size_t(tilesX_) * std::size_t(tilesY_));
  int maxLevels = 0;
  for (int ty = 0; ty < tilesY_; ++ty)
    for (int tx = 0; tx < tilesX_; ++tx) {
      TerrainTile t;
      t.col0 = tx * tc;
      t.row0 = ty * tc;
      t.cellsX = std::min(tc, cellsX - t.col0);
      t.cellsY = std::min(tc, cellsY - t.row0);
      t.levels = std::min(trailingLevels(t.cellsX), trailingLevels(t.cellsY)) + 1;
      if (opts_.maxLevels > 0) t.levels = std::min(t.levels, opts_.maxLevels);
      for (int k = 0; k < t.levels; ++k) {
        const auto [e, n] = computeLevel(grid_, t, k);
        t.maxError.push_back(e);
        t.triangles.push_back(n);
      }
      maxLevels = std::max(maxLevels, t.levels);
      tiles_.push_back(std::move(t));
    }
  levels_.assign(std::size_t(maxLevels), {});
  for (int k = 0; k < maxLevels; ++k) {
    levels_[std::size_t(k)].level = k;
    levels_[std::size_t(k)].step = 1 << k;
  }
  for (const TerrainTile& t : tiles_)
    for (int k = 0; k < t.levels; ++k) {
      TerrainLevelStats& row = levels_[std::size_t(k)];
      row.tiles += 1;
      row.triangles += t.triangles[std::size_t(k)];
      row.maxError = std::max(row.maxError, t.maxError[std::size_t(k)]);
    }
}

std::vector<GridTriangle> TerrainMesh::triangles(const TerrainTile& t, int level) const {
  std::vector<GridTriangle> out;
  if (level < 0 || level >= t.levels) return out;
  const int s = 1 << level;
  const int nx = t.cellsX / s, ny = t.cellsY / s;
  out.reserve(t.triangles[std::size_t(level)]);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int c = t.col0 + i * s, r = t.row0 + j * s;
      const bool va = grid_.isValid(c, r), vb = grid_.isValid(c + s, r), vc = grid_.isValid(c + s, r + s),
                 vd = grid_.isValid(c, r + s);
      if (va && vb && vc) out.push_back({{c, c + s, c + s}, {r, r, r + s}});
      if (va && vc && vd) out.push_back({{c, c + s, c}, {r, r + s, r + s}});
    }
  return out;
}

std::optional<double> TerrainMesh::heightAt(const TerrainTile& t, int level, double x, double y) const {
  if (level < 0 || level >= t.levels) return std::nullopt;
  const int s = 1 << level;
  const double fx = x / grid_.dx - t.col0, fy = -y / grid_.dy - t.row0;
  if (!(fx >= 0 && fx <= t.cellsX && fy >= 0 && fy <= t.cellsY)) return std::nullopt;
  const int nx = t.cellsX / s, ny = t.cellsY / s;
  const int i0 = std::min(int(fx / s), nx - 1), j0 = std::min(int(fy / s), ny - 1);
  // The surface is the closed union of the level's triangles: a point on the west or north border
  // of its cell also belongs to the neighbouring cell there, whose triangles may exist when this
  // cell's do not (holes).
  for (int j = j0; j >= std::max(0, j0 - 1); --j)
    for (int i = i0; i >= std::max(0, i0 - 1); --i) {
      const double u = fx / s - i, v = fy / s - j;
      if (u < 0 || u > 1 || v < 0 || v > 1) continue;
      const int c = t.col0 + i * s, r = t.row0 + j * s;
      const bool va = grid_.isValid(c, r), vb = grid_.isValid(c + s, r), vc = grid_.isValid(c + s, r + s),
                 vd = grid_.isValid(c, r + s);
      const double ha = grid_.height(c, r), hb = grid_.height(c + s, r), hc = grid_.height(c + s, r + s),
                   hd = grid_.height(c, r + s);
      if (u >= v && va && vb && vc) return ha + u * (hb - ha) + v * (hc - hb);
      if (v >= u && va && vc && vd) return ha + v * (hd - ha) + u * (hc - hd);
    }
  return std::nullopt;
}

Eigen::AlignedBox3f TerrainMesh::tileBox(const TerrainTile& t) const {
  Eigen::AlignedBox3f box;  // empty
  for (int r = t.row0; r <= t.row0 + t.cellsY; ++r)
    for (int c = t.col0; c <= t.col0 + t.cellsX; ++c)
      if (grid_.isValid(c, r)) box.extend(Eigen::Vector3f(float(c * grid_.dx), float(-r * grid_.dy), grid_.height(c, r)));
  return box;
}

std::vector<double> TerrainMesh::switchDistances(const TerrainTile& t, const LodRule& rule) const {
  const Eigen::AlignedBox3f box = tileBox(t);
  const double radius = box.isEmpty() ? 0.0 : 0.5 * double(box.diagonal().norm());
  std::vector<double> d(std::size_t(t.levels), 0.0);
  double e = 0;
  for (int k = 1; k < t.levels; ++k) {
    e = std::max(e, t.maxError[std::size_t(k)]);
    d[std::size_t(k)] = e > 0 ? rule.distanceFor(e) + radius : 0.0;
  }
  return d;
}

}  // namespace nestwalk::terrain
