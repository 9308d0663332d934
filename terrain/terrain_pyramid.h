// Reading a terrain pyramid (terrain_pyramid_format.h): opened from its terrain file's path in time
// independent of the DEM's size, then read by windows of any level.
//
// Opening reads the sidecar's header and checks it: the format version (a newer one is refused), the
// grid against the terrain file's, the terrain file's fingerprint (a terrain file changed since the
// pyramid was written is refused, never read with the old errors) and that every page is there with
// its size. The pages of at most kPyramidResidentValues values (the coarse levels' heights and
// blocks: at most 4 MB each) are read whole at once, checked against their CRC-32 and kept; of the
// larger ones, every tile must be stored (GDAL reads a missing one as zeros), and windows are read
// when asked, through GDAL's block cache: a DEFLATE tile is checked by its Adler-32 as Debian's GDAL
// (libdeflate) decodes it, and errors that are not finite distances are refused. Not caught there:
// a tile offset corrupted to point at another valid tile (the format keeps no per-tile CRC-32;
// verify() reads every page against its CRC-32).
//
// Errors: InputError naming the file and what is wrong (missing sidecar, stale, future version,
// truncated or corrupt page). Ownership: the pyramid owns its open GDAL datasets. Thread safety:
// the const reads may come from several threads: one mutex serialises them (GDAL datasets are not
// thread-safe); copies are not allowed, moves are (not while another thread reads).
#pragma once

#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/terrain/terrain_chunk.h"
#include "nestwalk/terrain/terrain_pyramid_format.h"

#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace nestwalk::terrain {

/// Pages of at most this many values are read whole when the pyramid opens (4 MB of floats).
inline constexpr std::size_t kPyramidResidentValues = std::size_t(1) << 20;

/// A block of a level (terrain_pyramid_format.h): its lowest and highest valid fine sample (NaN when
/// it has none) and its exact error, metres (rounded up to float).
struct PyramidBlock {
  float lo = 0, hi = 0, error = 0;
  bool empty() const { return !(lo <= hi); }
};

class TerrainPyramid {
 public:
  /// Opens the pyramid of the terrain file `terrainPath` (see above).
  explicit TerrainPyramid(const std::string& terrainPath);
  TerrainPyramid(TerrainPyramid&&) noexcept;
  TerrainPyramid& operator=(TerrainPyramid&&) noexcept;
  ~TerrainPyramid();

  const PyramidLayout& layout() const { return layout_; }
  const std::string& terrainPath() const { return terrainPath_; }
  const std::string& path() const { return path_; }
  /// The terrain's nodata value (heights pages store it where the DEM has a hole).
  std::optional<float> noData() const { return noData_; }
  /// The terrain file's sample frame (dem_reader.h; never flipped or rotated) and CRS as WKT.
  const RasterFrame& frame() const { return frame_; }
  const std::string& crsWkt() const { return crsWkt_; }

  /// Level `level`'s samples in its own grid's window [i0, i0 + w) x [j0, j0 + h) (level 0: the
  /// terrain file), row-major, the stored values. std::out_of_range outside the grid.
  std::vector<float> readHeights(int level, int i0, int j0, int w, int h) const;
  /// Level `level`'s blocks in the window [bx0, bx0 + w) x [by0, by0 + h), row-major.
  std::vector<PyramidBlock> readBlocks(int level, int bx0, int by0, int w, int h) const;
  /// What the pyramid knows of chunk `key` of the kPyramidTopCells-cell chunk layout
  /// (terrain_chunk.h: its blocks are the pyramid's): its blocks' errors, its level's samples with
  /// a one-sample margin and the lowest samples of the level's blocks within two blocks of it. At
  /// level 0, the errors only (the fine samples are the terrain file's). Heights and lows moved by
  /// heightShift metres (rounded to float, as the scene loader moves a heightfield's samples).
  /// std::out_of_range for a chunk not in that layout.
  ChunkPyramidData chunkPyramidData(const ChunkKey& key, double heightShift = 0) const;
  /// Reads every page whole and checks it against its CRC-32: InputError naming the page otherwise.
  void verify() const;

 private:
  struct Page {
    int width = 0, height = 0, bands = 0;
    std::uint32_t crc = 0;
    std::vector<float> resident;  // band after band, when held whole
    mutable GdalDataset dataset;  // opened with the pyramid
  };
  /// Reads a window of every band of page `page` (1-based), band after band.
  std::vector<float> readPage(int page, int x0, int y0, int w, int h) const;
  const Page& page(int number) const { return pages_[std::size_t(number - 1)]; }
  std::string terrainPath_, path_;
  PyramidLayout layout_;
  std::optional<float> noData_;
  RasterFrame frame_;
  std::string crsWkt_;
  std::vector<Page> pages_;
  mutable GdalDataset terrain_;
  std::unique_ptr<std::mutex> reading_ = std::make_unique<std::mutex>();  // GDAL's datasets, one reader at a time
};

/// The chunk levels' table (terrain_chunk.h's chunkLevelTable) of the pyramid's terrain in its
/// kPyramidTopCells-cell layout, from the blocks pages alone (read a row of chunks at a time): per
/// level, the chunks with a block holding a valid sample, 2 x the cells of those blocks as triangles
/// and the largest block error. Where the DEM has no holes these are chunkLevelTable's counts, and
/// its errors rounded up to float; with holes the counts are upper bounds (a block may hold a valid
/// sample and no whole triangle). Reads about 12 bytes per 64 fine cells instead of every sample per
/// level. Throws what the pyramid's reads throw.
std::vector<ChunkLevelStats> chunkLevelTable(const TerrainPyramid& pyramid);

}  // namespace nestwalk::terrain
