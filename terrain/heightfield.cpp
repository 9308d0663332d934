// Heightfield: construction, the O(1) ground lookup and the watertight ray cast (see heightfield.h).
//
// Ray cast: a min-max pyramid (Tevs, Ihrke & Seidel, "Maximum Mipmaps for Fast, Accurate, and
// Scalable Dynamic Height Field Rendering", I3D 2008) over the cells' valid height ranges, traversed
// front to back over the ray's 2D projection; at the cells the two triangles are tested with the
// watertight ray/triangle test of Woop, Benthin & Wald, "Watertight Ray/Triangle Intersection",
// JCGT 2(1), 2013, evaluated in double in the local frame.
#include "terrain/heightfield.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

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

struct Heightfield::RayAccel {
  int cellsX = 0, cellsY = 0;
  /// Heights with every hole replaced by NaN (so that one NaN test on a result covers three samples).
  std::vector<float> clean;
  /// Pyramid levels: level 0 = cells, level k node (i, j) covers cells [i 2^k, (i+1) 2^k) x [j 2^k, ...).
  /// Each node stores {min, max} of the valid samples at its cells' corners ({+inf, -inf} if none).
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
  std::vector<Level> levels;
  double noDataFraction = 0.0;
};

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
  if (cols < 2 || rows < 2) throw std::invalid_argument("Heightfield: need at least 2 x 2 samples");
  if (heights_.size() != std::size_t(cols) * std::size_t(rows))
    throw std::invalid_argument("Heightfield: heights.size() != cols * rows");
  if (!(std::isfinite(dx) && std::isfinite(dy) && dx > 0.0 && dy > 0.0))
    throw std::invalid_argument("Heightfield: dx and dy must be finite and > 0");
  if (!(std::isfinite(originX) && std::isfinite(originY)))
    throw std::invalid_argument("Heightfield: origin must be finite");
  noDataCompare_ = noData_ ? *noData_ : std::numeric_limits<float>::quiet_NaN();
  xLast_ = originX_ + (cols_ - 1) * dx_;  // as samplePosition(cols - 1, .) computes it
  yLast_ = originY_ - (rows_ - 1) * dy_;

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
  // Level 0: per cell.
  {
    RayAccel::Level L{accel->cellsX, accel->cellsY, {}};
    L.allocate();
    const float* H = accel->clean.data();
    for (int r = 0; r < L.ny; ++r)
      for (int c = 0; c < L.nx; ++c) {
        float lo = std::numeric_limits<float>::infinity(), hi = -lo;
        const float v[4] = {H[std::size_t(r) * cols + c], H[std::size_t(r) * cols + c + 1],
                            H[std::size_t(r + 1) * cols + c], H[std::size_t(r + 1) * cols + c + 1]};
        for (float h : v)
          if (!std::isnan(h)) lo = std::min(lo, h), hi = std::max(hi, h);
        const std::size_t k = 2 * L.index(c, r);
        L.range[k] = lo;
        L.range[k + 1] = hi;
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
  accel_ = std::move(accel);
  clean_ = accel_->clean.data();
  invDx_ = 1.0 / dx_;
  invDy_ = 1.0 / dy_;
}

bool Heightfield::valid(int col, int row) const {
  const float h = sample(col, row);
  return std::isfinite(h) && h != noDataCompare_;
}

std::optional<double> Heightfield::groundHeight(double x, double y) const {
  // Beyond the outermost sample lines (positions as samplePosition() computes them), or NaN: none.
  if (!(x >= originX_ && x <= xLast_ && y <= originY_ && y >= yLast_)) return std::nullopt;
  // Cell and fraction: u = (x - originX) / dx. x - originX is exact (Sterbenz) near the grid at UTM
  // magnitudes; the scaling rounds, so a query exactly on a grid line may land a rounding off the
  // integer. Within kSnapBand of a line, snap to it when x equals the line's position computed as
  // samplePosition() computes it, so that samples and grid edges are hit exactly.
  const double u = (x - originX_) * invDx_, v = (originY_ - y) * invDy_;
  int c = std::min(int(u), cols_ - 2), r = std::min(int(v), rows_ - 2);
  double fx = u - c, fy = v - r;
  if (fx < kSnapBand || fx > 1.0 - kSnapBand) [[unlikely]]
    snapToLine(x, originX_, dx_, cols_, c, fx);
  if (fy < kSnapBand || fy > 1.0 - kSnapBand) [[unlikely]]
    snapToLine(-y, -originY_, dy_, rows_, r, fy);
  const float* H = clean_ + std::size_t(r) * std::size_t(cols_) + std::size_t(c);
  const double h00 = H[0], h10 = H[1], h01 = H[cols_], h11 = H[cols_ + 1];
  // Upper triangle (c,r),(c+1,r),(c+1,r+1) where fx >= fy; lower (c,r),(c+1,r+1),(c,r+1) where fy >= fx.
  // Written so that fy == 0 / fx == 0 gives the plain edge interpolation h00 + f (h1 - h00), and
  // fx == 1 / fy == 1 gives h10 + fy (h11 - h10) / h01 + fx (h11 - h01) (h00 + (h10 - h00) == h10
  // exactly for float samples widened to double).
  const double h = fx >= fy ? h00 + fx * (h10 - h00) + fy * (h11 - h10) : h00 + fy * (h01 - h00) + fx * (h11 - h01);
  if (!std::isnan(h)) return h;
  return groundHeightNearHole(c, r, fx, fy, h00, h10, h01, h11);
}

std::optional<double> Heightfield::groundHeightNearHole(int, int, double fx, double fy, double h00, double h10,
                                                        double h01, double h11) {
  // Some sample of the containing triangle is a hole: the point has ground only if the smallest
  // closed simplex containing it (sample, edge, triangle) has valid samples only.
  const bool vx = fx == 0.0 || fx == 1.0, vy = fy == 0.0 || fy == 1.0;
  auto ok = [](double a) { return !std::isnan(a); };
  if (vx && vy) {  // at a sample
    const double s = fx == 0.0 ? (fy == 0.0 ? h00 : h01) : (fy == 0.0 ? h10 : h11);
    return ok(s) ? std::optional<double>(s) : std::nullopt;
  }
  auto edge = [&](double a, double b, double f) -> std::optional<double> {
    if (ok(a) && ok(b)) return a + f * (b - a);
    return std::nullopt;
  };
  if (fx == fy) return edge(h00, h11, fx);  // diagonal
  if (fy == 0.0) return edge(h00, h10, fx);  // north edge
  if (fy == 1.0) return edge(h01, h11, fx);  // south edge
  if (fx == 0.0) return edge(h00, h01, fy);  // west edge
  if (fx == 1.0) return edge(h10, h11, fy);  // east edge
  return std::nullopt;                       // interior of a triangle with a hole
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
  const float* H = A.clean.data();
  const std::size_t stride = std::size_t(cols_);

  double tBest = tMax;
  RayHit best;
  bool found = false;

  // The two triangles of cell (c, r), Woop's test on shared sheared vertices.
  auto testCell = [&](int c, int r) {
    const float* P = H + std::size_t(r) * stride + std::size_t(c);
    const double h00 = P[0], h10 = P[1], h01 = P[cols_], h11 = P[cols_ + 1];
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
    const RayAccel::Level& root = A.levels.back();
    if (!(root.range[0] <= root.range[1])) return std::nullopt;
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
                            std::max(std::abs(double(root.range[0])), std::abs(double(root.range[1])))) +
        1e-300;
    const double oz = o[2], dz = d[2];
    // The node's t-interval over its padded footprint, clipped to [tMin, tBest], and whether the ray's
    // height over it meets the node's padded height range.
    auto nodeInterval = [&](int level, int i, int j, double& na) -> bool {
      const RayAccel::Level& L = A.levels[std::size_t(level)];
      const float* rg = L.range.data() + 2 * L.index(i, j);
      const double lo = rg[0], hi = rg[1];
      if (!(lo <= hi)) return false;  // no valid sample in the node
      const int c0 = i << level, c1 = std::min((i + 1) << level, A.cellsX);
      const int r0 = j << level, r1 = std::min((j + 1) << level, A.cellsY);
      double xa, xb, ya, yb;
      slab(o[0], inv[0], c0 * dx_ - padXY, c1 * dx_ + padXY, xa, xb);
      slab(o[1], inv[1], r0 * dy_ - padXY, r1 * dy_ + padXY, ya, yb);
      na = std::max(std::max(xa, ya), tMin);
      const double nb = std::min(std::min(xb, yb), tBest);
      if (!(na <= nb)) return false;
      const double za = oz + na * dz, zb = oz + nb * dz;
      return !(std::max(za, zb) < lo - padZ || std::min(za, zb) > hi + padZ);
    };

    struct Entry {
      int level, i, j;
      double tEnter;
    };
    Entry stack[4 * 40];
    int sp = 0;
    const int top = int(A.levels.size()) - 1;
    stack[sp++] = {top, 0, 0, ta};
    // Children front to back: the near corner first, the far corner last (a monotone path cannot
    // enter both others except at their common corner, so their order is free). Pushed back to front.
    const int sx = d[0] >= 0.0 ? 0 : 1, sy = d[1] >= 0.0 ? 0 : 1;
    const int order[4][2] = {{1 - sx, 1 - sy}, {sx, 1 - sy}, {1 - sx, sy}, {sx, sy}};
    while (sp > 0) {
      const Entry e = stack[--sp];
      if (e.tEnter > tBest) continue;
      if (e.level == 0) {
        testCell(e.i, e.j);
        continue;
      }
      const int cl = e.level - 1;
      const RayAccel::Level& C = A.levels[std::size_t(cl)];
      for (const auto& oc : order) {
        const int ci = 2 * e.i + oc[0], cj = 2 * e.j + oc[1];
        if (ci >= C.nx || cj >= C.ny) continue;
        double na;
        if (nodeInterval(cl, ci, cj, na)) stack[sp++] = {cl, ci, cj, na};
      }
    }
  }
  if (!found) return std::nullopt;
  best.t = tBest;
  best.point = origin + tBest * direction;
  return best;
}

std::optional<std::pair<float, float>> Heightfield::heightRange() const {
  const auto& top = accel_->levels.back().range;
  if (!(top[0] <= top[1])) return std::nullopt;
  return std::make_pair(top[0], top[1]);
}

double Heightfield::noDataFraction() const {
  return accel_->noDataFraction;
}

}  // namespace nestwalk::terrain
