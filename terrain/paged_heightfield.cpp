#include "nestwalk/terrain/paged_heightfield.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/terrain/dem_reader.h"

#include <gdal.h>
#include <cpl_conv.h>

#include <algorithm>
#include <filesystem>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace nestwalk::terrain {
namespace {

/// The pyramid level whose blocks bound the tiles: its blocks are kPyramidBlockCells 2^5 = 256 fine
/// cells a side, one per tile (kHeightTileCells).
constexpr int kTileBoundsLevel = 5;
static_assert(kPyramidBlockCells << kTileBoundsLevel == kHeightTileCells, "a tile is a level-5 block");

/// A height moved by dz as the scene loader moves a resident heightfield's samples.
float shifted(float h, double dz) { return dz == 0.0 ? h : float(double(h) + dz); }

}  // namespace

Heightfield openPagedHeightfield(std::shared_ptr<const TerrainPyramid> pyramid, const PagedHeightfieldOptions& options) {
  if (!pyramid) throw std::invalid_argument("openPagedHeightfield: no pyramid");
  const PyramidLayout& layout = pyramid->layout();
  const int cols = layout.cols, rows = layout.rows;
  const double dz = options.shift.z();
  const std::optional<float> noData = pyramid->noData();

  // Bounds: every tile's, from the blocks of one level (a block's fine region is closed: the blocks
  // that touch a tile, sharing its edge samples, are folded in too).
  const int level = std::min(kTileBoundsLevel, layout.levels - 1);
  const int tilesX = (cols - 2) / kHeightTileCells + 1, tilesY = (rows - 2) / kHeightTileCells + 1;
  std::vector<float> tileRanges(2 * std::size_t(tilesX) * std::size_t(tilesY));
  for (std::size_t k = 0; k < tileRanges.size(); k += 2)
    tileRanges[k] = std::numeric_limits<float>::infinity(), tileRanges[k + 1] = -std::numeric_limits<float>::infinity();
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  {
    const int bx = layout.blocksX(level), by = layout.blocksY(level);
    const std::vector<PyramidBlock> blocks = pyramid->readBlocks(level, 0, 0, bx, by);
    const int span = kPyramidBlockCells << level;  // fine cells a side of a block
    for (int j = 0; j < by; ++j)
      for (int i = 0; i < bx; ++i) {
        const PyramidBlock& b = blocks[std::size_t(j) * std::size_t(bx) + std::size_t(i)];
        if (b.empty()) continue;
        lo = std::min(lo, b.lo), hi = std::max(hi, b.hi);
        // The block's fine samples [i span, (i + 1) span] (clamped); tile t holds [t T, (t + 1) T].
        const std::int64_t f0 = std::int64_t(i) * span, f1 = std::min<std::int64_t>(f0 + span, cols - 1);
        const std::int64_t g0 = std::int64_t(j) * span, g1 = std::min<std::int64_t>(g0 + span, rows - 1);
        const int tx0 = int(std::max<std::int64_t>(0, (f0 - 1) / kHeightTileCells)), tx1 = int(std::min<std::int64_t>(f1 / kHeightTileCells, tilesX - 1));
        const int ty0 = int(std::max<std::int64_t>(0, (g0 - 1) / kHeightTileCells)), ty1 = int(std::min<std::int64_t>(g1 / kHeightTileCells, tilesY - 1));
        for (int ty = ty0; ty <= ty1; ++ty)
          for (int tx = tx0; tx <= tx1; ++tx) {
            float* t = &tileRanges[2 * (std::size_t(ty) * std::size_t(tilesX) + std::size_t(tx))];
            t[0] = std::min(t[0], shifted(b.lo, dz));
            t[1] = std::max(t[1], shifted(b.hi, dz));
          }
      }
  }
  std::optional<std::pair<float, float>> range;
  if (lo <= hi) range = std::make_pair(shifted(lo, dz), shifted(hi, dz));

  auto loader = [pyramid, dz, noData](int c0, int r0, int w, int h) {
    std::vector<float> v = pyramid->readHeights(0, c0, r0, w, h);
    if (dz != 0.0)
      for (float& x : v)
        if (!(noData && x == *noData)) x = shifted(x, dz);
    return v;
  };
  if (!CPLGetConfigOption("GDAL_CACHEMAX", nullptr) && GDALGetCacheMax64() > GIntBig(kPagedGdalBlockCacheBytes))
    GDALSetCacheMax64(GIntBig(kPagedGdalBlockCacheBytes));  // see "GDAL's block cache"
  auto tiles = std::make_shared<const HeightTileCache>(cols, rows, noData, std::move(loader), std::move(tileRanges),
                                                       options.budgetBytes);
  const RasterFrame& f = pyramid->frame();
  return Heightfield(cols, rows, std::move(tiles), range, f.originX + options.shift.x(), f.originY + options.shift.y(),
                     f.dx, f.dy, noData, f.georeferenced ? pyramid->crsWkt() : std::string());
}

Heightfield openTerrainHeightfield(const std::string& path, std::vector<std::string>* warnings) {
  std::error_code ec;
  if (std::filesystem::exists(pyramidPathOf(path), ec)) {
    try {
      return openPagedHeightfield(std::make_shared<const TerrainPyramid>(path));
    } catch (const InputError& e) {
      if (warnings) warnings->push_back(std::string(e.what()) + " (read whole instead)");
    } catch (const std::invalid_argument&) {
      // A grid too small to page: read whole.
    }
  }
  return readDem(path, {}, warnings);
}

}  // namespace nestwalk::terrain
