// Heightfield: construction, the O(1) ground lookup and the watertight ray cast (see heightfield.h).
//
// Ray cast: a min-max pyramid (Tevs, Ihrke & Seidel, "Maximum Mipmaps for Fast, Accurate, and
// Scalable Dynamic Height Field Rendering", I3D 2008) over the cells' valid height ranges, traversed
// front to back over the ray's 2D projection; at the cells the two triangles are tested with the
// watertight ray/triangle test of Woop, Benthin & Wald, "Watertight Ray/Triangle Intersection",
// JCGT 2(1), 2013, evaluated in double in the local frame.
#include "nestwalk/terrain/heightfield.h"

#include "nestwalk/terrain/height_tiles.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <new>
#include <stdexcept>

#include <sys/mman.h>

namespace nestwalk::terrain {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Relative padding of every pyramid node's footprint and height range in the traversal. The node
/// tests round (slab parameters, ray heights: a few ulps, 1e-15 relative, of the magnitudes in play)
/// and the Woop test accepts hits up to rounding off the exact triangle; both are ~1e-15 of the
/// magnitudes (ray origin, grid extent, heights). 1e-9 keeps a 1e6 margin and costs nothing
/// measurable (it widens a 2 km grid's nodes by 2 um).
constexpr double kNodePadRelative = 1e-9;

/// Half-width, in cell units, of the band around a grid line in which groundHeight() checks whether
/// the query lies exactly on the line. It must exceed the rounding of u = (x - originX) * (1 / dx):
/// at most 3 ulps of u, 3 * 2^-53 * u < 7e-7 for grids below 2^31 cells. Inside the band the check
/// is exact (a comparison with the line's position), so the band only decides when to look.
constexpr double kSnapBand = 1e-6;

/// Slack, relative to the magnitudes of the ray's origin and the grid's extent (unitless), added to
/// a ray's reach when its positions are turned into block indices: the division by the block width
/// rounds by a few ulps (~1e-16 relative), so 1e-12 keeps every block the ray touches in range at
/// UTM magnitudes (1 um at 1e6 m) and adds nothing measurable.
constexpr double kIndexRangeRelativeSlack = 1e-12;

/// groundCeiling(): the rounding of a ground height above its triangle's highest corner. The
/// interpolation h00 + p (b - h00) + q (h11 - b) (p, q in [0, 1]) rounds at most a few ulps of the
/// largest corner's magnitude (4 operations: < 1e-15 relative); 1e-12 keeps a 1000x margin and is
/// 1 nm on a height of 1,000 m.
constexpr double kCeilingSlackRelative = 1e-12;
/// groundCeiling(): cells the rectangle is widened by on each side, in cell units. More than the
/// scaling's rounding and the snap band (kSnapBand above: a query within it of a grid line may be
/// placed in the cell on the line's other side), so every cell a query in the rectangle reads is
/// covered; small enough to add a block only for rectangles ending within it of a block's edge.
constexpr double kCeilingPadCells = 1e-3;
/// groundCeiling(): a rectangle touching at most this many cells is bounded by the samples of
/// those cells (at most 34, a few cache lines) rather than by the 8 x 8-cell blocks around them:
/// a flying leg's short ranges (walker.h: highestFlyingFeet) are then bounded to the cell.
constexpr int kCeilingCellsRead = 16;

/// Allocator for the large per-sample arrays: blocks of 2 MiB and more are 2 MiB aligned and, on
/// Linux, marked for transparent huge pages, so that random lookups and ray walks over a large grid
/// do not miss the TLB on nearly every access (random groundHeight on a 2049^2 grid, kernel THP mode
/// "madvise", noisy 2-core runs: 67-84 ns with the hint, 85-97 ns without).
template <class T>
struct LargePageAllocator {
  using value_type = T;
  static constexpr std::size_t kHuge = std::size_t(2) << 20;
  LargePageAllocator() = default;
  template <class U>
  LargePageAllocator(const LargePageAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kHuge) return std::allocator<T>().allocate(n);
    const std::size_t rounded = (bytes + kHuge - 1) / kHuge * kHuge;
    void* p = std::aligned_alloc(kHuge, rounded);
    if (!p) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    madvise(p, rounded, MADV_HUGEPAGE);  // a hint: failure only costs speed
#endif
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t n) noexcept {
    if (n * sizeof(T) < kHuge)
      std::allocator<T>().deallocate(p, n);
    else
      std::free(p);
  }
  template <class U>
  bool operator==(const LargePageAllocator<U>&) const noexcept {
    return true;
  }
};

}  // namespace

/// The pyramid level whose nodes (2^k x 2^k cells) the oblique traversal walks before the cells.
constexpr int kBlockLevel = 3;

struct Heightfield::RayAccel {
  int cellsX = 0, cellsY = 0;
  /// Heights with every hole replaced by NaN (so that one NaN test on a result covers three samples).
  std::vector<float, LargePageAllocator<float>> clean;
  /// Pyramid levels from baseLevel up (levels[0] is level baseLevel): level k node (i, j) covers cells
  /// [i 2^k, (i+1) 2^k) x [j 2^k, ...). Each node stores {min, max} of the valid samples at its cells'
  /// corners ({+inf, -inf} if none). Finer levels are not kept: the traversal reads none (a cell's
  /// range comes from its samples), and level 0 alone would cost twice the heights.
  /// Layout: 2 x 2 blocks of nodes (the four children of one parent) stored together, 32 bytes, so
  /// that a traversal step reads one cache line per level.
  struct Level {
    int nx, ny;
    std::vector<float> range;  // {min, max} per node, at 2 * index(i, j)
    std::size_t index(int i, int j) const {
      return (std::size_t(j >> 1) * std::size_t((nx + 1) >> 1) + std::size_t(i >> 1)) * 4 + std::size_t((j & 1) * 2 + (i & 1));
    }
    void allocate() {
      range.assign(std::size_t((nx + 1) >> 1) * std::size_t((ny + 1) >> 1) * 8, 0.0f);
      for (std::size_t k = 0; k < range.size(); k += 2)
        range[k] = std::numeric_limits<float>::infinity(), range[k + 1] = -std::numeric_limits<float>::infinity();
    }
  };
  std::vector<Level> levels;  // empty when paged (the tiles hold the base level's ranges)
  /// Resident: 1 where a base-level node's corner samples hold a hole (groundCeiling), row-major
  /// over the base level's nodes; empty when paged (the tiles hold their blocks' flags).
  std::vector<std::uint8_t> baseHoles;
  int baseLevel = 0;  // min(kBlockLevel, the root's level)
  int blocksX = 0, blocksY = 0;  // nodes of the base level
  float rootLo = std::numeric_limits<float>::infinity(), rootHi = -std::numeric_limits<float>::infinity();
  double noDataFraction = 0.0;
};

