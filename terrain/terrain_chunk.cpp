// Terrain chunks: the quadtree layout, a chunk's mesh with its exact error, skirts and baked
// shading (terrain_chunk.h).
//
// Why the maximum of |fine - coarse| over a chunk of square coarse cells is attained at fine samples:
// level k keeps the samples (i s, j s), s = 2^k, and splits every coarse cell along its north-west
// to south-east diagonal, the same direction as the fine rule. Every coarse edge therefore runs
// along fine edges: horizontal and vertical coarse edges lie on fine grid lines, and the coarse
// diagonal from (c, r) to (c+s, r+s) is the chain of fine diagonals through the fine samples
// (c+i, r+i), each of which is a fine cell's own diagonal since the directions agree. So the fine
// triangulation refines the coarse one: every fine triangle lies inside one coarse triangle. On a
// fine triangle both surfaces are linear, so their difference is linear there and |difference|
// reaches its maximum over the (closed) fine triangle at one of its three vertices, which are fine
// samples. The surfaces' common domain is the union of such fine triangles, plus fine edges and
// isolated valid samples (heightfield.h counts valid edges and samples as ground), on which the
// same argument holds with segments and points. Hence the maximum equals the maximum over the valid
// fine samples that lie in an existing coarse triangle (closed), evaluated exactly in double from
// the float heights. (A coarse cell that is not square, in the last column or row, has a diagonal
// that cuts through fine cells, so the maximum can fall inside a fine triangle there: cellError
// below also evaluates that diagonal's crossings with the fine edges.)
#include "nestwalk/terrain/terrain_chunk.h"

#include "nestwalk/terrain/coarse_cell_error.h"
#include "nestwalk/terrain/height_tiles.h"
#include "nestwalk/terrain/hillshade.h"
#include "nestwalk/terrain/terrain_pyramid_format.h"

#include <meshoptimizer.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <functional>
#include <map>
#include <tuple>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace nestwalk::terrain {

ChunkLayout::ChunkLayout(int cols, int rows, int chunkCells) : cols_(cols), rows_(rows), chunkCells_(chunkCells) {
  if (cols < 2 || rows < 2) throw std::invalid_argument("ChunkLayout: the grid needs 2 x 2 samples");
  if (chunkCells < 2 || (chunkCells & (chunkCells - 1)) != 0)
    throw std::invalid_argument("ChunkLayout: chunkCells must be a power of two >= 2");
  const std::int64_t cells = std::max(cols - 1, rows - 1);
  int level = 0;
  while ((std::int64_t(chunkCells) << level) < cells) ++level;
  levels_ = level + 1;
}

int ChunkLayout::chunksX(int level) const {
  const std::int64_t span = std::int64_t(chunkCells_) << level;
  return int((std::int64_t(cols_ - 1) + span - 1) / span);
}

int ChunkLayout::chunksY(int level) const {
  const std::int64_t span = std::int64_t(chunkCells_) << level;
  return int((std::int64_t(rows_ - 1) + span - 1) / span);
}

bool ChunkLayout::exists(const ChunkKey& k) const {
  return k.level >= 0 && k.level < levels_ && k.x >= 0 && k.y >= 0 && k.x < chunksX(k.level) && k.y < chunksY(k.level);
}

std::vector<ChunkKey> ChunkLayout::children(const ChunkKey& k) const {
  std::vector<ChunkKey> out;
  if (k.level == 0) return out;
  for (int b = 0; b < 2; ++b)
    for (int a = 0; a < 2; ++a) {
      const ChunkKey c{k.level - 1, 2 * k.x + a, 2 * k.y + b};
      if (exists(c)) out.push_back(c);
    }
  return out;
}

std::vector<int> ChunkLayout::kept(int first, int last, int step) const {
  std::vector<int> v;
  for (std::int64_t i = first; i < last; i += step) v.push_back(int(i));
  v.push_back(last);
  return v;
}

std::vector<int> ChunkLayout::columns(const ChunkKey& k) const {
  const std::int64_t span = std::int64_t(chunkCells_) << k.level;
  const std::int64_t first = k.x * span;
  return kept(int(first), int(std::min<std::int64_t>(first + span, cols_ - 1)), 1 << k.level);
}

std::vector<int> ChunkLayout::rowsOf(const ChunkKey& k) const {
  const std::int64_t span = std::int64_t(chunkCells_) << k.level;
  const std::int64_t first = k.y * span;
  return kept(int(first), int(std::min<std::int64_t>(first + span, rows_ - 1)), 1 << k.level);
}

Eigen::Vector3d terrainRampColour(double h, double lo, double hi) {
  const double f = std::clamp((h - lo) / (hi > lo ? hi - lo : 1.0), 0.0, 1.0);
  const Eigen::Vector3d green(0.25, 0.45, 0.2), brown(0.5, 0.4, 0.3), white(0.95, 0.95, 0.95);
  return f < 0.6 ? Eigen::Vector3d(green * (1 - f / 0.6) + brown * (f / 0.6))
                 : Eigen::Vector3d(brown * (1 - (f - 0.6) / 0.4) + white * ((f - 0.6) / 0.4));
}

namespace {

/// Adds triangle (a, b, c)'s upward normal, of length twice its area, to the block's sum.
void addNormal(ChunkBlock& block, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d n = (b - a).cross(c - a);
  block.normalSum += n.z() < 0 ? Eigen::Vector3d(-n) : n;
}

std::uint8_t toByte(double v) { return std::uint8_t(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); }

/// Texels of holes (index -1) take a valid neighbour's colour, spreading ring by ring, so that no
/// triangle's bilinear lookup near a hole blends towards black; a chunk without valid samples stays
/// black (it draws nothing).
void fillHoleTexels(std::vector<std::uint8_t>& texture, std::size_t w, std::size_t h, const std::vector<std::int32_t>& index) {
  std::vector<char> known(w * h);
  bool any = false;
  for (std::size_t k = 0; k < w * h; ++k) {
    known[k] = index[k] >= 0;
    any = any || !known[k];
  }
  while (any) {
    any = false;
    std::vector<char> next = known;
    for (std::size_t y = 0; y < h; ++y)
      for (std::size_t x = 0; x < w; ++x) {
        if (known[y * w + x]) continue;
        for (const auto& [ox, oy] : {std::pair(-1, 0), std::pair(1, 0), std::pair(0, -1), std::pair(0, 1)}) {
          const std::ptrdiff_t nx = std::ptrdiff_t(x) + ox, ny = std::ptrdiff_t(y) + oy;
          if (nx < 0 || ny < 0 || nx >= std::ptrdiff_t(w) || ny >= std::ptrdiff_t(h) || !known[std::size_t(ny) * w + std::size_t(nx)])
            continue;
          std::copy_n(&texture[4 * (std::size_t(ny) * w + std::size_t(nx))], 4, &texture[4 * (y * w + x)]);
          next[y * w + x] = 1;
          any = true;
          break;
        }
      }
    known.swap(next);
  }
}

/// A paged chunk's fine window is copied when it holds at most this many samples (4 MiB of floats):
/// levels 0 to 3 of 64-cell chunks (level 3: 513 x 513), the finest, which read every fine sample
/// under them (coarser ones take their errors from the pyramid: kPyramidErrorsFromLevel, paged_terrain.h);
/// level 4's 1025 x 1025 is over it.
constexpr std::size_t kFineWindowSamples = std::size_t(1) << 20;

/// The fine samples a chunk's error passes read, each several times: the heightfield's own when it
/// is resident; when it is paged, the chunk's closed fine window [c0, c1] x [r0, r1] copied once,
/// tile by tile (holes NaN, as valid() sees them), so the reads do not each look up a tile. Samples
/// outside the window come from the heightfield. The `Fine` grid of coarse_cell_error.h.
class FineSamples {
 public:
  FineSamples(const Heightfield& hf, int c0, int r0, int c1, int r1) : hf_(hf) {
    const std::size_t w = std::size_t(c1 - c0 + 1), h = std::size_t(r1 - r0 + 1);
    if (!hf.paged() || w * h > kFineWindowSamples) return;
    c0_ = c0;
    r0_ = r0;
    w_ = int(w);
    h_ = int(h);
    // The thread's buffer, reused: a fresh window of up to kFineWindowSamples floats would be zeroed
    // and faulted in page by page for every chunk, only to be overwritten. One FineSamples lives
    // on a thread at a time (buildChunk makes one and does not recurse).
    thread_local std::vector<float> buffer;
    if (buffer.size() < w * h) buffer.resize(w * h);
    window_ = buffer.data();
    // From the tiles that hold the window's cells: a tile holds its closing column and row
    // (height_tiles.h), so a window aligned on tiles, as a chunk of levels 1 to 3 is, reads only
    // the tiles under its cells, not a ring of neighbours for its last row and column (a level-3
    // chunk: 4 tiles instead of 9).
    const HeightTileCache& tiles = *hf.tiles();
    const std::optional<float> noData = hf.noData();
    for (int r = r0; r <= r1; ++r) {
      const int ty = std::min((r > r0 && r % kHeightTileCells == 0 ? r - 1 : r) / kHeightTileCells, tiles.tilesY() - 1);
      for (int c = c0; c <= c1;) {
        const int tx = std::min(c / kHeightTileCells, tiles.tilesX() - 1);
        const int last = tx == tiles.tilesX() - 1 ? c1 : std::min(c1, (tx + 1) * kHeightTileCells);
        const float* from = tiles.threadTile(tx, ty).at(c, r);
        float* to = &window_[std::size_t(r - r0) * w + std::size_t(c - c0)];
        for (int k = 0; k <= last - c; ++k)
          to[k] = std::isfinite(from[k]) && !(noData && from[k] == *noData) ? from[k] : std::numeric_limits<float>::quiet_NaN();
        c = last + 1;
      }
    }
  }
  bool valid(int c, int r) const {
    if (const float* p = find(c, r)) return !std::isnan(*p);
    return hf_.valid(c, r);
  }
  double height(int c, int r) const {
    if (const float* p = find(c, r)) return *p;
    return hf_.sample(c, r);
  }
  float sampleOrNaN(int c, int r) const {
    if (const float* p = find(c, r)) return *p;
    return hf_.valid(c, r) ? hf_.sample(c, r) : std::numeric_limits<float>::quiet_NaN();
  }

