// The terrain as the engine sees it: a regular grid of heights sampled at pixel centres, in a
// projected map frame, triangulated by one fixed rule that every query and every mesh shares.
//
// Frames: map coordinates are double (UTM reaches 1e7 m); the heightfield keeps a
// local origin (map coordinates of sample (0, 0)) and does its geometry in the local frame
//   local = map - origin,  sample (col, row) at local (col * dx, -row * dy)   (row 0 is the north row)
// Heights are metres, float as stored (Float32), widened to double in every computation.
//
// Triangulation rule: the cell between samples (c, r), (c+1, r), (c, r+1), (c+1, r+1) is split along
// the diagonal from (c, r) to (c+1, r+1) (north-west to south-east) into
//   upper triangle: (c, r), (c+1, r), (c+1, r+1)    lower triangle: (c, r), (c+1, r+1), (c, r+1)
// Holes: a triangle exists only when its three samples are valid (not nodata, finite). The surface
// is the closed union of the existing triangles, plus every grid edge whose two samples are valid and
// every valid sample (so a query exactly on a valid edge or sample next to a hole still has ground).
// "Grid edge" means every edge of the triangulation: east-west, north-south and the cell diagonals;
// i.e. a point has ground iff the smallest closed simplex (sample, edge, triangle) containing it has
// valid samples only. "Exactly on" a grid line means: the coordinate equals the line's position as
// samplePosition() computes it (originX + col * dx, originY - row * dy), to the last bit.
// Outside the grid's sample hull (beyond the outermost sample centres) there is no ground.
// A heightfield has at least 2 x 2 samples.
//
// Units: metres for a projected CRS; for a geographic CRS x, y, dx and dy are degrees and heights
// metres (dem_reader.h).
// Storage: resident (every sample in memory, 8 bytes a sample with the ray data) or paged (the
// samples in tiles read on demand through a HeightTileCache with a byte budget, height_tiles.h; for
// DEMs too large to hold, opened from their terrain pyramid by paged_heightfield.h). Both run the same
// arithmetic on the same samples: every answer of a paged heightfield is bit-identical to the
// resident one's. A paged query that needs a tile not held waits for its read; prefetch() asks for
// the tiles of a region ahead of time.
// Thread safety: a Heightfield is immutable once constructed (the ray pyramid is built by the
// constructor and shared, read-only, by copies; a paged one's tile cache is shared and
// thread-safe); its const queries may run from several threads at once.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace nestwalk::terrain {

class HeightTileCache;

/// A ray hit: the parameter t along the ray (point = origin + t * direction), the hit point in map
/// coordinates and the triangle (cell and which half: 0 upper, 1 lower).
struct RayHit {
  double t = std::numeric_limits<double>::infinity();
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // map frame
  std::int32_t col = -1, row = -1;
  std::int8_t half = -1;
};

class Heightfield {
 public:
  /// heights: cols * rows values, row-major, row 0 = north. originX/Y: map coordinates of the centre
  /// of sample (0, 0). dx, dy > 0: sample spacing east and south, metres. noData: the sentinel (NaN
  /// and infinities are always holes). Throws std::invalid_argument on inconsistent sizes.
  Heightfield(int cols, int rows, std::vector<float> heights, double originX, double originY, double dx, double dy,
              std::optional<float> noData = std::nullopt, std::string crsWkt = {});
  /// Paged: the samples come from `tiles` (its grid is cols x rows); heightRange: the lowest and
  /// highest valid sample (nullopt when there is none), as the tiles' source records it. Throws
  /// std::invalid_argument on inconsistent sizes or a grid of at most 8 cells a side.
  Heightfield(int cols, int rows, std::shared_ptr<const HeightTileCache> tiles,
              std::optional<std::pair<float, float>> heightRange, double originX, double originY, double dx, double dy,
              std::optional<float> noData = std::nullopt, std::string crsWkt = {});

  int cols() const { return cols_; }
  int rows() const { return rows_; }
  double dx() const { return dx_; }
  double dy() const { return dy_; }
  Eigen::Vector2d origin() const { return {originX_, originY_}; }
  const std::string& crsWkt() const { return crsWkt_; }
  std::optional<float> noData() const { return noData_; }

