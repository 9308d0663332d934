#include "nestwalk/terrain/terrain_pyramid.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/terrain/gdal_util.h"

#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <stdexcept>

namespace nestwalk::terrain {
namespace {

/// A header value as an unsigned integer in `base`; nullopt when missing or malformed.
std::optional<std::uint64_t> headerNumber(GDALDatasetH ds, const char* key, int base = 10) {
  const char* text = GDALGetMetadataItem(ds, key, nullptr);
  if (!text || !*text) return std::nullopt;
  std::uint64_t value = 0;
  const char* end = text + std::strlen(text);
  const auto [ptr, ec] = std::from_chars(text, end, value, base);
  if (ec != std::errc() || ptr != end) return std::nullopt;
  return value;
}

std::string pageName(const std::string& path, int page) { return "GTIFF_DIR:" + std::to_string(page) + ":" + path; }

}  // namespace

TerrainPyramid::TerrainPyramid(const std::string& terrainPath)
    : terrainPath_(terrainPath), path_(pyramidPathOf(terrainPath)), layout_(2, 2) {
  initGdal();
  terrain_ = openRaster(terrainPath);
  auto* terrain = static_cast<GDALDatasetH>(terrain_.get());
  const int cols = GDALGetRasterXSize(terrain), rows = GDALGetRasterYSize(terrain);
  if (cols < 2 || rows < 2) throw InputError(terrainPath + ": a terrain needs at least 2 x 2 samples");
  frame_ = rasterFrame(terrain);
  if (frame_.flipRows || frame_.flipColumns || frame_.rotated)
    throw InputError(terrainPath + ": stored south-up, east-to-west or rotated: its rows are not the pyramid's");
  crsWkt_ = terrain::crsWkt(terrain);
  const BandNoData nd = bandNoData(GDALGetRasterBand(terrain, 1));
  if (nd.has) noData_ = float(nd.value);

  std::error_code ec;
  if (!std::filesystem::exists(path_, ec))
    throw InputError(terrainPath + ": has no terrain pyramid (" + path_ +
                     "); nestwalk import-terrain writes one beside the terrain file");
  CPLErrorReset();
  GdalDataset first(GDALOpenEx(pageName(path_, 1).c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
  if (!first) throw InputError(path_ + ": not a readable terrain pyramid (" + lastGdalError() + ")");
  auto* ds = static_cast<GDALDatasetH>(first.get());
  const std::optional<std::uint64_t> version = headerNumber(ds, kPyramidKeyVersion);
  if (!version || *version == 0)
    throw InputError(path_ + ": not a nestwalk terrain pyramid (no valid " + std::string(kPyramidKeyVersion) + ")");
  if (*version > std::uint64_t(kPyramidFormatVersion))
    throw InputError(path_ + ": terrain pyramid format " + std::to_string(*version) + ", newer than the " +
                     std::to_string(kPyramidFormatVersion) + " this nestwalk reads; import the terrain again");
  const auto hCols = headerNumber(ds, kPyramidKeyCols), hRows = headerNumber(ds, kPyramidKeyRows);
  const auto hLevels = headerNumber(ds, kPyramidKeyLevels), hBlock = headerNumber(ds, kPyramidKeyBlockCells);
  const auto hBytes = headerNumber(ds, kPyramidKeyTerrainBytes);
  const auto hHead = headerNumber(ds, kPyramidKeyTerrainHead, 16), hTail = headerNumber(ds, kPyramidKeyTerrainTail, 16);
  if (!hCols || !hRows || !hLevels || !hBlock || !hBytes || !hHead || !hTail)
    throw InputError(path_ + ": terrain pyramid header incomplete or malformed");
  const TerrainFingerprint now = fingerprintOf(terrainPath);
  if (*hCols != std::uint64_t(cols) || *hRows != std::uint64_t(rows) || *hBytes != now.bytes ||
      *hHead != now.headCrc || *hTail != now.tailCrc)
    throw InputError(path_ + ": " + terrainPath + " changed since its pyramid was written; import the terrain again");
  layout_ = PyramidLayout(cols, rows);
  if (*hLevels != std::uint64_t(layout_.levels) || *hBlock != std::uint64_t(kPyramidBlockCells))
    throw InputError(path_ + ": terrain pyramid header does not match its " + std::to_string(cols) + " x " +
                     std::to_string(rows) + " grid");

  // Every page: there, of its size, with a CRC-32; the small ones read whole and checked.
  // GDAL lists a multi-page file's pages as subdatasets of the file itself (none for one page).
  CPLErrorReset();
  GdalDataset whole(GDALOpenEx(path_.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
  if (!whole) throw InputError(path_ + ": not a readable terrain pyramid (" + lastGdalError() + ")");
  const int listed = CSLCount(GDALGetMetadata(static_cast<GDALDatasetH>(whole.get()), "SUBDATASETS")) / 2;
  whole.reset();
  if (listed != layout_.pages() && !(layout_.pages() == 1 && listed == 0))
    throw InputError(path_ + ": terrain pyramid has " + std::to_string(listed) + " pages, not " +
                     std::to_string(layout_.pages()) + " (truncated or corrupt)");
  pages_.resize(std::size_t(layout_.pages()));
  for (int p = 1; p <= layout_.pages(); ++p) {
    Page& page = pages_[std::size_t(p - 1)];
    const bool heights = p < layout_.levels;
    const int level = heights ? p : p - layout_.levels;
    page.width = heights ? layout_.levelCols(level) : layout_.blocksX(level);
    page.height = heights ? layout_.levelRows(level) : layout_.blocksY(level);
    page.bands = heights ? 1 : 3;
    const auto crc = headerNumber(ds, pyramidPageCrcKey(p).c_str(), 16);
    if (!crc) throw InputError(path_ + ": terrain pyramid header has no CRC-32 for page " + std::to_string(p));
    page.crc = std::uint32_t(*crc);
    if (p == 1) page.dataset = std::move(first);
    else {
      CPLErrorReset();
      page.dataset.reset(
          GDALOpenEx(pageName(path_, p).c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
    }
    auto* pd = static_cast<GDALDatasetH>(page.dataset.get());
    if (!pd || GDALGetRasterXSize(pd) != page.width || GDALGetRasterYSize(pd) != page.height ||
        GDALGetRasterCount(pd) != page.bands || GDALGetRasterDataType(GDALGetRasterBand(pd, 1)) != GDT_Float32)
      throw InputError(path_ + ": terrain pyramid page " + std::to_string(p) + " is missing or not " +
                       std::to_string(page.width) + " x " + std::to_string(page.height) + " Float32 (truncated or corrupt)");
    for (int b = 1; b <= page.bands; ++b) checkBand(pd, b, pageName(path_, p));  // no block a corrupt header inflates
    if (std::size_t(page.width) * std::size_t(page.height) * std::size_t(page.bands) <= kPyramidResidentValues) {
      page.resident = readPage(p, 0, 0, page.width, page.height);
      if (crc32Floats(0, page.resident.data(), page.resident.size()) != page.crc)
        throw InputError(path_ + ": terrain pyramid page " + std::to_string(p) + " is corrupt (CRC-32 mismatch)");
    } else {
      // Every tile of a page read by windows is stored: GDAL would fill a missing (sparse) one with
      // zeros, which reads as heights or errors of 0.
      for (int b = 1; b <= page.bands; ++b) {
        GDALRasterBandH band = GDALGetRasterBand(pd, b);
        int tileX = 0, tileY = 0;
        GDALGetBlockSize(band, &tileX, &tileY);
        for (int ty = 0; ty * std::int64_t(tileY) < page.height; ++ty)
          for (int tx = 0; tx * std::int64_t(tileX) < page.width; ++tx) {
            const std::string key = "BLOCK_OFFSET_" + std::to_string(tx) + "_" + std::to_string(ty);
            const char* offset = GDALGetMetadataItem(band, key.c_str(), "TIFF");
            if (!offset || std::strtoull(offset, nullptr, 10) == 0)
              throw InputError(path_ + ": terrain pyramid page " + std::to_string(p) + " lacks its tile " +
                               std::to_string(tx) + ", " + std::to_string(ty) + " (truncated or corrupt)");
          }
      }
    }
  }
}

TerrainPyramid::TerrainPyramid(TerrainPyramid&&) noexcept = default;
TerrainPyramid& TerrainPyramid::operator=(TerrainPyramid&&) noexcept = default;
TerrainPyramid::~TerrainPyramid() = default;

std::vector<float> TerrainPyramid::readPage(int number, int x0, int y0, int w, int h) const {
  const Page& p = page(number);
  std::vector<float> out(std::size_t(w) * std::size_t(h) * std::size_t(p.bands));
  if (!p.resident.empty()) {
    for (int b = 0; b < p.bands; ++b)
      for (int y = 0; y < h; ++y)
        std::copy_n(p.resident.begin() +
                        std::ptrdiff_t((std::size_t(b) * std::size_t(p.height) + std::size_t(y0 + y)) * std::size_t(p.width) +
                                       std::size_t(x0)),
                    w, out.begin() + std::ptrdiff_t((std::size_t(b) * std::size_t(h) + std::size_t(y)) * std::size_t(w)));
    return out;
  }
  auto* ds = static_cast<GDALDatasetH>(p.dataset.get());
  const std::lock_guard lock(*reading_);
  for (int b = 1; b <= p.bands; ++b) {
    CPLErrorReset();
    if (GDALRasterIO(GDALGetRasterBand(ds, b), GF_Read, x0, y0, w, h,
                     out.data() + std::size_t(b - 1) * std::size_t(w) * std::size_t(h), w, h, GDT_Float32, 0,
                     0) != CE_None)
      throw InputError(path_ + ": cannot read terrain pyramid page " + std::to_string(number) +
                       " (truncated or corrupt?): " + lastGdalError());
  }
  return out;
}

std::vector<float> TerrainPyramid::readHeights(int level, int i0, int j0, int w, int h) const {
  if (level < 0 || level >= layout_.levels || i0 < 0 || j0 < 0 || w < 0 || h < 0 ||
      i0 + w > layout_.levelCols(level) || j0 + h > layout_.levelRows(level))
    throw std::out_of_range("TerrainPyramid::readHeights: window outside level " + std::to_string(level));
  if (level > 0) return readPage(layout_.heightsPage(level), i0, j0, w, h);
  std::vector<float> out(std::size_t(w) * std::size_t(h));
  const std::lock_guard lock(*reading_);
  CPLErrorReset();
  if (GDALRasterIO(GDALGetRasterBand(static_cast<GDALDatasetH>(terrain_.get()), 1), GF_Read, i0, j0, w, h,
                   out.data(), w, h, GDT_Float32, 0, 0) != CE_None)
    throw InputError(terrainPath_ + ": cannot read the samples (truncated or corrupt file?): " + lastGdalError());
  return out;
}

std::vector<PyramidBlock> TerrainPyramid::readBlocks(int level, int bx0, int by0, int w, int h) const {
  if (level < 0 || level >= layout_.levels || bx0 < 0 || by0 < 0 || w < 0 || h < 0 ||
      bx0 + w > layout_.blocksX(level) || by0 + h > layout_.blocksY(level))
    throw std::out_of_range("TerrainPyramid::readBlocks: window outside level " + std::to_string(level));
  const std::vector<float> bands = readPage(layout_.blocksPage(level), bx0, by0, w, h);
  const std::size_t n = std::size_t(w) * std::size_t(h);
  std::vector<PyramidBlock> out(n);
  for (std::size_t k = 0; k < n; ++k) out[k] = {bands[k], bands[n + k], bands[2 * n + k]};
  return out;
}

ChunkPyramidData TerrainPyramid::chunkPyramidData(const ChunkKey& key, double heightShift) const {
  static_assert(kPyramidTopCells / kChunkBlocksPerSide == kPyramidBlockCells, "a 64-cell chunk's blocks are the pyramid's");
  constexpr int kPerChunk = kChunkBlocksPerSide;
  /// Blocks around the chunk whose lows the skirts may need: a skirt reaches kSkirtReachSteps level
  /// cells (one block) beyond a segment that may end a cell past the chunk.
  constexpr int kSkirtBlocks = 2;
  static_assert(1 + kSkirtReachSteps <= kSkirtBlocks * kPyramidBlockCells, "a segment past the chunk and its reach");
  const int L = key.level;
  if (L < 0 || L >= layout_.levels || key.x < 0 || key.y < 0 || key.x * kPerChunk >= layout_.blocksX(L) ||
      key.y * kPerChunk >= layout_.blocksY(L))
    throw std::out_of_range("TerrainPyramid::chunkPyramidData: no such chunk");
  ChunkPyramidData out;
  out.blocksX = std::min(kPerChunk, layout_.blocksX(L) - key.x * kPerChunk);
  out.blocksY = std::min(kPerChunk, layout_.blocksY(L) - key.y * kPerChunk);
  // One read of the blocks page: the chunk's blocks and the skirts' margin around them.
  out.blockX0 = std::max(0, key.x * kPerChunk - kSkirtBlocks);
  out.blockY0 = std::max(0, key.y * kPerChunk - kSkirtBlocks);
  out.blockWidth = std::min(layout_.blocksX(L), key.x * kPerChunk + out.blocksX + kSkirtBlocks) - out.blockX0;
  out.blockHeight = std::min(layout_.blocksY(L), key.y * kPerChunk + out.blocksY + kSkirtBlocks) - out.blockY0;
  const std::vector<float> bands =
      readPage(layout_.blocksPage(L), out.blockX0, out.blockY0, out.blockWidth, out.blockHeight);
  const std::size_t n = std::size_t(out.blockWidth) * std::size_t(out.blockHeight);
  const int ox = key.x * kPerChunk - out.blockX0, oy = key.y * kPerChunk - out.blockY0;
  out.error.resize(std::size_t(out.blocksX) * std::size_t(out.blocksY));
  for (int j = 0; j < out.blocksY; ++j)
    for (int i = 0; i < out.blocksX; ++i)
      out.error[std::size_t(j) * std::size_t(out.blocksX) + std::size_t(i)] =
          bands[2 * n + std::size_t(j + oy) * std::size_t(out.blockWidth) + std::size_t(i + ox)];
  // An error is a finite distance: anything else is a damaged page (a NaN would vanish in a max).
  for (const float e : out.error)
    if (!(e >= 0.0f && std::isfinite(e)))
      throw InputError(path_ + ": terrain pyramid page " + std::to_string(layout_.blocksPage(L)) +
                       " holds an error that is not a distance (corrupt)");
  if (L == 0) {
    out.blockWidth = out.blockHeight = 0;
    return out;
  }
  out.blockLow.assign(bands.begin(), bands.begin() + std::ptrdiff_t(n));
  auto shifted = [heightShift](float h) { return heightShift == 0.0 ? h : float(double(h) + heightShift); };
  for (float& low : out.blockLow) low = shifted(low);
  // The level's samples: the chunk's and one more each side (clamped to the level's grid).
  const int first = key.x * kPyramidTopCells, firstRow = key.y * kPyramidTopCells;
  out.x0 = std::max(0, first - 1);
  out.y0 = std::max(0, firstRow - 1);
  out.width = std::min(layout_.levelCols(L), first + kPyramidTopCells + 2) - out.x0;
  out.height = std::min(layout_.levelRows(L), firstRow + kPyramidTopCells + 2) - out.y0;
  out.heights = readHeights(L, out.x0, out.y0, out.width, out.height);
  for (float& h : out.heights)
    h = !std::isfinite(h) || (noData_ && h == *noData_) ? std::numeric_limits<float>::quiet_NaN() : shifted(h);
  return out;
}

void TerrainPyramid::verify() const {
  const std::lock_guard lock(*reading_);
  for (int p = 1; p <= layout_.pages(); ++p) {
    const Page& pg = page(p);
    if (!pg.resident.empty()) continue;  // checked when opened
    std::uint32_t crc = 0;
    for (int b = 1; b <= pg.bands; ++b)
      for (int y0 = 0; y0 < pg.height; y0 += 256) {
        const int n = std::min(256, pg.height - y0);
        std::vector<float> strip(std::size_t(pg.width) * std::size_t(n));
        CPLErrorReset();
        if (GDALRasterIO(GDALGetRasterBand(static_cast<GDALDatasetH>(pg.dataset.get()), b), GF_Read, 0, y0, pg.width,
                         n, strip.data(), pg.width, n, GDT_Float32, 0, 0) != CE_None)
          throw InputError(path_ + ": cannot read terrain pyramid page " + std::to_string(p) +
                           " (truncated or corrupt?): " + lastGdalError());
        crc = crc32Floats(crc, strip.data(), strip.size());
      }
    if (crc != pg.crc)
      throw InputError(path_ + ": terrain pyramid page " + std::to_string(p) + " is corrupt (CRC-32 mismatch)");
  }
}

std::vector<ChunkLevelStats> chunkLevelTable(const TerrainPyramid& pyramid) {
  constexpr int kPerChunk = kChunkBlocksPerSide;
  const PyramidLayout& layout = pyramid.layout();
  std::vector<ChunkLevelStats> table(std::size_t(layout.levels));
  for (int level = 0; level < layout.levels; ++level) {
    ChunkLevelStats& row = table[std::size_t(level)];
    row.level = level;
    row.step = PyramidLayout::step(level);
    const int blocksX = layout.blocksX(level), blocksY = layout.blocksY(level);
    const int cellsX = layout.levelCols(level) - 1, cellsY = layout.levelRows(level) - 1;
    std::vector<char> chunkUsed(std::size_t((blocksX + kPerChunk - 1) / kPerChunk));
    for (int by0 = 0; by0 < blocksY; by0 += kPerChunk) {
      const int h = std::min(kPerChunk, blocksY - by0);
      const std::vector<PyramidBlock> blocks = pyramid.readBlocks(level, 0, by0, blocksX, h);
      std::fill(chunkUsed.begin(), chunkUsed.end(), 0);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < blocksX; ++x) {
          const PyramidBlock& b = blocks[std::size_t(y) * std::size_t(blocksX) + std::size_t(x)];
          if (b.empty()) continue;
          chunkUsed[std::size_t(x / kPerChunk)] = 1;
          const int by = by0 + y;
          const std::size_t cells = std::size_t(std::min(kPyramidBlockCells, cellsX - x * kPyramidBlockCells)) *
                                    std::size_t(std::min(kPyramidBlockCells, cellsY - by * kPyramidBlockCells));
          row.triangles += 2 * cells;
          row.maxError = std::max(row.maxError, double(b.error));
        }
      row.chunks += std::size_t(std::count(chunkUsed.begin(), chunkUsed.end(), 1));
    }
  }
  return table;
}

}  // namespace nestwalk::terrain