 private:
  const float* find(int c, int r) const {
    const unsigned dc = unsigned(c - c0_), dr = unsigned(r - r0_);
    return dc < unsigned(w_) && dr < unsigned(h_) ? &window_[std::size_t(dr) * std::size_t(w_) + dc] : nullptr;
  }
  const Heightfield& hf_;
  int c0_ = 0, r0_ = 0, w_ = 0, h_ = 0;  // no window: w_ = 0
  float* window_ = nullptr;  // the constructing thread's buffer (w_ x h_ samples)
};

/// The kept samples of one chunk and which coarse triangles exist: read from the heightfield, or
/// from the pyramid's level page (ChunkPyramidData::heights) when given.
struct ChunkGrid {
  const Heightfield& hf;
  std::vector<int> cols, rows;
  const ChunkPyramidData* level = nullptr;  // its heights cover the kept samples (checked by buildChunk)
  const FineSamples* fine = nullptr;         // the fine reads (null: the heightfield's)
  bool fineValid(int c, int r) const { return fine ? fine->valid(c, r) : hf.valid(c, r); }
  double fineHeight(int c, int r) const { return fine ? fine->height(c, r) : hf.sample(c, r); }
  /// Fine sample (c, r), NaN for a hole: one look-up where fineValid and fineHeight take two.
  float fineSampleOrNaN(int c, int r) const {
    if (fine) return fine->sampleOrNaN(c, r);
    return hf.valid(c, r) ? hf.sample(c, r) : std::numeric_limits<float>::quiet_NaN();
  }
  int step = 1, levelCol0 = 0, levelRow0 = 0;  // the level's column and row of kept sample (0, 0)
  std::size_t nc() const { return cols.size(); }
  std::size_t nr() const { return rows.size(); }
  float fromLevel(int li, int lj) const {
    return level->heights[std::size_t(lj - level->y0) * std::size_t(level->width) + std::size_t(li - level->x0)];
  }
  bool valid(std::size_t i, std::size_t j) const {
    return level ? !std::isnan(fromLevel(levelCol0 + int(i), levelRow0 + int(j))) : fineValid(cols[i], rows[j]);
  }
  double height(std::size_t i, std::size_t j) const {
    return level ? fromLevel(levelCol0 + int(i), levelRow0 + int(j)) : fineHeight(cols[i], rows[j]);
  }
  /// Fine sample (c, r), NaN for a hole: from the level page where it is one of the level's samples
  /// inside it, else from the heightfield.
  float sampleOrNaN(int c, int r) const {
    if (level) {
      const bool onC = c % step == 0 || c == hf.cols() - 1, onR = r % step == 0 || r == hf.rows() - 1;
      const int li = c == hf.cols() - 1 ? (c - 1) / step + 1 : c / step, lj = r == hf.rows() - 1 ? (r - 1) / step + 1 : r / step;
      if (onC && onR && li >= level->x0 && li < level->x0 + level->width && lj >= level->y0 && lj < level->y0 + level->height)
        return fromLevel(li, lj);
    }
    return fineValid(c, r) ? float(fineHeight(c, r)) : std::numeric_limits<float>::quiet_NaN();
  }
  bool upper(std::size_t i, std::size_t j) const { return valid(i, j) && valid(i + 1, j) && valid(i + 1, j + 1); }
  bool lower(std::size_t i, std::size_t j) const { return valid(i, j) && valid(i + 1, j + 1) && valid(i, j + 1); }
};

/// Max |fine - coarse| over one coarse cell (i, j) of the chunk (coarse_cell_error.h).
double cellError(const ChunkGrid& g, std::size_t i, std::size_t j) {
  if (g.fine) return coarseCellError(*g.fine, g.cols[i], g.rows[j], g.cols[i + 1], g.rows[j + 1]);
  return coarseCellError(HeightfieldGrid{g.hf}, g.cols[i], g.rows[j], g.cols[i + 1], g.rows[j + 1]);
}

/// A quadrant's surface simplified within some error: its triangles (indices into the chunk's
/// vertices), its blocks and their largest error, metres.
struct SimplifiedSurface {
  std::vector<std::uint32_t> indices;
  std::vector<ChunkBlock> blocks;
  double maxError = 0;
  /// meshoptimizer's own measure of the error it reached (metres, its quadric estimate, not exact):
  /// a target above it gives the same surface again.
  double reachedM = 0;
};

/// A surface triangle of a simplified quadrant, by fine sample (column, row) of each vertex.
struct FineTriangle {
  std::array<std::array<int, 2>, 3> v;  // (column, row)
  std::array<double, 3> h;              // heights
};

/// The plane through three corners in fine (column, row) coordinates with heights h:
/// h(col, row) = h0 + gc (col - c0) + gr (row - r0); nullopt for corners on one line.
struct GridPlane {
  double h0, c0, r0, gc, gr;
  double at(double col, double row) const { return h0 + gc * (col - c0) + gr * (row - r0); }
};
std::optional<GridPlane> planeThrough(const std::array<Eigen::Vector2d, 3>& v, const std::array<double, 3>& h) {
  const Eigen::Vector2d e1 = v[1] - v[0], e2 = v[2] - v[0];
  const double det = e1.x() * e2.y() - e2.x() * e1.y();
  if (det == 0) return std::nullopt;
  const double d1 = h[1] - h[0], d2 = h[2] - h[0];
  return GridPlane{h[0], v[0].x(), v[0].y(), (d1 * e2.y() - d2 * e1.y()) / det, (e1.x() * d2 - e2.x() * d1) / det};
}

/// Max |fine - plane| over one triangle whose corners are fine samples: the difference is linear on
/// every piece of the triangle cut by the fine triangulation, so its largest value lies at a fine
/// sample inside the triangle (found with exact integer edge tests) or where one of its edges crosses
/// a fine column, row or diagonal (terrain_chunk.h, "Simplification").
double triangleError(const ChunkGrid& g, const FineTriangle& t) {
  // Named corners, not a structured binding: clang 14 (the sanitizer builds) cannot capture those.
  const std::array<int, 2>& a = t.v[0];
  const std::array<int, 2>& b = t.v[1];
  const std::array<int, 2>& c = t.v[2];
  const std::optional<GridPlane> p =
      planeThrough({Eigen::Vector2d(a[0], a[1]), Eigen::Vector2d(b[0], b[1]), Eigen::Vector2d(c[0], c[1])}, t.h);
  if (!p) return 0.0;
  auto plane = [&](double col, double row) { return p->at(col, row); };
  double err = 0;
  // Fine samples inside (closed): the three edge functions share the sign of the orientation.
  const std::int64_t orient =
      std::int64_t(b[0] - a[0]) * (c[1] - a[1]) - std::int64_t(c[0] - a[0]) * (b[1] - a[1]) > 0 ? 1 : -1;
  const int cMin = std::min({a[0], b[0], c[0]}), cMax = std::max({a[0], b[0], c[0]});
  const int rMin = std::min({a[1], b[1], c[1]}), rMax = std::max({a[1], b[1], c[1]});
  // Row by row, the columns where orient * edge >= 0 for all three edges, edge(from, to) being
  // (to - from) x (sample - from): on a row that is coef * col + rest, so its columns are a
  // half-line bounded exactly by an integer division (the samples a test of each would keep).
  auto floorDiv = [](std::int64_t n, std::int64_t d) { return n / d - (n % d != 0 && n < 0 ? 1 : 0); };  // d > 0
  for (int row = rMin; row <= rMax; ++row) {
    std::int64_t lo = cMin, hi = cMax;
    for (const auto& [from, to] : {std::pair(&a, &b), std::pair(&b, &c), std::pair(&c, &a)}) {
      const std::int64_t dc = (*to)[0] - (*from)[0], dr = (*to)[1] - (*from)[1];
      const std::int64_t coef = -orient * dr, rest = orient * (dc * (row - (*from)[1]) + dr * (*from)[0]);
      if (coef > 0) lo = std::max(lo, -floorDiv(rest, coef));  // col >= ceil(-rest / coef)
      else if (coef < 0) hi = std::min(hi, floorDiv(rest, -coef));
      else if (rest < 0) hi = lo - 1;
    }
    for (std::int64_t k = lo; k <= hi; ++k) {
      const int col = int(k);
      const float h = g.fineSampleOrNaN(col, row);
      if (!std::isnan(h)) err = std::max(err, std::abs(double(h) - plane(col, row)));
    }
  }
  // Edge crossings with fine columns (col = k), rows (row = k) and diagonals (col - row = k). Along
  // each of those lines the fine surface is linear between the line's two samples around the
  // crossing, read from the fine samples (no map position, no tile lookup); a point of a line has
  // ground where both samples are valid, at a sample where it is (as Heightfield::groundHeight).
  auto onLine = [&](int c0, int r0, int dc, int dr, double f, double col, double row) {
    if (!g.fineValid(c0, r0)) return;
    const double h0 = g.fineHeight(c0, r0);
    double fine = h0;
    if (f > 0) {
      if (!g.fineValid(c0 + dc, r0 + dr)) return;
      fine = h0 + f * (g.fineHeight(c0 + dc, r0 + dr) - h0);
    }
    err = std::max(err, std::abs(fine - plane(col, row)));
  };
  for (const auto& [p, q] : {std::pair(a, b), std::pair(b, c), std::pair(c, a)}) {
    const double dcol = q[0] - p[0], drow = q[1] - p[1];
    for (int k = std::min(p[0], q[0]) + 1; k < std::max(p[0], q[0]); ++k) {  // columns
      const double row = p[1] + (k - p[0]) / dcol * drow, r0 = std::floor(row);
      onLine(k, int(r0), 0, 1, row - r0, k, row);
    }
    for (int k = std::min(p[1], q[1]) + 1; k < std::max(p[1], q[1]); ++k) {  // rows
      const double col = p[0] + (k - p[1]) / drow * dcol, c0 = std::floor(col);
      onLine(int(c0), k, 1, 0, col - c0, col, k);
    }
    const int d0 = p[0] - p[1], d1 = q[0] - q[1];
    for (int k = std::min(d0, d1) + 1; k < std::max(d0, d1); ++k) {  // diagonals: (c, r) to (c + 1, r + 1)
      const double col = p[0] + double(k - d0) / (d1 - d0) * dcol, c0 = std::floor(col);
      onLine(int(c0), int(c0) - k, 1, 1, col - c0, col, col - k);
    }
  }
  return err;
}

/// A clipped piece of less area than this (squared fine cells, its corners taken relative to its
/// first) is taken to have none, the two triangles only touching: far above the clipping's rounding
/// (1e-16 of coordinates up to 1e6 cells, times pieces up to 1e3 cells long: 1e-7), and a real piece
/// that thin lies within 1e-6 cells of its neighbours, whose corners bound it to the nanometre.
constexpr double kNoAreaCells2 = 1e-6;

/// A level triangle's corner bound of its share of triangleErrorBound is compared with this margin,
/// metres: a clipped corner's |level - plane| exceeds the corners' largest by roundings alone (about
/// 1e-13 m at heights of 1e3 m), so a share this far below the bound so far cannot raise it.
constexpr double kBoundRoundingM = 1e-9;

/// A bound of max |fine - plane| over a simplified triangle of a coarse chunk that reads no fine
/// sample (terrain_chunk.h, "Errors from the pyramid"): over each piece of the triangle cut by the
/// level grid's triangles, |fine - plane| <= |fine - level| + |level - plane|; the first is at most
/// the piece's block error, the second is linear on the piece and largest at one of its corners
/// (the level triangle clipped to the simplified one, in fine (column, row) coordinates).
template <class GridError>
double triangleErrorBound(const ChunkGrid& g, const FineTriangle& t, const GridError& gridErrorOf) {
  using P2 = Eigen::Vector2d;
  const std::array<P2, 3> tv = {P2(t.v[0][0], t.v[0][1]), P2(t.v[1][0], t.v[1][1]), P2(t.v[2][0], t.v[2][1])};
  const double area = (tv[1] - tv[0]).x() * (tv[2] - tv[0]).y() - (tv[1] - tv[0]).y() * (tv[2] - tv[0]).x();
  if (area == 0) return 0.0;
  const GridPlane plane = *planeThrough(tv, t.h);  // area != 0
  // Inside the simplified triangle: on the inner side of all three edges (orientation by `area`).
  auto side = [&](const P2& a, const P2& b, const P2& p) {
    const double s = (b - a).x() * (p - a).y() - (b - a).y() * (p - a).x();
    return area > 0 ? s : -s;
  };
  // The level cells the triangle's box overlaps.
  auto range = [](const std::vector<int>& kept, double lo, double hi) {
    const std::size_t a = std::size_t(std::upper_bound(kept.begin(), kept.end(), int(std::floor(lo))) - kept.begin());
    const std::size_t b = std::size_t(std::lower_bound(kept.begin(), kept.end(), int(std::ceil(hi))) - kept.begin());
    return std::pair<std::size_t, std::size_t>(a > 0 ? a - 1 : 0, std::min(b, kept.size() - 1));
  };
  const auto [ia, ib] = range(g.cols, std::min({tv[0].x(), tv[1].x(), tv[2].x()}), std::max({tv[0].x(), tv[1].x(), tv[2].x()}));
  const auto [ja, jb] = range(g.rows, std::min({tv[0].y(), tv[1].y(), tv[2].y()}), std::max({tv[0].y(), tv[1].y(), tv[2].y()}));
  // A level triangle's share is its corners' largest |level - plane| plus its cell's error when it
  // lies inside the simplified triangle (the clipping would keep it whole), nothing when its corners
  // all lie outside one edge (it would keep nothing: the corners' sides are exact integers), and at
  // most that when it straddles an edge (the difference is linear on it, and a clipped piece lies
  // inside it). The straddling ones are clipped from the largest such share down, and once a share
  // cannot exceed the bound so far by more than kBoundRoundingM the rest cannot raise it: the
  // bound is the one every level triangle clipped would give, bit for bit.
  struct LevelTriangle {
    double share;
    std::size_t i, j;
    int half;
  };
  // Scratch kept by the thread: a chunk calls this for each of its thousands of triangles.
  thread_local std::vector<LevelTriangle> straddling;
  thread_local std::vector<P2> poly, next;
  straddling.clear();
  auto corners = [&](std::size_t i, std::size_t j, int half, std::array<P2, 3>& lv, std::array<double, 3>& lh) {
    const std::array<std::size_t, 3> ci = half == 0 ? std::array<std::size_t, 3>{i, i + 1, i + 1}
                                                     : std::array<std::size_t, 3>{i, i + 1, i};
    const std::array<std::size_t, 3> cj = half == 0 ? std::array<std::size_t, 3>{j, j, j + 1}
                                                     : std::array<std::size_t, 3>{j, j + 1, j + 1};
    for (std::size_t k = 0; k < 3; ++k) {
      lv[k] = P2(g.cols[ci[k]], g.rows[cj[k]]);
      lh[k] = g.height(ci[k], cj[k]);
    }
  };
  double bound = 0;
  for (std::size_t j = ja; j < jb; ++j)
    for (std::size_t i = ia; i < ib; ++i)
      for (int half = 0; half < 2; ++half) {
        if (half == 0 ? !g.upper(i, j) : !g.lower(i, j)) continue;
        std::array<P2, 3> lv;
        std::array<double, 3> lh;
        corners(i, j, half, lv, lh);
        bool inside = true, outside = false;
        for (std::size_t e = 0; e < 3; ++e) {
          int in = 0;
          for (const P2& p : lv) in += side(tv[e], tv[(e + 1) % 3], p) >= 0 ? 1 : 0;
          inside = inside && in == 3;
          outside = outside || in == 0;
        }
        if (outside) continue;
        const GridPlane level = *planeThrough(lv, lh);  // a level cell's triangle is never flat
        double worst = 0;
        for (const P2& p : lv) worst = std::max(worst, std::abs(level.at(p.x(), p.y()) - plane.at(p.x(), p.y())));
        if (inside) bound = std::max(bound, worst + gridErrorOf(i, j));
        else straddling.push_back({worst + gridErrorOf(i, j), i, j, half});
      }
  std::sort(straddling.begin(), straddling.end(),
            [](const LevelTriangle& x, const LevelTriangle& y) { return x.share > y.share; });
  for (const LevelTriangle& c : straddling) {
    if (c.share + kBoundRoundingM <= bound) break;
    std::array<P2, 3> lv;
    std::array<double, 3> lh;
    corners(c.i, c.j, c.half, lv, lh);
    // Sutherland-Hodgman: the level triangle clipped by the simplified one's three edges.
    poly.assign(lv.begin(), lv.end());
    for (int e = 0; e < 3 && !poly.empty(); ++e) {
      const P2& a = tv[std::size_t(e)];
      const P2& b = tv[std::size_t((e + 1) % 3)];
      next.clear();
      for (std::size_t k = 0; k < poly.size(); ++k) {
        const P2& p = poly[k];
        const P2& q = poly[(k + 1) % poly.size()];
        const double sp = side(a, b, p), sq = side(a, b, q);
        if (sp >= 0) next.push_back(p);
        if ((sp > 0 && sq < 0) || (sp < 0 && sq > 0)) next.push_back(p + (q - p) * (sp / (sp - sq)));
      }
      poly.swap(next);
    }
    // A piece of no area (the triangles only touch) holds no point its neighbours do not.
    double twiceArea = 0;
    for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
      const P2 p = poly[k] - poly[0], q = poly[k + 1] - poly[0];
      twiceArea += p.x() * q.y() - q.x() * p.y();
    }
    if (poly.size() < 3 || std::abs(twiceArea) <= 2 * kNoAreaCells2) continue;
    const GridPlane level = *planeThrough(lv, lh);
    double worst = 0;
    for (const P2& p : poly) worst = std::max(worst, std::abs(level.at(p.x(), p.y()) - plane.at(p.x(), p.y())));
    bound = std::max(bound, worst + gridErrorOf(c.i, c.j));
  }
  return bound;
}

}  // namespace