namespace {

/// min(kBlockLevel, the root's level) for a grid of cellsX x cellsY cells.
int baseLevelFor(int cellsX, int cellsY) {
  int root = 0;
  while (((cellsX - 1) >> root) > 0 || ((cellsY - 1) >> root) > 0) ++root;
  return std::min(kBlockLevel, root);
}

}  // namespace

void Heightfield::initFrame(double originX, double originY, double dx, double dy) {
  if (cols_ < 2 || rows_ < 2) throw std::invalid_argument("Heightfield: need at least 2 x 2 samples");
  if (!(std::isfinite(dx) && std::isfinite(dy) && dx > 0.0 && dy > 0.0 && std::isfinite(1.0 / dx) &&
        std::isfinite(1.0 / dy)))
    throw std::invalid_argument("Heightfield: dx and dy must be finite and > 0, with finite inverses");
  if (!(std::isfinite(originX) && std::isfinite(originY) && std::isfinite(originX + (cols_ - 1) * dx) &&
        std::isfinite(originY - (rows_ - 1) * dy)))
    throw std::invalid_argument("Heightfield: origin and extent must be finite");
  noDataCompare_ = noData_ ? *noData_ : std::numeric_limits<float>::quiet_NaN();
  xLast_ = originX_ + (cols_ - 1) * dx_;  // as samplePosition(cols - 1, .) computes it
  yLast_ = originY_ - (rows_ - 1) * dy_;
  invDx_ = 1.0 / dx_;
  invDy_ = 1.0 / dy_;
}

Heightfield::Heightfield(int cols, int rows, std::vector<float> heights, double originX, double originY, double dx,
                         double dy, std::optional<float> noData, std::string crsWkt)
    : cols_(cols),
      rows_(rows),
      heights_(std::move(heights)),
      originX_(originX),
      originY_(originY),
      dx_(dx),
      dy_(dy),
      noData_(noData),
      crsWkt_(std::move(crsWkt)) {
  initFrame(originX, originY, dx, dy);
  if (heights_.size() != std::size_t(cols) * std::size_t(rows))
    throw std::invalid_argument("Heightfield: heights.size() != cols * rows");

  auto accel = std::make_shared<RayAccel>();
  accel->cellsX = cols - 1;
  accel->cellsY = rows - 1;
  accel->clean.resize(heights_.size());
  std::size_t holes = 0;
  for (std::size_t i = 0; i < heights_.size(); ++i) {
    const float h = heights_[i];
    const bool ok = std::isfinite(h) && h != noDataCompare_;
    accel->clean[i] = ok ? h : std::numeric_limits<float>::quiet_NaN();
    holes += ok ? 0 : 1;
  }
  accel->noDataFraction = double(holes) / double(heights_.size());
  // The base level: min(kBlockLevel, the root's level), straight from the samples of each node's
  // cells (the same as taking every finer level in turn).
  {
    const int K = baseLevelFor(accel->cellsX, accel->cellsY);
    accel->baseLevel = K;
    RayAccel::Level L{((accel->cellsX - 1) >> K) + 1, ((accel->cellsY - 1) >> K) + 1, {}};
    L.allocate();
    accel->baseHoles.assign(std::size_t(L.nx) * std::size_t(L.ny), 0);
    const float* H = accel->clean.data();
    for (int j = 0; j < L.ny; ++j)
      for (int i = 0; i < L.nx; ++i) {
        float lo = std::numeric_limits<float>::infinity(), hi = -lo;
        bool hole = false;
        const int c1 = std::min((i + 1) << K, accel->cellsX), r1 = std::min((j + 1) << K, accel->cellsY);
        for (int r = j << K; r <= r1; ++r)
          for (int c = i << K; c <= c1; ++c) {
            const float h = H[std::size_t(r) * std::size_t(cols) + std::size_t(c)];
            if (!std::isnan(h)) lo = std::min(lo, h), hi = std::max(hi, h);
            else hole = true;
          }
        const std::size_t k = 2 * L.index(i, j);
        L.range[k] = lo;
        L.range[k + 1] = hi;
        accel->baseHoles[std::size_t(j) * std::size_t(L.nx) + std::size_t(i)] = hole ? 1 : 0;
      }
    accel->levels.push_back(std::move(L));
  }
  while (accel->levels.back().nx > 1 || accel->levels.back().ny > 1) {
    const RayAccel::Level& P = accel->levels.back();
    RayAccel::Level L{(P.nx + 1) / 2, (P.ny + 1) / 2, {}};
    L.allocate();
    for (int j = 0; j < L.ny; ++j)
      for (int i = 0; i < L.nx; ++i) {
        float lo = std::numeric_limits<float>::infinity(), hi = -lo;
        for (int jj = 2 * j; jj < std::min(2 * j + 2, P.ny); ++jj)
          for (int ii = 2 * i; ii < std::min(2 * i + 2, P.nx); ++ii) {
            const std::size_t k = 2 * P.index(ii, jj);
            lo = std::min(lo, P.range[k]);
            hi = std::max(hi, P.range[k + 1]);
          }
        const std::size_t k = 2 * L.index(i, j);
        L.range[k] = lo;
        L.range[k + 1] = hi;
      }
    accel->levels.push_back(std::move(L));
  }
  accel->blocksX = accel->levels.front().nx;
  accel->blocksY = accel->levels.front().ny;
  accel->rootLo = accel->levels.back().range[0];
  accel->rootHi = accel->levels.back().range[1];
  accel_ = std::move(accel);
  clean_ = accel_->clean.data();
}

