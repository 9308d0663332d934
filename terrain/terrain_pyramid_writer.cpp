#include "nestwalk/terrain/terrain_pyramid_writer.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/core/output_file.h"
#include "nestwalk/terrain/coarse_cell_error.h"
#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/terrain/gdal_util.h"
#include "nestwalk/terrain/terrain_pyramid_format.h"

#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <vector>

namespace nestwalk::terrain {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

/// The stripe of fine rows [r0, r0 + rows) held in memory, as the coarse_cell_error.h grid.
struct StripeGrid {
  const float* data = nullptr;
  int cols = 0, r0 = 0;
  float noData = kNaN;  // never equal when the raster has none
  float at(int c, int r) const { return data[std::size_t(r - r0) * std::size_t(cols) + std::size_t(c)]; }
  bool valid(int c, int r) const {
    const float v = at(c, r);
    return std::isfinite(v) && v != noData;
  }
  double height(int c, int r) const { return at(c, r); }
};

/// A block's bounds and error while its rows are being read.
struct BlockStats {
  float lo = std::numeric_limits<float>::infinity(), hi = -std::numeric_limits<float>::infinity();
  double error = 0;
};

/// The smallest float not below `v`: errors stay bounds when stored as Float32.
float roundUp(double v) {
  float f = float(v);
  if (double(f) < v) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

/// One page's staging file: written row by row in order, its CRC-32 kept per band.
class StagedPage {
 public:
  StagedPage(const std::string& target, const std::string& tag, int width, int height, int bands)
      : file_(target, ".tif", tag), width_(width), height_(height), bands_(bands), crc_(std::size_t(bands), 0) {
    GDALDriverH gtiff = GDALGetDriverByName("GTiff");
    const char* zstd[] = {"TILED=YES", "BLOCKXSIZE=256", "BLOCKYSIZE=256", "COMPRESS=ZSTD", "ZSTD_LEVEL=1",
                          "BIGTIFF=IF_SAFER", "INTERLEAVE=BAND", nullptr};
    const char* deflate[] = {"TILED=YES", "BLOCKXSIZE=256", "BLOCKYSIZE=256", "COMPRESS=DEFLATE", "ZLEVEL=1",
                             "BIGTIFF=IF_SAFER", "INTERLEAVE=BAND", nullptr};
    ds_.reset(GDALCreate(gtiff, file_.tempPath().c_str(), width, height, bands, GDT_Float32, const_cast<char**>(zstd)));
    if (!ds_)  // ZSTD may be missing from the build
      ds_.reset(GDALCreate(gtiff, file_.tempPath().c_str(), width, height, bands, GDT_Float32,
                           const_cast<char**>(deflate)));
    if (!ds_) throw InputError(target + ": cannot create a staging file: " + lastGdalError());
  }
  /// Row `row` of band `band` (1-based), `width` values.
  void writeRow(int band, int row, const float* values) {
    crc_[std::size_t(band - 1)] = crc32Floats(crc_[std::size_t(band - 1)], values, std::size_t(width_));
    GDALRasterBandH b = GDALGetRasterBand(static_cast<GDALDatasetH>(ds_.get()), band);
    if (GDALRasterIO(b, GF_Write, 0, row, width_, 1, const_cast<float*>(values), width_, 1, GDT_Float32, 0, 0) !=
        CE_None)
      throw InputError(file_.target() + ": cannot write a staging file: " + lastGdalError());
  }
  /// The page's CRC-32: its bands' rows one after another.
  std::uint32_t crc() const {
    std::uint32_t c = crc_[0];
    const z_off_t bandBytes = z_off_t(width_) * z_off_t(height_) * z_off_t(sizeof(float));
    for (std::size_t b = 1; b < crc_.size(); ++b) c = std::uint32_t(::crc32_combine(c, crc_[b], bandBytes));
    return c;
  }
  GDALDatasetH dataset() const { return static_cast<GDALDatasetH>(ds_.get()); }
  int width() const { return width_; }
  int height() const { return height_; }
  int bands() const { return bands_; }

 private:
  OutputFile file_;  // scratch, never committed: removed with the page
  GdalDataset ds_;
  int width_, height_, bands_;
  std::vector<std::uint32_t> crc_;
};

std::string hex32(std::uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%08x", v);
  return buf;
}

/// Copies every staged page, in order, into one multi-page GeoTIFF at `path`.
void assemble(const std::string& path, const std::vector<StagedPage*>& pages, const PyramidLayout& layout,
              const double* terrainGt, const std::string& wkt, const BandNoData& noData,
              const std::vector<std::pair<std::string, std::string>>& header, const std::string& target,
              const std::function<void(double)>& progress) {
  GDALDriverH gtiff = GDALGetDriverByName("GTiff");
  std::uint64_t total = 0, done = 0;
  for (const StagedPage* p : pages) total += std::uint64_t(p->width()) * std::uint64_t(p->height()) * std::uint64_t(p->bands());
  std::vector<float> strip;
  for (std::size_t k = 0; k < pages.size(); ++k) {
    const StagedPage& page = *pages[k];
    const int pageNumber = int(k) + 1;
    CPLStringList options;
    // ZLEVEL=1 (GDAL's default is 6): the pages of the 100 M-sample survey of bench render's sweep
    // 0.6 % larger, its import about a second faster.
    for (const char* o : {"TILED=YES", "BLOCKXSIZE=256", "BLOCKYSIZE=256", "COMPRESS=DEFLATE", "ZLEVEL=1",
                          "PREDICTOR=3", "BIGTIFF=IF_SAFER", "INTERLEAVE=BAND", "NUM_THREADS=ALL_CPUS"})
      options.AddString(o);
    if (k > 0) options.AddString("APPEND_SUBDATASET=YES");
    GdalDataset out(GDALCreate(gtiff, path.c_str(), page.width(), page.height(), page.bands(), GDT_Float32,
                               options.List()));
    if (!out) throw InputError(target + ": cannot write the terrain pyramid: " + lastGdalError());
    auto* ds = static_cast<GDALDatasetH>(out.get());
    // Geotransform: heights pages have level L's spacing, blocks pages a block's (format header).
    const bool heights = pageNumber < layout.levels;
    const int level = heights ? pageNumber : pageNumber - layout.levels;
    if (terrainGt) {
      const double s = double(PyramidLayout::step(level));
      const double ox = terrainGt[0] + 0.5 * terrainGt[1], oy = terrainGt[3] + 0.5 * terrainGt[5];
      const double px = heights ? s * terrainGt[1] : kPyramidBlockCells * s * terrainGt[1];
      const double py = heights ? s * terrainGt[5] : kPyramidBlockCells * s * terrainGt[5];
      double gt[6] = {heights ? ox - 0.5 * px : ox, px, 0, heights ? oy - 0.5 * py : oy, 0, py};
      GDALSetGeoTransform(ds, gt);
    }
    if (!wkt.empty()) GDALSetProjection(ds, wkt.c_str());
    if (heights && noData.has) GDALSetRasterNoDataValue(GDALGetRasterBand(ds, 1), noData.value);
    for (int b = 1; b <= page.bands(); ++b)
      GDALSetDescription(GDALGetRasterBand(ds, b),
                         heights ? "height" : (b == 1 ? "lowest fine sample" : b == 2 ? "highest fine sample" : "error"));
    if (k == 0)
      for (const auto& [key, value] : header) GDALSetMetadataItem(ds, key.c_str(), value.c_str(), nullptr);
    const int w = page.width(), h = page.height();
    for (int b = 1; b <= page.bands(); ++b)
      for (int r0 = 0; r0 < h; r0 += 256) {
        const int n = std::min(256, h - r0);
        strip.resize(std::size_t(w) * std::size_t(n));
        if (GDALRasterIO(GDALGetRasterBand(page.dataset(), b), GF_Read, 0, r0, w, n, strip.data(), w, n, GDT_Float32,
                         0, 0) != CE_None ||
            GDALRasterIO(GDALGetRasterBand(ds, b), GF_Write, 0, r0, w, n, strip.data(), w, n, GDT_Float32, 0, 0) !=
                CE_None)
          throw InputError(target + ": cannot write the terrain pyramid: " + lastGdalError());
        done += std::uint64_t(w) * std::uint64_t(n);
        if (progress) progress(double(done) / double(std::max<std::uint64_t>(total, 1)));
      }
    CPLErrorReset();
    out.reset();  // closes the page: the next one is appended after it
    if (CPLGetLastErrorType() == CE_Failure)
      throw InputError(target + ": cannot write the terrain pyramid: " + lastGdalError());
  }
}

}  // namespace

PyramidWriteSummary writeTerrainPyramid(const std::string& terrainPath, const std::string& pyramidPath,
                                        const PyramidWriteOptions& options) {
  initGdal();
  const std::string samplesPath = options.samplesPath.empty() ? terrainPath : options.samplesPath;
  GdalDataset source = openRaster(samplesPath);
  auto* src = static_cast<GDALDatasetH>(source.get());
  const int cols = GDALGetRasterXSize(src), rows = GDALGetRasterYSize(src);
  if (cols < 2 || rows < 2) throw InputError(samplesPath + ": a terrain needs at least 2 x 2 samples");
  // The pyramid's rows and columns are the file's; they are the heightfield's only when the file is
  // north-up and west-to-east, as every terrain file nestwalk writes is.
  if (const RasterFrame f = rasterFrame(src); f.flipRows || f.flipColumns || f.rotated)
    throw InputError(samplesPath + ": stored south-up, east-to-west or rotated: import it (nestwalk import-terrain) "
                                   "to get a terrain file with a pyramid");
  GDALRasterBandH band = GDALGetRasterBand(src, 1);
  const BandNoData noData = bandNoData(band);
  const PyramidLayout layout(cols, rows);
  const int levels = layout.levels;
  const TerrainFingerprint fingerprint = fingerprintOf(terrainPath);

  // Staging pages: heights of levels 1.., blocks of levels 0..
  const auto levelCount = std::size_t(levels);
  std::vector<std::unique_ptr<StagedPage>> heightPages(levelCount), blockPages(levelCount);
  for (int level = 1; level < levels; ++level)
    heightPages[std::size_t(level)] = std::make_unique<StagedPage>(
        pyramidPath, "heights" + std::to_string(level), layout.levelCols(level), layout.levelRows(level), 1);
  for (int level = 0; level < levels; ++level)
    blockPages[std::size_t(level)] = std::make_unique<StagedPage>(
        pyramidPath, "blocks" + std::to_string(level), layout.blocksX(level), layout.blocksY(level), 3);

  if (options.minStripeRows < kPyramidBlockCells || options.minStripeRows % kPyramidBlockCells != 0)
    throw std::invalid_argument("writeTerrainPyramid: minStripeRows must be a positive multiple of 8");
  // A multiple of every level's step (the top one's), so that a stripe holds whole cells of each.
  const int top = PyramidLayout::step(levels - 1);
  const int stripeRows = (std::max(top, options.minStripeRows) + top - 1) / top * top;
  // A short grid needs no more rows than it has.
  std::vector<float> stripe(std::size_t(std::min(stripeRows, rows - 1) + 1) * std::size_t(cols));
  StripeGrid grid{stripe.data(), cols, 0, noData.has && !noData.isNan ? float(noData.value) : kNaN};
  // Unfinished block rows of every level, by block row.
  std::vector<std::map<int, std::vector<BlockStats>>> open(levelCount);
  auto blockRow = [&](int level, int by) -> std::vector<BlockStats>& {
    auto& row = open[std::size_t(level)][by];
    if (row.empty()) row.resize(std::size_t(layout.blocksX(level)));
    return row;
  };
  std::vector<float> levelRow, lo, hi, err;
  const int lastRow = rows - 1;
  for (int r0 = 0; r0 < lastRow; r0 += stripeRows) {
    const int rEnd = std::min(r0 + stripeRows, lastRow);
    // Rows [r0, rEnd]: the first one is the last stripe's last, kept.
    const int first = r0 == 0 ? 0 : r0 + 1;
    if (r0 > 0) std::copy_n(stripe.begin() + std::ptrdiff_t(std::size_t(stripeRows) * std::size_t(cols)), cols, stripe.begin());
    float* dst = stripe.data() + std::size_t(first - r0) * std::size_t(cols);
    CPLErrorReset();
    if (GDALRasterIO(band, GF_Read, 0, first, cols, rEnd - first + 1, dst, cols, rEnd - first + 1, GDT_Float32, 0,
                     0) != CE_None)
      throw InputError(samplesPath + ": cannot read the samples (truncated or corrupt file?): " + lastGdalError());
    grid.r0 = r0;

    // Level-0 blocks' bounds, folded into every level's blocks (fine rows [8 j, 8 j + 8] closed).
    std::vector<BlockStats> level0(std::size_t(layout.blocksX(0)));
    for (int j = r0 / kPyramidBlockCells; j * kPyramidBlockCells < rEnd; ++j) {
      const int ra = j * kPyramidBlockCells, rb = std::min(ra + kPyramidBlockCells, lastRow);
      for (int i = 0; i < layout.blocksX(0); ++i) {
        const int ca = i * kPyramidBlockCells, cb = std::min(ca + kPyramidBlockCells, cols - 1);
        BlockStats b;
        for (int r = ra; r <= rb; ++r)
          for (int c = ca; c <= cb; ++c)
            if (grid.valid(c, r)) {
              b.lo = std::min(b.lo, grid.at(c, r));
              b.hi = std::max(b.hi, grid.at(c, r));
            }
        level0[std::size_t(i)] = b;
      }
      for (int level = 0; level < levels; ++level) {
        std::vector<BlockStats>& into = blockRow(level, j >> level);
        for (std::size_t i = 0; i < level0.size(); ++i) {
          BlockStats& b = into[i >> level];
          b.lo = std::min(b.lo, level0[i].lo);
          b.hi = std::max(b.hi, level0[i].hi);
        }
      }
    }
    for (int level = 0; level < levels; ++level) {
      const int s = PyramidLayout::step(level);
      const int nc = layout.levelCols(level), nr = layout.levelRows(level);
      // Cell rows j whose rows [fineRow(j), fineRow(j + 1)] lie in the stripe.
      const int j0 = r0 / s;
      for (int j = j0; j + 1 < nr && layout.fineRow(level, j + 1) <= rEnd; ++j) {
        if (level == 0) continue;
        std::vector<BlockStats>& row = blockRow(level, j / kPyramidBlockCells);
        const int ra = layout.fineRow(level, j), rb = layout.fineRow(level, j + 1);
        for (int i = 0; i + 1 < nc; ++i) {
          const double e = coarseCellError(grid, layout.fineColumn(level, i), ra, layout.fineColumn(level, i + 1), rb);
          BlockStats& b = row[std::size_t(i / kPyramidBlockCells)];
          b.error = std::max(b.error, e);
        }
      }
      // The level's kept rows in [r0, rEnd), and the last row at the end.
      if (level > 0) {
        levelRow.resize(std::size_t(nc));
        for (int j = j0; j < nr; ++j) {
          const int r = layout.fineRow(level, j);
          if (r >= rEnd && !(r == lastRow && rEnd == lastRow)) break;
          for (int i = 0; i < nc; ++i) levelRow[std::size_t(i)] = grid.at(layout.fineColumn(level, i), r);
          heightPages[std::size_t(level)]->writeRow(1, j, levelRow.data());
        }
      }
      // Block rows that end in this stripe are complete.
      auto& rowsOpen = open[std::size_t(level)];
      while (!rowsOpen.empty()) {
        const int by = rowsOpen.begin()->first;
        if (layout.fineRow(level, std::min((by + 1) * kPyramidBlockCells, nr - 1)) > rEnd) break;
        const std::vector<BlockStats>& done = rowsOpen.begin()->second;
        lo.resize(done.size());
        hi.resize(done.size());
        err.resize(done.size());
        for (std::size_t i = 0; i < done.size(); ++i) {
          const bool any = done[i].lo <= done[i].hi;
          lo[i] = any ? done[i].lo : kNaN;
          hi[i] = any ? done[i].hi : kNaN;
          err[i] = roundUp(done[i].error);
        }
        StagedPage& page = *blockPages[std::size_t(level)];
        page.writeRow(1, by, lo.data());
        page.writeRow(2, by, hi.data());
        page.writeRow(3, by, err.data());
        rowsOpen.erase(rowsOpen.begin());
      }
    }
    if (options.progress) options.progress(0.8 * double(rEnd) / double(lastRow));
  }

  // The header, then every page in order.
  std::vector<StagedPage*> pages;
  for (int level = 1; level < levels; ++level) pages.push_back(heightPages[std::size_t(level)].get());
  for (int level = 0; level < levels; ++level) pages.push_back(blockPages[std::size_t(level)].get());
  std::vector<std::pair<std::string, std::string>> header = {
      {kPyramidKeyVersion, std::to_string(kPyramidFormatVersion)},
      {kPyramidKeyCols, std::to_string(cols)},
      {kPyramidKeyRows, std::to_string(rows)},
      {kPyramidKeyLevels, std::to_string(levels)},
      {kPyramidKeyBlockCells, std::to_string(kPyramidBlockCells)},
      {kPyramidKeyTerrainBytes, std::to_string(fingerprint.bytes)},
      {kPyramidKeyTerrainHead, hex32(fingerprint.headCrc)},
      {kPyramidKeyTerrainTail, hex32(fingerprint.tailCrc)}};
  for (std::size_t k = 0; k < pages.size(); ++k) {
    GDALFlushCache(pages[k]->dataset());
    header.emplace_back(pyramidPageCrcKey(int(k) + 1), hex32(pages[k]->crc()));
  }
  GdalDataset terrain = openRaster(terrainPath);
  double gt[6];
  const bool hasGt = GDALGetGeoTransform(static_cast<GDALDatasetH>(terrain.get()), gt) == CE_None;
  const std::string wkt = crsWkt(terrain.get());
  OutputFile out(pyramidPath, ".tif");
  std::function<void(double)> assemblyProgress;
  if (options.progress) assemblyProgress = [&](double f) { options.progress(0.8 + 0.2 * f); };
  assemble(out.tempPath(), pages, layout, hasGt ? gt : nullptr, wkt, noData, header, pyramidPath, assemblyProgress);
  out.commit();
  return {levels, stripe.size() * sizeof(float)};
}

}  // namespace nestwalk::terrain