ChunkMesh buildChunk(const Heightfield& hf, const ChunkLayout& layout, const ChunkKey& key, const ChunkShading& shading,
                     double simplifyFraction, const ChunkPyramidData* fromPyramid) {
  if (layout.cols() != hf.cols() || layout.rows() != hf.rows() || !layout.exists(key))
    throw std::invalid_argument("buildChunk: the chunk is not in the heightfield's layout");
  ChunkMesh m;
  m.key = key;
  ChunkGrid g{hf, layout.columns(key), layout.rowsOf(key)};
  g.step = 1 << key.level;
  g.levelCol0 = key.x * layout.chunkCells();
  g.levelRow0 = key.y * layout.chunkCells();
  // The pyramid's errors of the level grid's blocks (null: evaluated at the fine samples).
  const ChunkPyramidData* gridErrors = fromPyramid && !fromPyramid->error.empty() ? fromPyramid : nullptr;
  if (fromPyramid && key.level > 0 && !fromPyramid->heights.empty()) {
    const ChunkPyramidData& d = *fromPyramid;
    if (d.heights.size() != std::size_t(d.width) * std::size_t(d.height) || d.x0 > g.levelCol0 || d.y0 > g.levelRow0 ||
        d.x0 + d.width < g.levelCol0 + int(g.nc()) || d.y0 + d.height < g.levelRow0 + int(g.nr()) ||
        d.blockLow.size() != std::size_t(d.blockWidth) * std::size_t(d.blockHeight))
      throw std::invalid_argument("buildChunk: the pyramid's samples do not cover the chunk");
    g.level = &d;
  }
  // Without the pyramid's errors the error passes read every fine sample under the chunk.
  std::optional<FineSamples> fine;
  if (!(gridErrors && g.level) && hf.paged())
    g.fine = &fine.emplace(hf, g.cols.front(), g.rows.front(), g.cols.back(), g.rows.back());
  const std::size_t blockCells = std::size_t(chunkBlockCells(layout));
  if (gridErrors &&
      (gridErrors->blocksX != int((g.nc() - 1 + blockCells - 1) / blockCells) ||
       gridErrors->blocksY != int((g.nr() - 1 + blockCells - 1) / blockCells) ||
       gridErrors->error.size() != std::size_t(gridErrors->blocksX) * std::size_t(gridErrors->blocksY)))
    throw std::invalid_argument("buildChunk: the grid errors are not the chunk's blocks");
  // The level grid's error at chunk cell (i, j): its block's, as given.
  auto gridErrorOf = [&](std::size_t i, std::size_t j) {
    return double(gridErrors->error[(j / blockCells) * std::size_t(gridErrors->blocksX) + i / blockCells]);
  };
  const std::size_t nc = g.nc(), nr = g.nr();
  const int step = 1 << key.level;
  const double dx = hf.dx(), dy = hf.dy();
  const int c0 = g.cols.front(), r0 = g.rows.front();
  m.offset = {c0 * dx, -r0 * dy, 0.0};
  constexpr double kInf = std::numeric_limits<double>::infinity();
  m.surfaceMin = m.boxMin = Eigen::Vector3d::Constant(kInf);
  m.surfaceMax = m.boxMax = Eigen::Vector3d::Constant(-kInf);

  // Base colours: the imagery on the level's regular grid (the last, irregular column or row blended
  // between the two regular ones around it), over the height ramp where the imagery is transparent.
  std::vector<std::uint8_t> image;
  if (shading.imagery && shading.baseColours) {
    image = shading.imagery(shading.mapOrigin.x() + c0 * dx, shading.mapOrigin.y() - r0 * dy, step * dx, step * dy,
                            int(nc), int(nr));
    if (image.size() != nc * nr * 4) image.clear();
  }
  auto imageAt = [&](std::size_t i, std::size_t j) -> Eigen::Vector4d {
    // Regular position of kept column i is c0 + i step; the last kept one may lie before it.
    auto coord = [&](const std::vector<int>& kept, std::size_t i, int first) {
      const double f = double(kept[i] - first) / step;
      const std::size_t lo = std::min(std::size_t(f), kept.size() - 1);
      return std::pair<std::size_t, double>(lo, f - double(lo));
    };
    const auto [ci, fx] = coord(g.cols, i, c0);
    const auto [rj, fy] = coord(g.rows, j, r0);
    Eigen::Vector4d acc = Eigen::Vector4d::Zero();
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a) {
        const double wgt = (a ? fx : 1 - fx) * (b ? fy : 1 - fy);
        if (wgt == 0) continue;
        const std::size_t x = std::min(ci + a, nc - 1), y = std::min(rj + b, nr - 1);
        const std::uint8_t* p = &image[(y * nc + x) * 4];
        acc += wgt * Eigen::Vector4d(p[0], p[1], p[2], p[3]) / 255.0;
      }
    return acc;
  };
  const double lo = shading.heightLo, hi = shading.heightHi;

  std::vector<std::int32_t> index(nc * nr, -1);
  std::vector<std::array<int, 2>> fineOf;  // surface vertex -> its fine (column, row)
  m.textureWidth = int(nc);
  m.textureHeight = int(nr);
  m.texture.assign(nc * nr * 4, 0);
  for (std::size_t j = 0; j < nr; ++j)
    for (std::size_t i = 0; i < nc; ++i) {
      if (!g.valid(i, j)) continue;
      const int c = g.cols[i], r = g.rows[j];
      const Eigen::Vector3d p(c * dx, -r * dy, g.height(i, j));
      index[j * nc + i] = std::int32_t(m.positions.size() / 3);
      fineOf.push_back({c, r});
      for (int k = 0; k < 3; ++k) m.positions.push_back(float(p[k] - m.offset[k]));
      m.surfaceMin = m.surfaceMin.cwiseMin(p);
      m.surfaceMax = m.surfaceMax.cwiseMax(p);
      Eigen::Vector3d colour = shading.baseColours ? terrainRampColour(p.z(), lo, hi) : Eigen::Vector3d::Ones();
      if (!image.empty()) {
        const Eigen::Vector4d im = imageAt(i, j);
        colour = im.w() * im.head<3>() + (1 - im.w()) * colour;
      }
      if (shading.shade) {
        // Horn's neighbours are the level's own samples: one off its lattice (step - 1 or fewer
        // samples from the grid's irregular last column or row) counts as missing, as one beyond
        // the grid does.
        const double shade = hornShadeOf(
            [&](int sc, int sr) {
              const bool onLattice = (sc % step == 0 || sc == hf.cols() - 1) && (sr % step == 0 || sr == hf.rows() - 1);
              return onLattice ? g.sampleOrNaN(sc, sr) : std::numeric_limits<float>::quiet_NaN();
            },
            hf.cols(), hf.rows(), dx, dy, c, r, shading.sun, step);
        colour *= std::min(1.0, kAmbientLight + kSunLight * shade);
      }
      for (int k = 0; k < 3; ++k) m.colours.push_back(toByte(colour[k]));
      m.colours.push_back(255);
      std::copy(m.colours.end() - 4, m.colours.end(), m.texture.begin() + std::ptrdiff_t(4 * (j * nc + i)));
      m.texCoords.push_back(float((double(i) + 0.5) / double(nc)));
      m.texCoords.push_back(float((double(j) + 0.5) / double(nr)));
    }
  m.surfaceVertices = m.positions.size() / 3;
  fillHoleTexels(m.texture, nc, nr, index);
  auto vertex = [&](std::size_t i, std::size_t j) { return std::uint32_t(index[j * nc + i]); };

  // Skirts (terrain_chunk.h, "Cracks") hang from a kept grid line in spans of at most
  // kSkirtSpanSegments segments, aligned on the line's kept samples. Each vertex has a lowest point:
  // the lowest fine sample of its line within reach of its two segments. A span's two bottoms lie
  // under its ends, each at the least lowest point of the vertices of the aligned spans around it
  // (less kSkirtMarginM), so the bottom line between them lies below every lowest point of the span
  // and the skirt reaches at least as deep as one bottom per vertex would. Bottoms are shared by the
  // skirts that hang from one line (the two quadrants' midline skirts on either side of a midline,
  // and neighbouring quadrants' edges at the kept sample between them).
  const int reach = kSkirtReachSteps * step;
  std::map<std::tuple<bool, std::size_t, std::size_t>, std::uint32_t> bottoms;
  // Kept sample k of the kept row (alongRow) or column `line`.
  auto keptAt = [&](bool alongRow, std::size_t line, std::size_t k) {
    return alongRow ? std::pair(k, line) : std::pair(line, k);
  };
  std::map<std::tuple<bool, std::size_t, std::size_t>, double> lowests;
  auto lowestOf = [&](bool alongRow, std::size_t line, std::size_t k) -> double {
    const auto key = std::tuple(alongRow, line, k);
    if (const auto it = lowests.find(key); it != lowests.end()) return it->second;
    const std::vector<int>& along = alongRow ? g.cols : g.rows;
    const int fineLine = alongRow ? g.rows[line] : g.cols[line];
    const int lineEnd = (alongRow ? hf.cols() : hf.rows()) - 1;
    const int from = std::max(0, along[k > 0 ? k - 1 : k] - reach);
    const int to = std::min(lineEnd, along[k + 1 < along.size() ? k + 1 : k] + reach);
    const auto [ki, kj] = keptAt(alongRow, line, k);
    double lowest = g.height(ki, kj);
    if (g.level) {
      // The pyramid's blocks (kPyramidBlockCells level cells a side) holding the line from `from` to
      // `to`: their lowest samples are at or below the line's.
      const ChunkPyramidData& d = *g.level;
      const int span = kPyramidBlockCells * step;  // fine samples a side of a level block
      const int blocksAlong = alongRow ? d.blockX0 + d.blockWidth : d.blockY0 + d.blockHeight;
      const int across = fineLine / span - (fineLine == (alongRow ? hf.rows() : hf.cols()) - 1 && fineLine % span == 0 ? 1 : 0);
      const int b0 = from / span, b1 = std::min(to / span, blocksAlong - 1);
      const int a0 = alongRow ? d.blockY0 : d.blockX0, a1 = a0 + (alongRow ? d.blockHeight : d.blockWidth);
      const int f0 = alongRow ? d.blockX0 : d.blockY0;
      if (across < a0 || across >= a1 || b0 < f0)
        throw std::invalid_argument("buildChunk: the pyramid's blocks do not cover a skirt's reach");
      for (int b = b0; b <= b1; ++b) {
        const int bx = alongRow ? b : across, by = alongRow ? across : b;
        const float low = d.blockLow[std::size_t(by - d.blockY0) * std::size_t(d.blockWidth) + std::size_t(bx - d.blockX0)];
        if (!std::isnan(low)) lowest = std::min(lowest, double(low));
      }
    } else {
      for (int p = from; p <= to; ++p) {
        const int c = alongRow ? p : fineLine, r = alongRow ? fineLine : p;
        if (g.fineValid(c, r)) lowest = std::min(lowest, g.fineHeight(c, r));
      }
    }
    lowests.emplace(key, lowest);
    return lowest;
  };
  auto bottomOf = [&](bool alongRow, std::size_t line, std::size_t k) -> std::uint32_t {
    const auto key = std::tuple(alongRow, line, k);
    if (const auto it = bottoms.find(key); it != bottoms.end()) return it->second;
    const std::size_t span = kSkirtSpanSegments, last = (alongRow ? nc : nr) - 1;
    const std::size_t from = k % span == 0 ? (k >= span ? k - span : 0) : k - k % span;
    const std::size_t to = std::min(last, k % span == 0 ? k + span : from + span);
    double lowest = kInf;
    for (std::size_t v = from; v <= to; ++v) {
      const auto [vi, vj] = keptAt(alongRow, line, v);
      if (g.valid(vi, vj)) lowest = std::min(lowest, lowestOf(alongRow, line, v));
    }
    const auto [ki, kj] = keptAt(alongRow, line, k);
    const std::uint32_t top = vertex(ki, kj);
    const Eigen::Vector3d q(m.positions[3 * top] + m.offset.x(), m.positions[3 * top + 1] + m.offset.y(),
                            lowest - kSkirtMarginM);
    const auto v = std::uint32_t(m.positions.size() / 3);
    for (int i = 0; i < 3; ++i) m.positions.push_back(float(q[i] - m.offset[i]));
    for (int i = 0; i < 4; ++i) m.colours.push_back(m.colours[4 * top + i]);
    for (int i = 0; i < 2; ++i) m.texCoords.push_back(m.texCoords[2 * top + i]);
    m.boxMin = m.boxMin.cwiseMin(q);
    bottoms.emplace(key, v);
    return v;
  };
  auto pos = [&](std::uint32_t v) {
    return Eigen::Vector3d(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]);
  };
  // A skirt along kept line `line` over kept samples [k0, k1], facing `out`, on the segments whose
  // inner triangle exists: each run of such segments in spans, each span one polygon (its top
  // vertices, then its two bottoms) of as many triangles as it has segments plus one.
  auto skirt = [&](bool alongRow, std::size_t line, std::size_t k0, std::size_t k1, const Eigen::Vector2d& out,
                   const std::function<bool(std::size_t)>& segmentHasTriangle) {
    std::vector<std::uint32_t> top;
    auto emit = [&](std::uint32_t p, std::uint32_t q, std::uint32_t r) {
      // Outward-facing: the triangle's normal has a positive outward part, else its order turns.
      const Eigen::Vector3d n = (pos(q) - pos(p)).cross(pos(r) - pos(p));
      if (n.x() * out.x() + n.y() * out.y() >= 0) m.indices.insert(m.indices.end(), {p, q, r});
      else m.indices.insert(m.indices.end(), {p, r, q});
    };
    // The polygon left, top[lo..hi], right (left is top[lo] or a bottom under it, right likewise),
    // whose ends lie no higher than any top vertex between them: the lowest of those makes a
    // triangle with the ends, the sides from the ends to it lie below the top vertices on their side,
    // and both halves are such polygons again. The triangles follow the top vertices' heights alone,
    // not the bottoms' (a chunk from the pyramid has deeper bottoms and the same triangles).
    auto fill = [&](auto& self, std::uint32_t left, std::size_t lo, std::size_t hi, std::uint32_t right) -> void {
      std::size_t lowest = hi;
      for (std::size_t j = lo + 1; j < hi; ++j)
        if (lowest == hi || pos(top[j]).z() < pos(top[lowest]).z()) lowest = j;
      if (lowest == hi) {  // one segment
        if (left != top[lo]) emit(left, top[lo], top[hi]);
        if (right != top[hi]) emit(left, top[hi], right);
        return;
      }
      emit(left, top[lowest], right);
      self(self, left, lo, lowest, top[lowest]);
      self(self, top[lowest], lowest, hi, right);
    };
    for (std::size_t k = k0; k < k1;) {
      if (!segmentHasTriangle(k)) {
        ++k;
        continue;
      }
      std::size_t end = k + 1;
      while (end < k1 && segmentHasTriangle(end)) ++end;
      for (std::size_t a = k; a < end;) {
        const std::size_t b = std::min(end, (a / kSkirtSpanSegments + 1) * kSkirtSpanSegments);
        top.clear();
        for (std::size_t j = a; j <= b; ++j) {
          const auto [ti, tj] = keptAt(alongRow, line, j);
          top.push_back(vertex(ti, tj));
        }
        fill(fill, bottomOf(alongRow, line, a), 0, b - a, bottomOf(alongRow, line, b));
        a = b;
      }
      k = end;
    }
  };

  // Quadrants: the cells of child (2x + a, 2y + b), split at the kept sample chunkCells / 2.
  const std::size_t cellsX = nc - 1, cellsY = nr - 1, half = std::size_t(layout.chunkCells() / 2);
  const int rowsEnd = hf.rows() - 1, colsEnd = hf.cols() - 1;
  std::array<std::vector<std::uint32_t>, 4> exactSurfaces;  // level 0: the grid a simplified quadrant replaced
  std::array<std::vector<SimplifiedSurface>, 4> refinedSurfaces;  // level 0: finer simplifications, coarsest first
  for (int q = 0; q < 4; ++q) {
    const int a = q & 1, b = q >> 1;
    const std::size_t i0 = a ? half : 0, i1 = a ? cellsX : std::min(half, cellsX);
    const std::size_t j0 = b ? half : 0, j1 = b ? cellsY : std::min(half, cellsY);
    ChunkQuadrant& quad = m.quadrants[std::size_t(q)];
    quad.firstIndex = m.indices.size();
    if (i0 >= i1 || j0 >= j1) continue;
    // Blocks: cell i of the quadrant goes to block i / blockCells (the quadrant starts at a multiple
    // of blockCells, so blocks are aligned on the level's grid as the pyramid's are).
    const std::size_t bx = (i1 - i0 + blockCells - 1) / blockCells, by = (j1 - j0 + blockCells - 1) / blockCells;
    auto blockOf = [&](std::size_t i, std::size_t j) { return ((j - j0) / blockCells) * bx + (i - i0) / blockCells; };
    quad.blocks.assign(bx * by, ChunkBlock{0.0, Eigen::Vector3d::Constant(kInf), Eigen::Vector3d::Constant(-kInf)});
    // Surface: the heightfield's vertex order is clockwise seen from above; OpenGL's front faces are
    // counter-clockwise, so the second and third vertices swap.
    for (std::size_t j = j0; j < j1; ++j)
      for (std::size_t i = i0; i < i1; ++i) {
        const bool up = g.upper(i, j), low = g.lower(i, j);
        if (up) m.indices.insert(m.indices.end(), {vertex(i, j), vertex(i + 1, j + 1), vertex(i + 1, j)});
        if (low) m.indices.insert(m.indices.end(), {vertex(i, j), vertex(i, j + 1), vertex(i + 1, j + 1)});
        if (!up && !low) continue;
        ChunkBlock& blk = quad.blocks[blockOf(i, j)];
        if (key.level > 0) blk.error = std::max(blk.error, gridErrors ? gridErrorOf(i, j) : cellError(g, i, j));
        {
          auto at = [&](std::size_t ii, std::size_t jj) {
            return Eigen::Vector3d(g.cols[ii] * dx, -g.rows[jj] * dy, g.height(ii, jj));
          };
          if (up) addNormal(blk, at(i, j), at(i + 1, j + 1), at(i + 1, j));
          if (low) addNormal(blk, at(i, j), at(i, j + 1), at(i + 1, j + 1));
        }
        for (std::size_t jj = j; jj <= j + 1; ++jj)
          for (std::size_t ii = i; ii <= i + 1; ++ii)
            if (g.valid(ii, jj)) {
              const Eigen::Vector3d p(g.cols[ii] * dx, -g.rows[jj] * dy, g.height(ii, jj));
              blk.min = blk.min.cwiseMin(p);
              blk.max = blk.max.cwiseMax(p);
            }
      }
    for (const ChunkBlock& blk : quad.blocks) quad.maxError = std::max(quad.maxError, blk.error);
    // The simplification's target: a fraction of the level grid's error, at level 0 of the error the
    // next level's grid would have here (level 0's own is 0).
    double target = simplifyFraction * quad.maxError;
    if (key.level == 0 && simplifyFraction > 0) {
      auto everyOther = [](int first, int last) {
        std::vector<int> v;
        for (int i = first; i < last; i += 2) v.push_back(i);
        v.push_back(last);
        return v;
      };
      const ChunkGrid coarser{hf, everyOther(g.cols[i0], g.cols[i1]), everyOther(g.rows[j0], g.rows[j1])};
      double coarserError = 0;
      for (std::size_t j = 0; j + 1 < coarser.nr(); ++j)
        for (std::size_t i = 0; i + 1 < coarser.nc(); ++i) coarserError = std::max(coarserError, cellError(coarser, i, j));
      target = simplifyFraction * coarserError;
    }
    if (target > 0) {
      // Simplification (terrain_chunk.h): a surface is kept only when every triangle still faces up
      // and it has fewer triangles than the grid; its errors and blocks are then those of its own
      // triangles.
      const std::size_t gridCount = m.indices.size() - quad.firstIndex;
      // The quadrant's own vertices, numbered from 0: meshoptimizer's work grows with the vertex
      // count it is given, and the chunk has four quadrants' (and its skirts').
      std::vector<std::uint32_t> localIndices(gridCount), globalOf;
      std::vector<float> localPositions;
      {
        std::vector<std::int32_t> localOf(m.positions.size() / 3, -1);
        for (std::size_t k = 0; k < gridCount; ++k) {
          const std::uint32_t v = m.indices[quad.firstIndex + k];
          if (localOf[v] < 0) {
            localOf[v] = std::int32_t(globalOf.size());
            globalOf.push_back(v);
            localPositions.insert(localPositions.end(), &m.positions[3 * v], &m.positions[3 * v] + 3);
          }
          localIndices[k] = std::uint32_t(localOf[v]);
        }
      }
      const float scale = meshopt_simplifyScale(localPositions.data(), globalOf.size(), 3 * sizeof(float));
      auto simplify = [&](double targetM) -> std::optional<SimplifiedSurface> {
        SimplifiedSurface out;
        out.indices.resize(gridCount);
        float resultError = 0;
        out.indices.resize(meshopt_simplify(out.indices.data(), localIndices.data(), gridCount, localPositions.data(),
                                            globalOf.size(), 3 * sizeof(float), 0, float(targetM / scale),
                                            meshopt_SimplifyLockBorder, &resultError));
        if (out.indices.size() >= gridCount) return std::nullopt;
        out.reachedM = double(resultError) * scale;
        for (std::uint32_t& v : out.indices) v = globalOf[v];
        for (std::size_t t = 0; t < out.indices.size(); t += 3) {
          const auto& p = fineOf[out.indices[t]];
          const auto& q = fineOf[out.indices[t + 1]];
          const auto& r = fineOf[out.indices[t + 2]];
          // Counter-clockwise seen from above is clockwise in (column, row), rows running south.
          if (std::int64_t(q[0] - p[0]) * (r[1] - p[1]) - std::int64_t(q[1] - p[1]) * (r[0] - p[0]) > 0)
            return std::nullopt;
        }
        out.blocks.assign(bx * by, ChunkBlock{0.0, Eigen::Vector3d::Constant(kInf), Eigen::Vector3d::Constant(-kInf)});
        for (std::size_t t = 0; t < out.indices.size(); t += 3) {
          FineTriangle tri;
          Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
          for (std::size_t k = 0; k < 3; ++k) {
            tri.v[k] = fineOf[out.indices[t + k]];
            tri.h[k] = g.sampleOrNaN(tri.v[k][0], tri.v[k][1]);
            centroid += Eigen::Vector2d(tri.v[k][0], tri.v[k][1]) / 3.0;
          }
          // The block of the cell holding the centroid.
          const std::size_t ci = std::clamp<std::size_t>(std::size_t(std::max(0.0, (centroid.x() - c0) / step)), i0, i1 - 1);
          const std::size_t cj = std::clamp<std::size_t>(std::size_t(std::max(0.0, (centroid.y() - r0) / step)), j0, j1 - 1);
          ChunkBlock& blk = out.blocks[blockOf(ci, cj)];
          blk.error = std::max(blk.error, gridErrors && key.level > 0 ? triangleErrorBound(g, tri, gridErrorOf)
                                                                       : triangleError(g, tri));
          std::array<Eigen::Vector3d, 3> corner;
          for (std::size_t k = 0; k < 3; ++k) {
            corner[k] = Eigen::Vector3d(tri.v[k][0] * dx, -tri.v[k][1] * dy, tri.h[k]);
            blk.min = blk.min.cwiseMin(corner[k]);
            blk.max = blk.max.cwiseMax(corner[k]);
          }
          addNormal(blk, corner[0], corner[1], corner[2]);
        }
        for (const ChunkBlock& blk : out.blocks) out.maxError = std::max(out.maxError, blk.error);
        return out;
      };
      if (std::optional<SimplifiedSurface> primary = simplify(target)) {
        if (key.level == 0) {
          // Level 0: finer simplifications of the same grid, then the grid itself (exact), for the
          // eye's neighbourhood (terrain_chunk.h, "Refinements").
          exactSurfaces[std::size_t(q)].assign(m.indices.begin() + std::ptrdiff_t(quad.firstIndex), m.indices.end());
          double coarserError = primary->maxError;
          std::size_t coarserTriangles = primary->indices.size();
          // Targets kRefinementTargetDivisor apart, skipping those at or above what the last
          // simplification reached: meshoptimizer (0.18) makes the same collapses in the same
          // passes for them, none of which went above that error, so the same surface again.
          double reached = primary->reachedM;
          for (double t = target / kRefinementTargetDivisor;
               refinedSurfaces[std::size_t(q)].size() < std::size_t(kMaxRefinements) && t >= kMinRefinementTargetM;
               t /= kRefinementTargetDivisor) {
            if (t >= reached) continue;
            std::optional<SimplifiedSurface> finer = simplify(t);
            if (finer) reached = finer->reachedM;
            if (!finer || double(finer->indices.size()) > kRefinementMaxGridShare * double(gridCount)) break;
            if (finer->maxError >= coarserError || finer->indices.size() <= coarserTriangles) continue;
            coarserError = finer->maxError;
            coarserTriangles = finer->indices.size();
            refinedSurfaces[std::size_t(q)].push_back(std::move(*finer));
          }
        }
        m.indices.resize(quad.firstIndex);
        m.indices.insert(m.indices.end(), primary->indices.begin(), primary->indices.end());
        quad.blocks = std::move(primary->blocks);
        quad.maxError = primary->maxError;
      }
    }
    quad.surfaceTriangles = (m.indices.size() - quad.firstIndex) / 3;
    m.maxError = std::max(m.maxError, quad.maxError);
    // Skirts on the quadrant's edges inside the grid: first the chunk's own edges there, then each
    // midline it shares with another quadrant of the chunk, a range of its own (terrain_chunk.h,
    // "Cracks"). Edges: north (row j0), south (row j1), west (column i0), east (column i1); the
    // vertical midline is the east edge of a western quadrant (a = 0), the west edge of an eastern.
    const std::array<bool, 4> midline{b == 1, b == 0, a == 1, a == 0};
    const std::array<std::function<void()>, 4> edges{
        [&] { if (g.rows[j0] > 0) skirt(true, j0, i0, i1, {0, 1}, [&](std::size_t k) { return g.upper(k, j0); }); },
        [&] { if (g.rows[j1] < rowsEnd) skirt(true, j1, i0, i1, {0, -1}, [&](std::size_t k) { return g.lower(k, j1 - 1); }); },
        [&] { if (g.cols[i0] > 0) skirt(false, i0, j0, j1, {-1, 0}, [&](std::size_t k) { return g.lower(i0, k); }); },
        [&] { if (g.cols[i1] < colsEnd) skirt(false, i1, j0, j1, {1, 0}, [&](std::size_t k) { return g.upper(i1 - 1, k); }); }};
    for (std::size_t e = 0; e < 4; ++e)
      if (!midline[e]) edges[e]();
    quad.indexCount = m.indices.size() - quad.firstIndex;
    quad.skirtTriangles = quad.indexCount / 3 - quad.surfaceTriangles;
    // Midline skirts: [0] on the vertical midline (beside quadrant q ^ 1: edge 2 or 3), [1] on the
    // horizontal one (beside q ^ 2: edge 0 or 1).
    for (std::size_t k = 0; k < 2; ++k) {
      const std::size_t e = k == 0 ? (a == 1 ? 2 : 3) : (b == 1 ? 0 : 1);
      ChunkSkirt& skirtRange = quad.midlineSkirts[k];
      skirtRange.firstIndex = m.indices.size();
      edges[e]();
      skirtRange.indexCount = m.indices.size() - skirtRange.firstIndex;
      m.midlineSkirtTriangles += skirtRange.indexCount / 3;
    }
    m.surfaceTriangles += quad.surfaceTriangles;
    m.skirtTriangles += quad.skirtTriangles;
  }
  // Level 0's exact grids, for the quadrants simplified there: the grid's surface, then a copy of the
  // quadrant's skirts (the same border vertices).
  for (std::size_t q = 0; q < 4; ++q) {
    if (exactSurfaces[q].empty()) continue;
    ChunkQuadrant& quad = m.quadrants[q];
    quad.exactFirstIndex = m.indices.size();
    m.indices.insert(m.indices.end(), exactSurfaces[q].begin(), exactSurfaces[q].end());
    // A copy: inserting into m.indices may move it.
    const auto skirtsFrom = m.indices.begin() + std::ptrdiff_t(quad.firstIndex + 3 * quad.surfaceTriangles);
    const std::vector<std::uint32_t> skirts(skirtsFrom, skirtsFrom + std::ptrdiff_t(3 * quad.skirtTriangles));
    m.indices.insert(m.indices.end(), skirts.begin(), skirts.end());
    quad.exactIndexCount = m.indices.size() - quad.exactFirstIndex;
    quad.exactSurfaceTriangles = exactSurfaces[q].size() / 3;
    for (SimplifiedSurface& r : refinedSurfaces[q]) {
      ChunkRefinement& refinement = quad.refinements.emplace_back();
      refinement.firstIndex = m.indices.size();
      m.indices.insert(m.indices.end(), r.indices.begin(), r.indices.end());
      m.indices.insert(m.indices.end(), skirts.begin(), skirts.end());
      refinement.indexCount = m.indices.size() - refinement.firstIndex;
      refinement.surfaceTriangles = r.indices.size() / 3;
      refinement.maxError = r.maxError;
      refinement.blocks = std::move(r.blocks);
    }
  }
  if (m.surfaceVertices > 0) {
    m.boxMin = m.boxMin.cwiseMin(m.surfaceMin);
    m.boxMax = m.boxMax.cwiseMax(m.surfaceMax);
  }
  if (!shading.baseColours) {  // the light alone, per vertex: no texture of the level's own
    m.texture = {};
    m.texCoords = {};
    m.textureWidth = m.textureHeight = 0;
  }
  return m;
}