Heightfield::Heightfield(int cols, int rows, std::shared_ptr<const HeightTileCache> tiles,
                         std::optional<std::pair<float, float>> heightRange, double originX, double originY, double dx,
                         double dy, std::optional<float> noData, std::string crsWkt)
    : cols_(cols),
      rows_(rows),
      originX_(originX),
      originY_(originY),
      dx_(dx),
      dy_(dy),
      noData_(noData),
      crsWkt_(std::move(crsWkt)),
      tiles_(std::move(tiles)) {
  initFrame(originX, originY, dx, dy);
  if (!tiles_) throw std::invalid_argument("Heightfield: no tiles");
  auto accel = std::make_shared<RayAccel>();
  accel->cellsX = cols - 1;
  accel->cellsY = rows - 1;
  accel->baseLevel = baseLevelFor(accel->cellsX, accel->cellsY);
  if (accel->baseLevel != kBlockLevel || kHeightTileBlockCells != (1 << kBlockLevel) ||
      kHeightTileCells % kHeightTileBlockCells != 0)
    throw std::invalid_argument("Heightfield: a paged grid needs more than 8 cells a side");
  if (tiles_->tilesX() != (cols - 2) / kHeightTileCells + 1 || tiles_->tilesY() != (rows - 2) / kHeightTileCells + 1)
    throw std::invalid_argument("Heightfield: the tiles are of another grid");
  accel->blocksX = ((accel->cellsX - 1) >> kBlockLevel) + 1;
  accel->blocksY = ((accel->cellsY - 1) >> kBlockLevel) + 1;
  if (heightRange) accel->rootLo = heightRange->first, accel->rootHi = heightRange->second;
  accel->noDataFraction = std::numeric_limits<double>::quiet_NaN();
  accel_ = std::move(accel);
}

float Heightfield::pagedSample(int col, int row) const {
  return *tiles_->threadTile(std::min(col / kHeightTileCells, tiles_->tilesX() - 1),
                             std::min(row / kHeightTileCells, tiles_->tilesY() - 1))
              .at(col, row);
}

std::optional<std::array<int, 4>> Heightfield::tilesUnder(double x0, double y0, double x1, double y1) const {
  if (!tiles_) return std::nullopt;
  const double u0 = (std::min(x0, x1) - originX_) * invDx_, u1 = (std::max(x0, x1) - originX_) * invDx_;
  const double v0 = (originY_ - std::max(y0, y1)) * invDy_, v1 = (originY_ - std::min(y0, y1)) * invDy_;
  if (!(u1 >= 0.0 && v1 >= 0.0 && u0 <= cols_ - 1 && v0 <= rows_ - 1)) return std::nullopt;  // NaN or outside
  const int tx0 = int(std::max(u0, 0.0)) / kHeightTileCells, ty0 = int(std::max(v0, 0.0)) / kHeightTileCells;
  const int tx1 = std::min(int(std::min(u1, double(cols_ - 2))) / kHeightTileCells, tiles_->tilesX() - 1);
  const int ty1 = std::min(int(std::min(v1, double(rows_ - 2))) / kHeightTileCells, tiles_->tilesY() - 1);
  return std::array<int, 4>{tx0, ty0, tx1, ty1};
}

void Heightfield::holdTiles(double x0, double y0, double x1, double y1) const {
  const auto r = tilesUnder(x0, y0, x1, y1);
  if (!r) return;
  for (int ty = (*r)[1]; ty <= (*r)[3]; ++ty)
    for (int tx = (*r)[0]; tx <= (*r)[2]; ++tx) tiles_->tile(tx, ty);
}

void Heightfield::prefetch(double x0, double y0, double x1, double y1, const Eigen::Vector2d& from,
                           const Eigen::Vector2d& to) const {
  const auto r = tilesUnder(x0, y0, x1, y1);
  if (!r) return;
  // The ordering and the look-ups are the background thread's (height_tiles.h: request()).
  tiles_->request({.tx0 = (*r)[0],
                   .ty0 = (*r)[1],
                   .tx1 = (*r)[2],
                   .ty1 = (*r)[3],
                   .fromCol = (from.x() - originX_) * invDx_,
                   .fromRow = (originY_ - from.y()) * invDy_,
                   .toCol = (to.x() - originX_) * invDx_,
                   .toRow = (originY_ - to.y()) * invDy_});
}

bool Heightfield::valid(int col, int row) const {
  const float h = sample(col, row);
  return std::isfinite(h) && h != noDataCompare_;
}

// groundHeight()'s fast path is inline (heightfield_inline.h); near grid lines and holes it comes here.

