// Opening a terrain too large to hold as a paged Heightfield (heightfield.h): its samples read in
// tiles from the terrain file on demand (height_tiles.h), its bounds from the terrain pyramid
// (terrain_pyramid.h), so that opening reads no fine sample and the memory held is the tile
// budget (and GDAL's block cache of the terrain file's tiles), whatever the DEM's size.
//
// What the pyramid gives: the lowest and highest valid sample and each tile's bounds (both from the
// blocks of level min(5, levels - 1), a tile's being those of the blocks that touch it). Every answer is bit-identical to readDem's resident heightfield of the same file (the
// tests compare ground heights, rays and samples); `shift` moves the map frame as the scene
// loader's mapShift does (heights by shift.z, rounded to float; holes stay holes).
//
// GDAL's block cache: the tiles keep what a query reads, so GDAL's cache of the terrain file's own
// tiles (and the pyramid's pages) only needs the few a tile's read decodes; opening lowers it, for
// the whole process, to kPagedGdalBlockCacheBytes (never raises it; a GDAL_CACHEMAX set by the user
// stays). A run over a 1 G-sample survey: peak resident memory 1,673 -> 1,463 MiB.
//
// Errors: the pyramid's (InputError naming the file) when the tiles are read; std::invalid_argument
// for a grid of at most 8 cells a side (too small to page). Ownership: the heightfield and its
// tile cache share the pyramid. Thread safety: as Heightfield.
#pragma once

#include "nestwalk/terrain/height_tiles.h"
#include "nestwalk/terrain/heightfield.h"
#include "nestwalk/terrain/terrain_pyramid.h"

#include <Eigen/Core>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace nestwalk::terrain {

/// GDAL's block cache from the first paged heightfield's opening on (see above): 64 COG tiles of
/// 512 x 512 floats, the up to 4 a height tile's read decodes and their neighbours many times over.
inline constexpr std::size_t kPagedGdalBlockCacheBytes = std::size_t(64) << 20;

struct PagedHeightfieldOptions {
  std::size_t budgetBytes = kDefaultHeightTileBudgetBytes;
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
};

Heightfield openPagedHeightfield(std::shared_ptr<const TerrainPyramid> pyramid,
                                 const PagedHeightfieldOptions& options = {});

/// The heightfield of the terrain file at `path` for a tool that reads a few places of it: paged
/// from its pyramid when one is beside it and opens (so a survey of any size opens at once; the
/// pyramid's checks stand for readDem's: no warning for a raster without georeferencing, NaN
/// samples and an all-nodata file not refused but holes), else read whole (readDem, band 1). A pyramid that is refused (stale, damaged) is set aside with its
/// reason appended to `warnings` (when given); readDem's warnings are appended too. InputError as
/// readDem's.
Heightfield openTerrainHeightfield(const std::string& path, std::vector<std::string>* warnings = nullptr);

}  // namespace nestwalk::terrain