std::optional<double> chunkHeightAt(const Heightfield& hf, const ChunkLayout& layout, const ChunkKey& key, double x,
                                    double y) {
  const ChunkGrid g{hf, layout.columns(key), layout.rowsOf(key)};
  const double fc = x / hf.dx(), fr = -y / hf.dy();
  if (!(fc >= g.cols.front() && fc <= g.cols.back() && fr >= g.rows.front() && fr <= g.rows.back())) return std::nullopt;
  const int s = 1 << key.level;
  auto cellOf = [&](const std::vector<int>& kept, double f) {
    return std::min(std::size_t((f - kept.front()) / s), kept.size() - 2);
  };
  const std::size_t i0 = cellOf(g.cols, fc), j0 = cellOf(g.rows, fr);
  // The closed union: a point on a cell's west or north border also belongs to the neighbour there.
  for (std::size_t j = j0 + 1; j-- > (j0 > 0 ? j0 - 1 : 0);)
    for (std::size_t i = i0 + 1; i-- > (i0 > 0 ? i0 - 1 : 0);) {
      const double w = g.cols[i + 1] - g.cols[i], h = g.rows[j + 1] - g.rows[j];
      const double u = (fc - g.cols[i]) / w, v = (fr - g.rows[j]) / h;
      if (u < 0 || u > 1 || v < 0 || v > 1) continue;
      const double ha = g.height(i, j), hb = g.height(i + 1, j), hc = g.height(i + 1, j + 1), hd = g.height(i, j + 1);
      if (u >= v && g.upper(i, j)) return ha + u * (hb - ha) + v * (hc - hb);
      if (v >= u && g.lower(i, j)) return ha + v * (hd - ha) + u * (hc - hd);
    }
  return std::nullopt;
}