namespace {

/// One axis of groundHeight's snapping, in the coordinate s increasing with the index (x, or -y):
/// if s equals s0 + n * ds (samplePosition's arithmetic) for the nearest line n, the fraction becomes
/// exactly 0 (cell n) or exactly 1 (cell n - 1 when n is the last line); otherwise it is clamped to
/// [0, 1] (a rounding past the last line stays on the last cell).
inline void snapToLine(double s, double s0, double ds, int count, int& cell, double& f) {
  const int n = f < 0.5 ? cell : cell + 1;
  if (n <= count - 1 && s0 + n * ds == s) {  // for -y: -(originY - n dy) == -y, the same test
    cell = std::min(n, count - 2);
    f = double(n - cell);
  } else {
    f = std::min(std::max(f, 0.0), 1.0);
  }
}

}  // namespace

double Heightfield::groundHeightNearHoleOrNaN(double fx, double fy, double h00, double h10, double h01, double h11) {
  // Some sample of the containing triangle is a hole: the point has ground only if the smallest
  // closed simplex containing it (sample, edge, triangle) has valid samples only.
  constexpr double none = std::numeric_limits<double>::quiet_NaN();
  const bool vx = fx == 0.0 || fx == 1.0, vy = fy == 0.0 || fy == 1.0;
  if (vx && vy)  // at a sample (NaN when it is a hole)
    return fx == 0.0 ? (fy == 0.0 ? h00 : h01) : (fy == 0.0 ? h10 : h11);
  auto edge = [&](double a, double b, double f) -> double {
    if (!std::isnan(a) && !std::isnan(b)) return a + f * (b - a);
    return none;
  };
  if (fx == fy) return edge(h00, h11, fx);  // diagonal
  if (fy == 0.0) return edge(h00, h10, fx);  // north edge
  if (fy == 1.0) return edge(h01, h11, fx);  // south edge
  if (fx == 0.0) return edge(h00, h01, fy);  // west edge
  if (fx == 1.0) return edge(h10, h11, fy);  // east edge
  return none;                               // interior of a triangle with a hole
}

double Heightfield::groundHeightFull(double x, double y) const {
  static_assert(kSnapBand_ == kSnapBand, "heightfield.h and heightfield.cpp disagree on the snap band");
  double h = std::numeric_limits<double>::quiet_NaN();
  // Beyond the outermost sample lines (positions as samplePosition() computes them), or NaN: none.
  if (x >= originX_ && x <= xLast_ && y <= originY_ && y >= yLast_) [[likely]] {
    // Cell and fraction: u = (x - originX) / dx. x - originX is exact (Sterbenz) near the grid at UTM
    // magnitudes; the scaling rounds, so a query exactly on a grid line may land a rounding off the
    // integer. Within kSnapBand_ of a line, snap to it when x equals the line's position computed as
    // samplePosition() computes it, so that samples and grid edges are hit exactly.
    const double u = (x - originX_) * invDx_, v = (originY_ - y) * invDy_;
    int c = std::min(int(u), cols_ - 2), r = std::min(int(v), rows_ - 2);
    double fx = u - c, fy = v - r;
    if (fx < kSnapBand_ || fx > 1.0 - kSnapBand_) [[unlikely]]
      snapToLine(x, originX_, dx_, cols_, c, fx);
    if (fy < kSnapBand_ || fy > 1.0 - kSnapBand_) [[unlikely]]
      snapToLine(-y, -originY_, dy_, rows_, r, fy);
    const float* H;
    std::ptrdiff_t stride;
    if (clean_) [[likely]] {
      H = clean_ + std::size_t(r) * std::size_t(cols_) + std::size_t(c);
      stride = cols_;
    } else {
      // Paged: the tile holding cell (c, r), alive until this thread's next tile (read just below).
      const HeightTile& tile = tiles_->threadTile(c / kHeightTileCells, r / kHeightTileCells);
      H = tile.at(c, r);
      stride = tile.cols;
    }
    // Upper triangle (c,r),(c+1,r),(c+1,r+1) where fx >= fy: h00 + fx (h10 - h00) + fy (h11 - h10);
    // lower (c,r),(c+1,r+1),(c,r+1) where fy > fx: h00 + fy (h01 - h00) + fx (h11 - h01). Both are
    // h00 + p (b - h00) + q (h11 - b) with p = max(fx, fy), q = min(fx, fy) and b the third corner:
    // the same operations, without a branch. fy == 0 / fx == 0 gives the plain edge interpolation
    // h00 + f (h1 - h00), and fx == 1 / fy == 1 gives h10 + fy (h11 - h10) / h01 + fx (h11 - h01)
    // (h00 + (h10 - h00) == h10 exactly for float samples widened to double).
    const double p = std::max(fx, fy), q = std::min(fx, fy);
    const std::ptrdiff_t third = 1 + std::ptrdiff_t(fx < fy) * (stride - 1);  // (c+1,r) or (c,r+1)
    const double h00 = H[0], h11 = H[stride + 1], b = H[third];
    h = h00 + p * (b - h00) + q * (h11 - b);
    if (std::isnan(h)) h = groundHeightNearHoleOrNaN(fx, fy, h00, H[1], H[stride], h11);
  }
  return h;
}