  /// The stored sample (may be the nodata value or NaN; a paged heightfield gives NaN for every hole,
  /// as readDem's resident one does, except where readDem keeps a sample that differs from the band's
  /// nodata value only by its rounding to float, which a paged one makes a hole: valid() and every
  /// query agree there).
  float sample(int col, int row) const {
    if (!heights_.empty()) [[likely]]
      return heights_[std::size_t(row) * std::size_t(cols_) + std::size_t(col)];
    return pagedSample(col, row);
  }
  /// Whether the samples are paged (see above), and their tiles (nullptr when resident).
  bool paged() const { return tiles_ != nullptr; }
  const std::shared_ptr<const HeightTileCache>& tiles() const { return tiles_; }
  /// Paged: queues the tiles under the map rectangle [x0, x1] x [y0, y1] (either order) that are not
  /// held for reading in the background, ahead of the tiles queued by earlier calls, the soonest
  /// reached first by a walk along the map segment `from` -> `to` (a walker's feet and where its
  /// motion takes it): the tiles the segment crosses in the order it enters them, the others by
  /// the shortest walk along it and then off it (HeightTileCache::request: the caller stores the
  /// request, the background thread orders and queues each one in the order made).
  /// Resident: nothing to do.
  void prefetch(double x0, double y0, double x1, double y1, const Eigen::Vector2d& from, const Eigen::Vector2d& to) const;
  /// Paged: reads every tile under the rectangle that is not held yet, waiting for each (a walker
  /// placed somewhere new reads the ground around it before its first step). Resident: nothing.
  void holdTiles(double x0, double y0, double x1, double y1) const;
  /// Paged: the tiles under that rectangle, {tx0, ty0, tx1, ty1} inclusive; nullopt when resident
  /// or when the rectangle misses the grid. What prefetch() would ask for, at the cost of a few
  /// multiplications (a walker asks again only when it changes).
  std::optional<std::array<int, 4>> tilesUnder(double x0, double y0, double x1, double y1) const;
  bool valid(int col, int row) const;
  /// Map coordinates of sample (col, row).
  Eigen::Vector2d samplePosition(int col, int row) const { return {originX_ + col * dx_, originY_ - row * dy_}; }

  /// Ground height at map (x, y): the vertical ray, O(1). nullopt where there is no surface.
  std::optional<double> groundHeight(double x, double y) const;

  /// The first hit of the ray origin + t * direction, t in [tMin, tMax] (map frame, direction need
  /// not be unit). Exact against the triangulated surface and watertight: rays through vertices and
  /// along edges do not slip through. nullopt when the ray misses (holes, beyond the edge).
  /// Two-sided: a ray starting below the surface returns the first crossing with t >= tMin.
  /// Measure-zero parts are ignored: a ray meeting the surface only at an isolated valid edge or
  /// sample next to holes (no existing triangle there), or lying in a triangle's plane (grazing a flat
  /// triangle) does not hit that part; it still hits the neighbouring triangles' edges it crosses.
  /// Likewise a ray that touches the surface only at a point of its outer boundary (raster edge, hole
  /// border) may miss by rounding; crossings in the interior of the surface never slip through.
  /// Method: a min-max pyramid over the cells, traversed front to back, and the watertight
  /// ray/triangle test of Woop, Benthin & Wald (JCGT 2013) in double in the local frame.
  std::optional<RayHit> intersectRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double tMin = 0.0,
                                     double tMax = std::numeric_limits<double>::infinity()) const;

  /// An upper bound of every groundHeight() answer in the map rectangle [x0, x1] x [y0, y1] (either
  /// order), when every point of it has ground: the highest sample of the ray blocks (8 x 8 cells)
  /// the rectangle touches, or of its cells themselves when it touches at most 16 within one tile
  /// (kCeilingCellsRead), plus the interpolation's rounding (kCeilingSlackRelative,
  /// heightfield.cpp). nullopt when the rectangle leaves the sample hull or a block (or cell) it
  /// touches holds a hole (it may have ground everywhere and still get nullopt: the answer is a cheap
  /// certificate, not a search). Costs a few block reads, or at most 34 samples, whatever the
  /// rectangle's size in cells (a walker's leg of a few blocks). Paged: reads the tiles under it as groundHeight() would.
  std::optional<double> groundCeiling(double x0, double y0, double x1, double y1) const;

  /// Lowest and highest valid sample (nullopt when every sample is a hole).
  std::optional<std::pair<float, float>> heightRange() const;
  /// Fraction of samples that are holes (NaN when paged: it would take reading every sample).
  double noDataFraction() const;

 private:
  int cols_, rows_;
  std::vector<float> heights_;
  double originX_, originY_, dx_, dy_;
  std::optional<float> noData_;
  std::string crsWkt_;
  float noDataCompare_;  // *noData_, or NaN (never equal) when there is no sentinel
  double xLast_, yLast_;  // map x of the last column, map y of the last row
  double invDx_, invDy_;
  // Heights with holes as NaN, owned by *accel_ (shared, so copies stay valid); nullptr when paged.
  const float* clean_ = nullptr;
  std::shared_ptr<const HeightTileCache> tiles_;  // paged only
  void initFrame(double originX, double originY, double dx, double dy);
  [[gnu::cold]] float pagedSample(int col, int row) const;
  // groundHeight() in full (snapping to grid lines, holes), NaN where there is no ground (a ground
  // height is never NaN); the inline groundHeight() (heightfield_inline.h) calls it near grid lines
  // and holes. Ground near a hole: the smallest closed simplex containing the point decides.
  [[gnu::cold]] double groundHeightFull(double x, double y) const;
  static double groundHeightNearHoleOrNaN(double fx, double fy, double h00, double h10, double h01, double h11);
  /// Half-width, in cell units, of the band around a grid line in which groundHeight() checks whether
  /// the query lies exactly on the line (see heightfield.cpp).
  static constexpr double kSnapBand_ = 1e-6;
  // Acceleration data for intersectRay (built in the constructor) live in the .cpp's structures.
  struct RayAccel;
  std::shared_ptr<const RayAccel> accel_;
};

}  // namespace nestwalk::terrain

#include "nestwalk/terrain/heightfield_inline.h"  // IWYU pragma: export
