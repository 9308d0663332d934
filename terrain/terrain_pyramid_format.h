// The terrain pyramid: what `nestwalk import-terrain` writes beside the terrain file so that a DEM of
// any size opens by reading its header, the terrain file's ends and the coarse pages, and the renderer builds a coarse chunk without reading
// a fine sample. This header is the format's one description (README, "Terrain pyramid" repeats it
// for users); terrain_pyramid_writer.h writes it, terrain_pyramid.h reads it.
//
// Files: the terrain file NAME.tif (the full-resolution Cloud-Optimized GeoTIFF of terrain_import.h,
// unchanged: level 0) and its sidecar NAME.pyramid.tif, a multi-page GeoTIFF (one image per TIFF
// directory; GDAL lists them as subdatasets GTIFF_DIR:n:NAME.pyramid.tif, QGIS opens each). Every
// page is Float32, tiled 256 x 256, DEFLATE with the floating-point predictor, in the terrain's CRS.
//
// Levels: with s = 2^L, level L keeps the fine columns 0, s, 2s, ... and the last column (cols - 1)
// where it falls between two kept ones; rows likewise (the chunk layout's rule, terrain_chunk.h).
// Level L's grid therefore has ceil((cols - 1) / s) + 1 columns; column i is fine column
// min(i s, cols - 1). Levels run from 0 to levels - 1, the coarsest being the first whose grid has
// at most kPyramidTopCells cells a side (the root of the renderer's 64-cell chunks).
//
// Pages, in order:
//   1 .. levels - 1            level L's heights (L = page): the DEM's own Float32 values at the
//                              kept samples, nodata as in the terrain file. Geotransform: pixel
//                              size s dx, pixel i centred on fine column i s (the last, irregular
//                              column is drawn there too, up to s - 1 fine cells east of where it is).
//   levels .. 2 levels - 1     level L's blocks (L = page - levels), 3 bands: a block is
//                              kPyramidBlockCells x kPyramidBlockCells cells of level L (fewer in
//                              the last column or row of blocks), covering the closed fine region
//                              between its corner samples. Band 1: the lowest valid fine sample in
//                              it, band 2: the highest (NaN when it has none), band 3: the largest
//                              exact vertical error of its cells against the full-resolution surface
//                              (coarse_cell_error.h; 0 at level 0), rounded up to float. Pixel size
//                              kPyramidBlockCells s dx, pixel (0, 0)'s corner at fine sample (0, 0)'s
//                              centre.
// Page 1 carries the header as GDAL metadata (kPyramidKey* below): the format version, the grid
// size and levels, the terrain file's fingerprint (its size and the CRC-32 of its first and last
// bytes: a terrain file changed since the pyramid was written no longer matches) and each page's
// CRC-32 (of its values as little-endian Float32, row-major, band after band).
//
// Integrity: the header and the pages a reader holds whole (the coarse ones) are checked against
// their CRC-32 when opened; a window of a fine page relies on its DEFLATE tiles' own Adler-32 and
// the reader's checks (terrain_pyramid.h); TerrainPyramid::verify() checks every page's CRC-32.
// The fingerprint covers the terrain file's size and ends: a same-size edit in its middle (the tile
// data of a GeoTIFF rewritten in place) is not seen; a COG's header (in its first MiB up to some
// 100,000 tiles) changes with any tile's compressed size.
//
// Units: heights and errors metres, as the terrain file. Thread safety: plain values and pure
// functions.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>

namespace nestwalk::terrain {

/// The format's version: a reader refuses a pyramid with a larger one (written by a newer nestwalk).
inline constexpr int kPyramidFormatVersion = 1;
/// Cells a side of a block, at its level's spacing: the renderer's chunk blocks (64-cell chunks,
/// kChunkBlocksPerSide = 8 blocks a side), so a chunk's block bounds are read, not computed.
inline constexpr int kPyramidBlockCells = 8;
/// The coarsest level has at most this many cells a side: the root chunk of the renderer's default
/// 64-cell chunks (paged_terrain.h).
inline constexpr int kPyramidTopCells = 64;
/// Bytes at each end of the terrain file that its fingerprint's CRC-32s cover: the COG's header
/// (directories, tile offsets and sizes, which change with any tile's content) and its last tiles.
inline constexpr std::uint64_t kFingerprintBytes = 1u << 20;

/// Header keys (GDAL metadata of page 1, default domain).
inline constexpr const char* kPyramidKeyVersion = "NESTWALK_PYRAMID_VERSION";
inline constexpr const char* kPyramidKeyCols = "NESTWALK_COLS";
inline constexpr const char* kPyramidKeyRows = "NESTWALK_ROWS";
inline constexpr const char* kPyramidKeyLevels = "NESTWALK_LEVELS";
inline constexpr const char* kPyramidKeyBlockCells = "NESTWALK_BLOCK_CELLS";
inline constexpr const char* kPyramidKeyTerrainBytes = "NESTWALK_TERRAIN_BYTES";
inline constexpr const char* kPyramidKeyTerrainHead = "NESTWALK_TERRAIN_HEAD_CRC32";
inline constexpr const char* kPyramidKeyTerrainTail = "NESTWALK_TERRAIN_TAIL_CRC32";
/// "NESTWALK_PAGE_<n>_CRC32", n from 1.
std::string pyramidPageCrcKey(int page);

/// The sidecar's path: NAME.tif -> NAME.pyramid.tif (any other name: NAME + ".pyramid.tif").
std::string pyramidPathOf(const std::string& terrainPath);

/// The grid of every level (see above).
struct PyramidLayout {
  int cols = 0, rows = 0;  // the terrain file's samples, at least 2 x 2
  int levels = 1;

  /// Throws std::invalid_argument below 2 x 2 samples.
  PyramidLayout(int cols, int rows);
  static int step(int level) { return 1 << level; }
  int levelCols(int level) const { return int((std::int64_t(cols) - 2) / step(level)) + 2; }
  int levelRows(int level) const { return int((std::int64_t(rows) - 2) / step(level)) + 2; }
  /// The fine column of level column i (and row of level row j).
  int fineColumn(int level, int i) const { return int(std::min<std::int64_t>(std::int64_t(i) << level, cols - 1)); }
  int fineRow(int level, int j) const { return int(std::min<std::int64_t>(std::int64_t(j) << level, rows - 1)); }
  int blocksX(int level) const { return int((std::int64_t(levelCols(level)) - 2 + kPyramidBlockCells) / kPyramidBlockCells); }
  int blocksY(int level) const { return int((std::int64_t(levelRows(level)) - 2 + kPyramidBlockCells) / kPyramidBlockCells); }
  /// Pages (1-based, see above).
  int heightsPage(int level) const { return level; }  // level >= 1
  int blocksPage(int level) const { return levels + level; }
  int pages() const { return 2 * levels - 1; }
};

/// What ties a pyramid to its terrain file (see above).
struct TerrainFingerprint {
  std::uint64_t bytes = 0;
  std::uint32_t headCrc = 0, tailCrc = 0;
  friend bool operator==(const TerrainFingerprint&, const TerrainFingerprint&) = default;
};
/// Reads kFingerprintBytes at each end of the file. InputError naming it when it cannot be read.
TerrainFingerprint fingerprintOf(const std::string& terrainPath);

/// CRC-32 (zlib's) of `count` floats as little-endian bytes, continuing `crc` (0 to start).
std::uint32_t crc32Floats(std::uint32_t crc, const float* values, std::size_t count);

}  // namespace nestwalk::terrain
