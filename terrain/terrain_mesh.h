// Terrain meshes for rendering: the heightfield's grid cut into square tiles of cells (neighbouring
// tiles share their border samples) with levels of detail, each level carrying its exact maximum
// vertical error against the full-resolution surface. The drawing side turns them into
// OpenSceneGraph nodes (render/terrain_tile_nodes.h); nothing here knows a renderer.
//
// Levels: level k of a tile keeps every 2^k-th sample of the tile (the tile's first sample and
// every step s = 2^k samples after it, up to and including the tile's last sample) and triangulates
// the coarse cells by the heightfield's rule (terrain/heightfield.h): the coarse cell with corners
// (c, r) and (c+s, r+s) is split along the north-west to south-east diagonal into
//   upper (c, r), (c+s, r), (c+s, r+s)    lower (c, r), (c+s, r+s), (c, r+s)
// and a coarse triangle exists only when its three samples are valid. Level 0 is exactly the
// heightfield's triangulation. A tile has levels 0..L where 2^L divides both its cell counts (a
// full tile of 2^n cells has n + 1 levels; a narrower last tile at the east or south edge fewer).
//
// Error: levelError(tile, k) is max |fine(p) - coarse(p)| over every point p where both surfaces
// exist (the fine surface is the full-resolution heightfield surface). It is exact and computed
// at the fine samples only; terrain_mesh.cpp explains why that is enough. Where the coarse level
// covers a fine hole, or leaves a hole the fine surface does not have, the difference is one of
// coverage, not of height, and is not part of the error.
//
// Cracks: neighbouring tiles at different levels do not meet along their common edge (T-junctions
// and small gaps of at most the coarser level's error). Closing them is the renderer's business;
// the meshes here carry no skirts.
//
// Ownership: a TerrainMesh keeps its own copy of the grid (no reference to the Heightfield).
// Thread safety: immutable once constructed; its const members may run from several threads at
// once.
#pragma once

#include "nestwalk/terrain/heightfield.h"

#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

namespace nestwalk::terrain {

struct TerrainMeshOptions {
  int tileCells = 128;  // cells per tile side, a power of two >= 1
  int maxLevels = 0;    // at most this many levels per tile (0: as many as the tile allows)
};

/// One tile: cells [col0, col0 + cellsX) x [row0, row0 + cellsY); samples col0 .. col0 + cellsX.
struct TerrainTile {
  int col0 = 0, row0 = 0;
  int cellsX = 0, cellsY = 0;
  int levels = 1;                  // levels 0 .. levels-1
  std::vector<double> maxError;    // per level, metres (level 0: 0)
  std::vector<std::size_t> triangles;  // per level, existing triangles
};

/// A row of the per-level table: over every tile that has the level.
struct TerrainLevelStats {
  int level = 0;
  int step = 1;                 // 2^level samples
  std::size_t tiles = 0;        // tiles that have this level
  std::size_t triangles = 0;    // existing triangles summed over those tiles
  double maxError = 0;          // max over those tiles of the tile's error, metres
};

/// A triangle of a tile level: three samples of the full grid (col, row), in the heightfield's
/// order (upper (c,r),(c+s,r),(c+s,r+s); lower (c,r),(c+s,r+s),(c,r+s)).
struct GridTriangle {
  std::array<std::int32_t, 3> col, row;
};

/// The heights and validity of a grid, as the mesh reads it.
struct TerrainGrid {
  int cols = 0, rows = 0;
  double dx = 1, dy = 1;
  std::vector<float> heights;        // row-major, row 0 north
  std::vector<std::uint8_t> valid;   // 1 where the sample is valid
  float height(int c, int r) const { return heights[std::size_t(r) * std::size_t(cols) + std::size_t(c)]; }
  bool isValid(int c, int r) const { return valid[std::size_t(r) * std::size_t(cols) + std::size_t(c)] != 0; }
  static TerrainGrid fromHeightfield(const Heightfield& hf);
  /// Validity: finite and not equal to noData.
  static TerrainGrid fromHeights(int cols, int rows, std::vector<float> heights, double dx, double dy,
                                 std::optional<float> noData = std::nullopt);
};

/// The renderer's projection rule for the LOD switch: a level is used once its recorded error,
/// seen at the given distance, projects to at most `maxPixels` on a screen `screenHeightPx` high
/// with vertical field of view `fovYDegrees`: pixels = error * screenHeightPx / (2 tan(fovY/2)) / d.
struct LodRule {
  double fovYDegrees = 60.0;
  double screenHeightPx = 720.0;  // 1280 x 720
  double maxPixels = 1.0;
  /// Pixels per metre of error at distance 1 m (~623.5 for the defaults).
  double pixelsPerRadian() const;
  /// The smallest distance at which an error of `error` metres projects to <= maxPixels.
  double distanceFor(double error) const;
};

class TerrainMesh {
 public:
  explicit TerrainMesh(const Heightfield& hf, TerrainMeshOptions opts = {});
  explicit TerrainMesh(TerrainGrid grid, TerrainMeshOptions opts = {});

  const TerrainGrid& grid() const { return grid_; }
  int tileCells() const { return opts_.tileCells; }
  int tilesX() const { return tilesX_; }
  int tilesY() const { return tilesY_; }
  const std::vector<TerrainTile>& tiles() const { return tiles_; }
  const TerrainTile& tile(int tx, int ty) const { return tiles_[std::size_t(ty) * std::size_t(tilesX_) + std::size_t(tx)]; }
  /// The per-level error table (rows 0 .. the most levels any tile has - 1).
  const std::vector<TerrainLevelStats>& levelTable() const { return levels_; }

  /// The existing triangles of a tile at a level.
  std::vector<GridTriangle> triangles(const TerrainTile& t, int level) const;
  /// The coarse surface of a tile level at local (x, y) (the heightfield's local frame), the closed
  /// union of the level's existing triangles; nullopt outside the tile or in a hole of that level.
  /// Level 0 is the full-resolution surface (without the heightfield's isolated valid edges and
  /// samples next to holes, which carry no triangle).
  std::optional<double> heightAt(const TerrainTile& t, int level, double x, double y) const;

  /// The box of a tile's valid samples in the mesh frame ((col * dx, -row * dy, h), each coordinate
  /// rounded to float as the drawn vertices are); empty when the tile has none.
  Eigen::AlignedBox3f tileBox(const TerrainTile& t) const;
  /// The valid heights' range over the whole grid (metres; 0, 0 without valid samples): what the
  /// drawn tiles' colours by height span.
  float heightLow() const { return heightLo_; }
  float heightHigh() const { return heightHi_; }
  /// A tile's switch distances D_0 .. D_{levels-1}: level k is drawn from D_k to D_{k+1} (the last
  /// to infinity), D_0 = 0, D_k = rule.distanceFor(E_k) + tile radius, E_k = max of the errors of
  /// levels 1..k (so the distances are ordered). Distances are measured from the eye to the centre
  /// of tileBox; adding its radius (half its diagonal) keeps the nearest point of the tile at least
  /// distanceFor(E_k) away, so the projected error stays <= rule.maxPixels.
  std::vector<double> switchDistances(const TerrainTile& t, const LodRule& rule = {}) const;

 private:
  void build();
  TerrainGrid grid_;
  TerrainMeshOptions opts_;
  int tilesX_ = 0, tilesY_ = 0;
  std::vector<TerrainTile> tiles_;
  std::vector<TerrainLevelStats> levels_;
  float heightLo_ = 0, heightHi_ = 0;  // valid heights' range, for the colours
};

}  // namespace nestwalk::terrain