namespace {

/// Woop, Benthin & Wald 2013, per-ray precomputation: the axis kz of the largest |direction|
/// component, kx, ky the others (swapped to keep the winding), and the shear Sx, Sy, Sz.
struct WoopRay {
  int kx, ky, kz;
  double Sx, Sy, Sz;
  double o[3];  // ray origin in the traversal frame
};

struct ShearedVertex {
  double x, y, z;
};

inline ShearedVertex shear(const WoopRay& R, double X, double Y, double Z) {
  const double a[3] = {X - R.o[0], Y - R.o[1], Z - R.o[2]};
  return {a[R.kx] - R.Sx * a[R.kz], a[R.ky] - R.Sy * a[R.kz], R.Sz * a[R.kz]};
}

/// The watertight test (section 3 of the paper) on sheared vertices, two-sided, closed (edges and
/// vertices count). Returns the parameter t, or NaN on a miss. Shared edges evaluate their edge
/// function with the same operands in both triangles (exact negation), hence no ray slips between.
inline double woopTest(const ShearedVertex& A, const ShearedVertex& B, const ShearedVertex& C) {
  const double U = C.x * B.y - C.y * B.x;
  const double V = A.x * C.y - A.y * C.x;
  const double W = B.x * A.y - B.y * A.x;
  if ((U < 0.0 || V < 0.0 || W < 0.0) && (U > 0.0 || V > 0.0 || W > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  const double det = U + V + W;
  if (det == 0.0) return std::numeric_limits<double>::quiet_NaN();  // ray in the triangle's plane, or degenerate
  const double T = U * A.z + V * B.z + W * C.z;
  return T / det;
}


/// Whether cell (x1, y1), triangle half1 comes after (x2, y2), half2 in the front-to-back quadtree
/// order (coordinates already flipped along the ray's negative axes): Morton order with the y bit
/// above the x bit at each level, then the half.
inline bool laterInQuadtreeOrder(std::uint32_t x1, std::uint32_t y1, int half1, std::uint32_t x2, std::uint32_t y2,
                                 int half2) {
  const std::uint32_t ex = x1 ^ x2, ey = y1 ^ y2;
  if (ex == 0 && ey == 0) return half1 > half2;
  auto lessMsb = [](std::uint32_t a, std::uint32_t b) { return a < b && a < (a ^ b); };
  if (ey != 0 && !lessMsb(ey, ex)) return y1 > y2;
  return x1 > x2;
}

/// Slab interval of the ray over [lo, hi] on one axis (closed); empty when ta > tb.
inline void slab(double o, double inv, double lo, double hi, double& ta, double& tb) {
  if (!std::isfinite(inv)) {  // parallel to the slab (zero or subnormal direction component)
    if (o >= lo && o <= hi) {
      ta = -kInf;
      tb = kInf;
    } else {
      ta = kInf;
      tb = -kInf;
    }
    return;
  }
  const double t0 = (lo - o) * inv, t1 = (hi - o) * inv;
  ta = std::min(t0, t1);
  tb = std::max(t0, t1);
}

}  // namespace

std::optional<RayHit> Heightfield::intersectRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                                double tMin, double tMax) const {
  if (!origin.allFinite() || !direction.allFinite() || direction.isZero(0.0) || std::isnan(tMin) || std::isnan(tMax) ||
      tMin > tMax)
    return std::nullopt;
  const RayAccel& A = *accel_;
  // Traversal frame: X = east from sample (0,0), Y = south (row direction), Z = height.
  const double o[3] = {origin.x() - originX_, originY_ - origin.y(), origin.z()};
  const double d[3] = {direction.x(), -direction.y(), direction.z()};
  const double inv[2] = {1.0 / d[0], 1.0 / d[1]};

  WoopRay W;
  {
    const double ad[3] = {std::abs(d[0]), std::abs(d[1]), std::abs(d[2])};
    W.kz = ad[0] > ad[1] ? (ad[0] > ad[2] ? 0 : 2) : (ad[1] > ad[2] ? 1 : 2);
    W.kx = (W.kz + 1) % 3;
    W.ky = (W.kx + 1) % 3;
    if (d[W.kz] < 0.0) std::swap(W.kx, W.ky);
    W.Sx = d[W.kx] / d[W.kz];
    W.Sy = d[W.ky] / d[W.kz];
    W.Sz = 1.0 / d[W.kz];
    W.o[0] = o[0];
    W.o[1] = o[1];
    W.o[2] = o[2];
  }

  const double extX = A.cellsX * dx_, extY = A.cellsY * dy_;
  const double padXY = kNodePadRelative * (std::abs(o[0]) + std::abs(o[1]) + extX + extY);

  // The samples, resident or paged: cell(c, r) points at sample (c, r) of a run in which (c + 1, r),
  // (c, r + 1) and (c + 1, r + 1) are at +1, +stride() and +stride() + 1; block(i, j, za, zb, padZ)
  // is the base level's node test (and, paged, makes the node's tile current: its cells are read
  // next). Both read the same values, so the traversal below is one for both.
  auto nodeMisses = [](const float* rg, double za, double zb, double padZ) {
    const double lo = rg[0], hi = rg[1];
    if (!(lo <= hi)) return true;
    return std::max(za, zb) < lo - padZ || std::min(za, zb) > hi + padZ;
  };
  struct ResidentSamples {
    const float* H;
    std::ptrdiff_t rowStride;
    const RayAccel::Level& base;
    const float* cell(int c, int r) { return H + std::size_t(r) * std::size_t(rowStride) + std::size_t(c); }
    std::ptrdiff_t stride() const { return rowStride; }
    const float* blockRange(int i, int j, double, double, double) { return base.range.data() + 2 * base.index(i, j); }
  };
  struct PagedSamples {
    const HeightTileCache& tiles;
    std::shared_ptr<const HeightTile> tile;
    int tx = -1, ty = -1;
    void use(int x, int y) {
      if (x != tx || y != ty) tile = tiles.tile(x, y), tx = x, ty = y;
    }
    const float* cell(int c, int r) {
      use(c / kHeightTileCells, r / kHeightTileCells);
      return tile->at(c, r);
    }
    std::ptrdiff_t stride() const { return tile->cols; }
    /// nullptr when the node's tile as a whole misses (then so does the node: its range is inside).
    const float* blockRange(int i, int j, double za, double zb, double padZ) {
      constexpr int kPerTile = kHeightTileCells / kHeightTileBlockCells;
      const int x = i / kPerTile, y = j / kPerTile;
      if (x != tx || y != ty) {
        const auto [lo, hi] = tiles.tileRange(x, y);
        const float rg[2] = {lo, hi};
        const double l = rg[0], h = rg[1];
        if (!(l <= h) || std::max(za, zb) < l - padZ || std::min(za, zb) > h + padZ) return nullptr;
        use(x, y);
      }
      return tile->range(i, j);
    }
  };

  auto traverse = [&](auto& samples) -> std::optional<RayHit> {
    double tBest = tMax;
    RayHit best;
    bool found = false;

    // The two triangles of cell (c, r), Woop's test on shared sheared vertices.
    auto testCell = [&](int c, int r) {
      const float* P = samples.cell(c, r);
      const std::ptrdiff_t stride = samples.stride();
      const double h00 = P[0], h10 = P[1], h01 = P[stride], h11 = P[stride + 1];
      if (std::isnan(h00) || std::isnan(h11)) return;  // both triangles need the diagonal
      const double X0 = c * dx_, X1 = (c + 1) * dx_, Y0 = r * dy_, Y1 = (r + 1) * dy_;
      const ShearedVertex s00 = shear(W, X0, Y0, h00), s11 = shear(W, X1, Y1, h11);
      if (!std::isnan(h10)) {
        const double t = woopTest(s00, shear(W, X1, Y0, h10), s11);
        if (t >= tMin && t <= tBest) {
          tBest = t;
          best.col = c, best.row = r, best.half = 0;
          found = true;
        }
      }
      if (!std::isnan(h01)) {
        const double t = woopTest(s00, s11, shear(W, X0, Y1, h01));
        if (t >= tMin && t <= tBest) {
          tBest = t;
          best.col = c, best.row = r, best.half = 1;
          found = true;
        }
      }
    };

    if (d[0] == 0.0 && d[1] == 0.0) {
      // Vertical ray: the surface is a graph, so the ray meets it at most at one height. Test the cell
      // containing the point and, within kSnapBand of a grid line, the cell across it (the band covers
      // the rounding of u, v; a point on a line touches the cells on both sides).
      const double u = o[0] / dx_, v = o[1] / dy_;
      if (!(u >= -kSnapBand && u <= A.cellsX + kSnapBand && v >= -kSnapBand && v <= A.cellsY + kSnapBand))
        return std::nullopt;
      const int c0 = int(std::floor(u)), r0 = int(std::floor(v));
      const double fu = u - c0, fv = v - r0;
      const int cLo = std::max(fu <= kSnapBand ? c0 - 1 : c0, 0), cHi = std::min(fu >= 1.0 - kSnapBand ? c0 + 1 : c0, A.cellsX - 1);
      const int rLo = std::max(fv <= kSnapBand ? r0 - 1 : r0, 0), rHi = std::min(fv >= 1.0 - kSnapBand ? r0 + 1 : r0, A.cellsY - 1);
      for (int r = rLo; r <= rHi; ++r)
        for (int c = cLo; c <= cHi; ++c) testCell(c, r);
    } else {
      // Root interval: the ray's 2D direction is non-zero, so the exit parameter is finite and every
      // node's t-interval below is finite too.
      if (!(A.rootLo <= A.rootHi)) return std::nullopt;
      double ta, tb;
      {
        double xa, xb, ya, yb;
        slab(o[0], inv[0], -padXY, extX + padXY, xa, xb);
        slab(o[1], inv[1], -padXY, extY + padXY, ya, yb);
        ta = std::max({xa, ya, tMin});
        tb = std::min({xb, yb, tMax});
        if (!(ta <= tb)) return std::nullopt;
      }
      tBest = tb;
      // Height slack of the node tests: the ray heights over [ta, tb] and the samples bound every
      // magnitude in the per-node comparisons (see kNodePadRelative).
      const double padZ =
          kNodePadRelative * (std::abs(o[2]) + std::abs(d[2]) * std::max(std::abs(ta), std::abs(tb)) +
                              std::max(std::abs(double(A.rootLo)), std::abs(double(A.rootHi)))) +
          1e-300;
      const double oz = o[2], dz = d[2];
      // Traversal: the blocks of pyramid level kBlockLevel (rows of blocks in the ray's y order, the
      // blocks of a row in its x order), then the cells of each block whose node test passes, the same
      // way; a cell's height range comes straight from its samples. Every node test is the pyramid's
      // (same padded footprint and height range), so every cell that can hold a hit at or before the
      // best so far is tested. Equal parameters are resolved as the quadtree's front-to-back order
      // would (the last tested there wins): see laterInQuadtreeOrder.
      const int K = A.baseLevel;
      const bool finX = std::isfinite(inv[0]), finY = std::isfinite(inv[1]);
      const int sx = d[0] >= 0.0 ? 0 : 1, sy = d[1] >= 0.0 ? 0 : 1;
      const std::uint32_t mx = sx ? ~0u : 0u, my = sy ? ~0u : 0u;
      auto take = [&](double t, int c, int r, int half) {
        if (!(t >= tMin)) return;
        if (t < tBest || (t == tBest && (!found || laterInQuadtreeOrder(std::uint32_t(c) ^ mx, std::uint32_t(r) ^ my, half,
                                                                          std::uint32_t(best.col) ^ mx,
                                                                          std::uint32_t(best.row) ^ my, best.half)))) {
          tBest = t;
          best.col = c, best.row = r, best.half = std::int8_t(half);
          found = true;
        }
      };
      auto testCellOrdered = [&](int c, int r, double h00, double h10, double h01, double h11) {
        if (std::isnan(h00) || std::isnan(h11)) return;  // both triangles need the diagonal
        const double X0 = c * dx_, X1 = (c + 1) * dx_, Y0 = r * dy_, Y1 = (r + 1) * dy_;
        const ShearedVertex s00 = shear(W, X0, Y0, h00), s11 = shear(W, X1, Y1, h11);
        if (!std::isnan(h10)) take(woopTest(s00, shear(W, X1, Y0, h10), s11), c, r, 0);
        if (!std::isnan(h01)) take(woopTest(s00, s11, shear(W, X0, Y1, h01)), c, r, 1);
      };
      // Conservative index range [lo, hi] (clamped to [0, n - 1]) of the intervals of width w covering
      // the positions p0, p1 widened by slack, plus one on each side; the whole range when not finite.
      auto indexRange = [](double p0, double p1, double slack, double w, int n, int& lo, int& hi) {
        const double a = (std::min(p0, p1) - slack) / w, b = (std::max(p0, p1) + slack) / w;
        if (!(std::isfinite(a) && std::isfinite(b))) {
          lo = 0, hi = n - 1;
          return;
        }
        lo = int(std::max(std::floor(std::max(a, -2.0)) - 1.0, 0.0));
        hi = int(std::min(std::floor(std::min(b, double(n) + 2.0)) + 1.0, double(n - 1)));
      };
      const double slack = padXY + kIndexRangeRelativeSlack * (std::abs(o[0]) + std::abs(o[1]) + extX + extY);
      const int B = 1 << K;
      const double bw = dx_ * B, bh = dy_ * B;
      int j0, j1;
      indexRange(o[1] + ta * d[1], o[1] + tb * d[1], slack, bh, A.blocksY, j0, j1);
      const int jn = j1 - j0 + 1;
      for (int jk = 0; jk < jn; ++jk) {
        const int j = sy ? j1 - jk : j0 + jk;
        const int br0 = j << K, br1 = std::min((j + 1) << K, A.cellsY);
        double bya, byb;
        slab(o[1], inv[1], br0 * dy_ - padXY, br1 * dy_ + padXY, bya, byb);
        const double ra = std::max(bya, ta), rb = std::min(byb, tBest);
        if (!(ra <= rb)) {
          if (finY && ra > tBest) break;  // later rows start later still
          continue;
        }
        int i0, i1;
        indexRange(o[0] + ra * d[0], o[0] + rb * d[0], slack, bw, A.blocksX, i0, i1);
        const int in = i1 - i0 + 1;
        for (int ik = 0; ik < in; ++ik) {
          const int i = sx ? i1 - ik : i0 + ik;
          const int bc0 = i << K, bc1 = std::min((i + 1) << K, A.cellsX);
          double bxa, bxb;
          slab(o[0], inv[0], bc0 * dx_ - padXY, bc1 * dx_ + padXY, bxa, bxb);
          const double na = std::max(std::max(bxa, bya), tMin);
          const double nb = std::min(std::min(bxb, byb), tBest);
          if (!(na <= nb)) {
            if (finX && na > tBest) break;  // later blocks of the row start later still
            continue;
          }
          {
            const double za = oz + na * dz, zb = oz + nb * dz;
            const float* rg = samples.blockRange(i, j, za, zb, padZ);
            if (!rg || nodeMisses(rg, za, zb, padZ)) continue;
          }
          // The cells of the block.
          int r0, r1;
          indexRange(o[1] + na * d[1], o[1] + nb * d[1], slack, dy_, A.cellsY, r0, r1);
          r0 = std::max(r0, br0), r1 = std::min(r1, br1 - 1);
          {
            // Fetch the sample rows the cells below read, all at once (the loads are the cost here).
            int pc0, pc1;
            indexRange(o[0] + na * d[0], o[0] + nb * d[0], slack, dx_, A.cellsX, pc0, pc1);
            pc0 = std::max(pc0, bc0), pc1 = std::min(pc1, bc1 - 1);
            if (pc0 <= pc1)
              for (int r = r0; r <= r1 + 1; ++r) {
                const float* rowP = samples.cell(pc0, std::min(r, r1));
                const std::ptrdiff_t down = r > r1 ? samples.stride() : 0;  // the block's last sample row
                __builtin_prefetch(rowP + down);
                __builtin_prefetch(rowP + down + (pc1 - pc0) + 1);
              }
          }
          for (int rk = 0, rn = r1 - r0 + 1; rk < rn; ++rk) {
            const int r = sy ? r1 - rk : r0 + rk;
            double cya, cyb;
            slab(o[1], inv[1], r * dy_ - padXY, (r + 1) * dy_ + padXY, cya, cyb);
            const double cra = std::max(cya, na), crb = std::min(cyb, tBest);
            if (!(cra <= crb)) {
              if (finY && cra > tBest) break;
              continue;
            }
            int c0, c1;
            indexRange(o[0] + cra * d[0], o[0] + crb * d[0], slack, dx_, A.cellsX, c0, c1);
            c0 = std::max(c0, bc0), c1 = std::min(c1, bc1 - 1);
            if (c0 > c1) continue;
            const float* rowP = samples.cell(c0, r);  // sample (c0, r)
            const std::ptrdiff_t stride = samples.stride();
            for (int ck = 0, cn = c1 - c0 + 1; ck < cn; ++ck) {
              const int c = sx ? c1 - ck : c0 + ck;
              double cxa, cxb;
              slab(o[0], inv[0], c * dx_ - padXY, (c + 1) * dx_ + padXY, cxa, cxb);
              const double ca = std::max(std::max(cxa, cya), tMin);
              const double cb = std::min(std::min(cxb, cyb), tBest);
              if (!(ca <= cb)) {
                if (finX && ca > tBest) break;
                continue;
              }
              const float* P = rowP + (c - c0);
              const float f00 = P[0], f10 = P[1], f01 = P[stride], f11 = P[stride + 1];
              // min / max of the samples, or NaN when one is a hole (then the test passes; the triangle tests sort it out).
              // (nan0 is 0, or NaN when some sample is a hole: the sum of four floats in double is exact
              // enough not to overflow.)
              const double sum = (double(f00) + double(f10)) + (double(f01) + double(f11)), nan0 = sum - sum;
              const double lo = double(std::min(std::min(f00, f10), std::min(f01, f11))) + nan0;
              const double hi = double(std::max(std::max(f00, f10), std::max(f01, f11))) + nan0;
              const double za = oz + ca * dz, zb = oz + cb * dz;
              if (std::max(za, zb) < lo - padZ || std::min(za, zb) > hi + padZ) continue;
              testCellOrdered(c, r, f00, f10, f01, f11);
            }
          }
        }
      }
    }
    if (!found) return std::nullopt;
    best.t = tBest;
    best.point = origin + tBest * direction;
    return best;
  };
  if (clean_) {
    ResidentSamples samples{clean_, cols_, A.levels.front()};
    return traverse(samples);
  }
  PagedSamples samples{*tiles_, nullptr};
  return traverse(samples);
}

std::optional<double> Heightfield::groundCeiling(double x0, double y0, double x1, double y1) const {
  if (x0 > x1) std::swap(x0, x1);
  if (y0 > y1) std::swap(y0, y1);
  // Every point within the outermost sample lines (as groundHeight() tests them; NaN fails too).
  if (!(x0 >= originX_ && x1 <= xLast_ && y1 <= originY_ && y0 >= yLast_)) return std::nullopt;
  // The cells groundHeight() may use for a point of the rectangle: its cell index, clamped as there,
  // widened by kCeilingPadCells for the scaling's rounding and the snap to a grid line.
  const RayAccel& A = *accel_;
  auto cellRange = [](double lo, double hi, int cells) {
    return std::pair<int, int>(std::max(0, int(std::max(0.0, lo - kCeilingPadCells))),
                               std::min(cells - 1, int(hi + kCeilingPadCells)));
  };
  const auto [c0, c1] = cellRange((x0 - originX_) * invDx_, (x1 - originX_) * invDx_, A.cellsX);
  const auto [r0, r1] = cellRange((originY_ - y1) * invDy_, (originY_ - y0) * invDy_, A.cellsY);
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  auto ceiling = [&lo, &hi]() -> std::optional<double> {
    if (!(lo <= hi)) return std::nullopt;  // not expected: a rectangle without holes has samples
    const double magnitude = std::max(std::abs(double(lo)), std::abs(double(hi)));
    return double(hi) + kCeilingSlackRelative * magnitude;
  };
  // A few cells: the highest of their own samples (a height is a convex combination of its
  // triangle's corners), when the cells lie in one tile (height_tiles.h; resident grids take the
  // same choice, so that paged answers stay the resident ones).
  // (The tile test first: then the product is at most a tile's cells, no overflow.)
  if (c0 / kHeightTileCells == c1 / kHeightTileCells && r0 / kHeightTileCells == r1 / kHeightTileCells &&
      (c1 - c0 + 1) * (r1 - r0 + 1) <= kCeilingCellsRead) {
    const float* H = clean_ ? clean_ + std::size_t(r0) * std::size_t(cols_) + std::size_t(c0) : nullptr;
    std::size_t stride = std::size_t(cols_);
    if (!clean_) {
      const HeightTile& tile = tiles_->threadTile(c0 / kHeightTileCells, r0 / kHeightTileCells);
      H = tile.at(c0, r0);
      stride = std::size_t(tile.cols);
    }
    for (int r = 0; r <= r1 - r0 + 1; ++r)
      for (int c = 0; c <= c1 - c0 + 1; ++c) {
        const float h = H[std::size_t(r) * stride + std::size_t(c)];
        if (std::isnan(h)) return std::nullopt;
        lo = std::min(lo, h), hi = std::max(hi, h);
      }
    return ceiling();
  }
  const int K = A.baseLevel;
  const int i0 = c0 >> K, i1 = c1 >> K, j0 = r0 >> K, j1 = r1 >> K;
  if (!A.levels.empty()) {
    const RayAccel::Level& L = A.levels.front();
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        if (A.baseHoles[std::size_t(j) * std::size_t(L.nx) + std::size_t(i)]) return std::nullopt;
        const float* rg = L.range.data() + 2 * L.index(i, j);
        lo = std::min(lo, rg[0]), hi = std::max(hi, rg[1]);
      }
  } else {
    // Paged: tile by tile (a tile holds kHeightTileCells / kHeightTileBlockCells blocks a side).
    constexpr int kBlocksPerTile = kHeightTileCells / kHeightTileBlockCells;
    for (int ty = j0 / kBlocksPerTile; ty <= j1 / kBlocksPerTile; ++ty)
      for (int tx = i0 / kBlocksPerTile; tx <= i1 / kBlocksPerTile; ++tx) {
        const HeightTile& tile = tiles_->threadTile(tx, ty);
        for (int j = std::max(j0, ty * kBlocksPerTile); j <= std::min(j1, ty * kBlocksPerTile + kBlocksPerTile - 1); ++j)
          for (int i = std::max(i0, tx * kBlocksPerTile); i <= std::min(i1, tx * kBlocksPerTile + kBlocksPerTile - 1);
               ++i) {
            if (tile.holes(i, j)) return std::nullopt;
            const float* rg = tile.range(i, j);
            lo = std::min(lo, rg[0]), hi = std::max(hi, rg[1]);
          }
      }
  }
  return ceiling();
}

std::optional<std::pair<float, float>> Heightfield::heightRange() const {
  if (!(accel_->rootLo <= accel_->rootHi)) return std::nullopt;
  return std::make_pair(accel_->rootLo, accel_->rootHi);
}

double Heightfield::noDataFraction() const {
  return accel_->noDataFraction;
}

}  // namespace nestwalk::terrain