std::optional<double> levelHeightAt(const Heightfield& hf, int level, double x, double y) {
  const int lastC = hf.cols() - 1, lastR = hf.rows() - 1;
  const double fc = x / hf.dx(), fr = -y / hf.dy();
  if (!(fc >= 0 && fc <= lastC && fr >= 0 && fr <= lastR)) return std::nullopt;
  const int s = 1 << level;
  const int cellsX = (lastC - 1) / s + 1, cellsY = (lastR - 1) / s + 1;  // the last one may be narrower
  const int i0 = std::min(int(fc / s), cellsX - 1), j0 = std::min(int(fr / s), cellsY - 1);
  // The closed union: a point on a cell's west or north border also belongs to the neighbour there.
  for (int j = j0; j >= std::max(j0 - 1, 0); --j)
    for (int i = i0; i >= std::max(i0 - 1, 0); --i) {
      const int ca = i * s, cb = std::min(ca + s, lastC), ra = j * s, rb = std::min(ra + s, lastR);
      const double u = (fc - ca) / (cb - ca), v = (fr - ra) / (rb - ra);
      if (u < 0 || u > 1 || v < 0 || v > 1) continue;
      const bool a = hf.valid(ca, ra), b = hf.valid(cb, ra), c = hf.valid(cb, rb), d = hf.valid(ca, rb);
      const double ha = hf.sample(ca, ra), hb = hf.sample(cb, ra), hc = hf.sample(cb, rb), hd = hf.sample(ca, rb);
      if (u >= v && a && b && c) return ha + u * (hb - ha) + v * (hc - hb);
      if (v >= u && a && c && d) return ha + v * (hd - ha) + u * (hc - hd);
    }
  return std::nullopt;
}

std::vector<ChunkLevelStats> chunkLevelTable(const Heightfield& hf, const ChunkLayout& layout) {
  std::vector<ChunkLevelStats> table(std::size_t(layout.levels()));
  ChunkShading plain;
  plain.shade = false;
  for (int level = 0; level < layout.levels(); ++level) {
    ChunkLevelStats& row = table[std::size_t(level)];
    row.level = level;
    row.step = 1 << level;
    for (int y = 0; y < layout.chunksY(level); ++y)
      for (int x = 0; x < layout.chunksX(level); ++x) {
        const ChunkKey key{level, x, y};
        if (!layout.exists(key)) continue;
        const ChunkMesh mesh = buildChunk(hf, layout, key, plain);
        if (mesh.surfaceTriangles == 0) continue;
        ++row.chunks;
        row.triangles += mesh.surfaceTriangles;
        row.maxError = std::max(row.maxError, mesh.maxError);
      }
  }
  return table;
}

}  // namespace nestwalk::terrain
