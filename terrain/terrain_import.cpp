#include "nestwalk/terrain/terrain_import.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/core/output_file.h"
#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/terrain/gdal_util.h"
#include "nestwalk/terrain/terrain_pyramid_format.h"
#include "nestwalk/terrain/terrain_pyramid_writer.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal.h>
#include <gdal_alg.h>
#include <gdal_utils.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <system_error>

namespace nestwalk::terrain {
namespace {

namespace fs = std::filesystem;

/// Scaled progress for one stage of the pipeline (nullptr when progress is off).
struct StageProgress {
  void* data = nullptr;
  StageProgress(bool on, double from, double to) {
    if (on) data = GDALCreateScaledProgress(from, to, GDALTermProgress, nullptr);
  }
  ~StageProgress() {
    if (data) GDALDestroyScaledProgress(data);
  }
  GDALProgressFunc fn() const { return data ? GDALScaledProgress : nullptr; }
  void report(double fraction) const {
    if (data) GDALScaledProgress(fraction, nullptr, data);
  }
};

void checkOutput(const std::string& in, const std::string& out, bool overwrite) {
  std::error_code ec;
  if (!in.empty() && fs::exists(out, ec) && fs::equivalent(in, out, ec))
    throw InputError(out + ": the output is the input file; choose another OUT");
  if (fs::exists(out, ec)) {
    if (fs::is_directory(out, ec)) throw InputError(out + ": is a folder; OUT must be a file name");
    if (!overwrite) throw InputError(out + ": already exists (use --overwrite to replace it)");
  }
  const std::string pyramid = pyramidPathOf(out);
  if (!in.empty() && fs::exists(pyramid, ec) && fs::equivalent(in, pyramid, ec))
    throw InputError(out + ": its terrain pyramid " + pyramid + " would replace the input file; choose another OUT");
  if (fs::exists(pyramid, ec) && !overwrite)
    throw InputError(pyramid + ": already exists (the terrain pyramid of " + out + "; use --overwrite to replace it)");
  const fs::path p(out);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec)) throw InputError(out + ": the folder " + dir.string() + " does not exist");
}

/// Writes the staging dataset (at `stagingPath`) as the terrain COG to a temporary file, then its
/// pyramid (terrain_pyramid_writer.h, renamed into place first; its levels are returned, 0 when none),
/// and renames the COG to `out`.
int writeCogFrom(GDALDatasetH staging, const std::string& stagingPath, const std::string& out,
                 const StageProgress& progress, const StageProgress& pyramidProgress) {
  GDALDriverH cog = GDALGetDriverByName("COG");
  if (!cog) throw std::runtime_error("GDAL has no COG driver");
  OutputFile tmp(out, ".tif");
  // PREDICTOR=STANDARD: horizontal differencing of the floats' bits, lossless; the floating-point
  // predictor packs 7-16 % tighter but doubles the time a tile takes to decode (bench render's
  // 3.2 cm survey: 5.4 against 2.8 ms a 512 x 512 tile), and the paged ground and the chunk loader
  // decode tiles while the walker and the view wait. It encodes somewhat slower (bench render's 1 G
  // survey imported in 171 s against 136), once per survey. LEVEL=1: DEFLATE's fastest (GDAL's
  // default is 6) writes the 100 M-sample survey of bench render's sweep in 15 s instead of 18-20,
  // 3 % larger, and its tiles decode no slower (3.05 against 3.23 ms a 512 x 512 tile).
  const char* options[] = {"COMPRESS=DEFLATE", "LEVEL=1", "PREDICTOR=STANDARD", "BLOCKSIZE=512", "OVERVIEWS=AUTO",
                           "OVERVIEW_RESAMPLING=AVERAGE", "BIGTIFF=IF_SAFER", "NUM_THREADS=ALL_CPUS", nullptr};
  CPLErrorReset();
  GDALDatasetH ds = GDALCreateCopy(cog, tmp.tempPath().c_str(), staging, FALSE, const_cast<char**>(options),
                                   progress.fn(), progress.data);
  if (!ds) throw InputError(out + ": cannot write the terrain file: " + lastGdalError());
  CPLErrorReset();
  GDALClose(ds);
  if (CPLGetLastErrorType() == CE_Failure)
    throw InputError(out + ": cannot write the terrain file: " + lastGdalError());
  PyramidWriteOptions pyramidOptions;
  pyramidOptions.samplesPath = stagingPath;
  if (pyramidProgress.data) pyramidOptions.progress = [&](double f) { pyramidProgress.report(f); };
  // A grid of one row or column is no terrain the engine can walk (heightfield.h): it has no pyramid.
  int levels = 0;
  if (GDALGetRasterXSize(staging) >= 2 && GDALGetRasterYSize(staging) >= 2)
    levels = writeTerrainPyramid(tmp.tempPath(), pyramidPathOf(out), pyramidOptions).levels;
  tmp.commit();
  return levels;
}

GDALDatasetH createStaging(const std::string& path, int cols, int rows) {
  GDALDriverH gtiff = GDALGetDriverByName("GTiff");
  const char* options[] = {"TILED=YES", "BLOCKXSIZE=512", "BLOCKYSIZE=512", "COMPRESS=ZSTD", "ZSTD_LEVEL=1",
                           "BIGTIFF=IF_SAFER", nullptr};
  GDALDatasetH ds = GDALCreate(gtiff, path.c_str(), cols, rows, 1, GDT_Float32, const_cast<char**>(options));
  if (!ds) {
    // ZSTD may be missing from the build: fall back to DEFLATE.
    const char* fallback[] = {"TILED=YES", "BLOCKXSIZE=512", "BLOCKYSIZE=512", "COMPRESS=DEFLATE", "ZLEVEL=1",
                              "BIGTIFF=IF_SAFER", nullptr};
    ds = GDALCreate(gtiff, path.c_str(), cols, rows, 1, GDT_Float32, const_cast<char**>(fallback));
  }
  if (!ds) throw InputError(path + ": cannot create the staging file: " + lastGdalError());
  GDALSetRasterNoDataValue(GDALGetRasterBand(ds, 1), kTerrainNoData);
  return ds;
}

struct Stats {
  std::size_t valid = 0, total = 0;
  float lo = std::numeric_limits<float>::infinity(), hi = -std::numeric_limits<float>::infinity();
};

/// Height range and nodata count of band 1 of a staging file, block row by block row.
Stats scanStaging(GDALDatasetH ds, const std::string& name) {
  GDALRasterBandH band = GDALGetRasterBand(ds, 1);
  const int cols = GDALGetRasterXSize(ds), rows = GDALGetRasterYSize(ds);
  std::vector<float> strip;
  Stats s;
  for (int r0 = 0; r0 < rows; r0 += 512) {
    const int n = std::min(512, rows - r0);
    strip.resize(std::size_t(n) * std::size_t(cols));
    if (GDALRasterIO(band, GF_Read, 0, r0, cols, n, strip.data(), cols, n, GDT_Float32, 0, 0) != CE_None)
      throw InputError(name + ": cannot read back the staging file: " + lastGdalError());
    for (float v : strip) {
      if (v == kTerrainNoData || !std::isfinite(v)) continue;
      ++s.valid;
      s.lo = std::min(s.lo, v);
      s.hi = std::max(s.hi, v);
    }
    s.total += strip.size();
  }
  return s;
}

}  // namespace

bool isTerrainCog(const std::string& path) {
  initGdal();
  GdalDataset ds(GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
  if (!ds) return false;
  GDALDriverH driver = GDALGetDatasetDriver(ds.get());
  const char* layout = GDALGetMetadataItem(ds.get(), "LAYOUT", "IMAGE_STRUCTURE");
  double gt[6];
  return driver && std::string(GDALGetDriverShortName(driver)) == "GTiff" && layout && std::string(layout) == "COG" &&
         GDALGetRasterCount(ds.get()) == 1 && GDALGetRasterDataType(GDALGetRasterBand(ds.get(), 1)) == GDT_Float32 &&
         GDALGetGeoTransform(ds.get(), gt) == CE_None;
}

ImportSummary importTerrain(const std::string& in, const std::string& out, const ImportOptions& options) {
  initGdal();
  ImportSummary summary;
  GdalDataset owned = openRaster(in);
  auto* src = static_cast<GDALDatasetH>(owned.get());
  checkBand(src, options.band, in);
  checkOutput(in, out, options.overwrite);
  if (!(options.verticalScale != 0.0 && std::isfinite(options.verticalScale)))
    throw InputError("--vertical-scale must be finite and non-zero");
  if (options.resolution && !(*options.resolution > 0.0 && std::isfinite(*options.resolution)))
    throw InputError("--resolution must be a positive number");
  if (options.window) {
    const auto& w = *options.window;
    if (!(w[0] < w[2] && w[1] < w[3]))
      throw InputError("--window must be MINX MINY MAXX MAXY with MINX < MAXX and MINY < MAXY");
  }

  const RasterFrame frame = rasterFrame(src);
  // Resampling is needed for a new CRS or resolution and for a rotated grid; a grid stored south-up
  // or east-to-west only needs its rows or columns reordered: nearest neighbour, sample-exact.
  const bool resample = !options.targetCrs.empty() || options.resolution.has_value() || frame.rotated;
  const bool warp = resample || frame.flipRows || frame.flipColumns;
  if (!frame.georeferenced) {
    if (warp || options.window)
      throw InputError(in + ": no georeferencing, so it cannot be cropped to map coordinates, resampled or reprojected");
    summary.warnings.push_back(in + ": no georeferencing; the terrain is written in pixel units (cell size 1)");
  }
  if (frame.rotated) summary.warnings.push_back(in + ": rotated or sheared geotransform; warped north-up");
  if (!options.targetCrs.empty()) {
    if (crsWkt(src).empty()) throw InputError(in + ": has no CRS, so it cannot be reprojected to " + options.targetCrs);
    OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
    const bool ok = OSRSetFromUserInput(srs, options.targetCrs.c_str()) == OGRERR_NONE;
    OSRDestroySpatialReference(srs);
    if (!ok) throw InputError("--crs " + options.targetCrs + ": not a CRS GDAL knows");
  }

  // 1. Scan the input band: readable, finite, not all nodata. Without the warper the one pass of
  // stage 3 sees the input's samples as they are and checks them itself (one read of IN, not two).
  const double passFrom = warp ? 0.25 : 0.0;
  if (warp) {
    const StageProgress scanProgress(options.progress, 0.0, 0.25);
    GDALRasterBandH band = GDALGetRasterBand(src, options.band);
    const BandNoData noData = bandNoData(band);
    const int cols = GDALGetRasterXSize(src), rows = GDALGetRasterYSize(src);
    int bx = 0, by = 0;
    GDALGetBlockSize(band, &bx, &by);
    const int stripRows = std::max(std::max(by, 1), int(std::min<long>(rows, (1L << 22) / cols)));
    std::vector<double> strip;
    std::size_t valid = 0;
    for (int r0 = 0; r0 < rows; r0 += stripRows) {
      const int n = std::min(stripRows, rows - r0);
      readRowsFloat64(band, r0, cols, n, strip, in);
      for (std::size_t i = 0; i < strip.size(); ++i) {
        const double v = strip[i];
        if (noData.hole(v)) continue;
        if (!std::isfinite(v))
          throw InputError(in + ": NaN or infinite sample at column " + std::to_string(i % std::size_t(cols)) +
                           ", row " + std::to_string(r0 + int(i / std::size_t(cols))) + " (band " +
                           std::to_string(options.band) + " declares no such nodata value)");
        ++valid;
      }
      scanProgress.report(double(r0 + n) / rows);
    }
    if (valid == 0) throw InputError(in + ": every sample is nodata (no ground at all)");
  }

  // 2. The virtual chain: band (and crop) through gdal_translate, then the warper when needed.
  GdalArgv tArgs;
  tArgs.args = {"-of", "VRT", "-b", std::to_string(options.band)};
  if (options.window && !warp) {
    const auto& w = *options.window;
    tArgs.args.insert(tArgs.args.end(),
                      {"-projwin", gdalNumber(w[0]), gdalNumber(w[3]), gdalNumber(w[2]), gdalNumber(w[1])});
  }
  GDALTranslateOptions* tOpts = GDALTranslateOptionsNew(tArgs.get(), nullptr);
  CPLErrorReset();
  int usageError = 0;
  GdalDataset translated(GDALTranslate("", src, tOpts, &usageError));
  GDALTranslateOptionsFree(tOpts);
  if (!translated) {
    if (options.window) throw InputError(in + ": the crop window does not fit the raster (" + lastGdalError() + ")");
    throw InputError(in + ": cannot build the import chain: " + lastGdalError());
  }
  GdalDataset warped;
  GDALDatasetH chain = static_cast<GDALDatasetH>(translated.get());
  if (warp) {
    GdalArgv wArgs;
    wArgs.args = {"-of", "VRT",     "-r",         resample ? "bilinear" : "near",
                  "-ot", "Float32", "-dstnodata", gdalNumber(kTerrainNoData)};
    if (!options.targetCrs.empty()) wArgs.args.insert(wArgs.args.end(), {"-t_srs", options.targetCrs});
    if (options.resolution)
      wArgs.args.insert(wArgs.args.end(), {"-tr", gdalNumber(*options.resolution), gdalNumber(*options.resolution)});
    if (!resample) {
      // Only reordering: the same grid, north-up (the window snapped outward to whole samples).
      const double* g = frame.geoTransform;
      const int sc = GDALGetRasterXSize(src), sr = GDALGetRasterYSize(src);
      const double dx = std::abs(g[1]), dy = std::abs(g[5]);
      double x0 = std::min(g[0], g[0] + sc * g[1]), x1 = std::max(g[0], g[0] + sc * g[1]);
      double y0 = std::min(g[3], g[3] + sr * g[5]), y1 = std::max(g[3], g[3] + sr * g[5]);
      if (options.window) {
        const auto& w = *options.window;
        const double nx0 = x0 + std::floor((w[0] - x0) / dx) * dx, nx1 = x0 + std::ceil((w[2] - x0) / dx) * dx;
        const double ny0 = y0 + std::floor((w[1] - y0) / dy) * dy, ny1 = y0 + std::ceil((w[3] - y0) / dy) * dy;
        x0 = std::max(x0, nx0), x1 = std::min(x1, nx1), y0 = std::max(y0, ny0), y1 = std::min(y1, ny1);
        if (!(x1 - x0 >= 0.5 * dx && y1 - y0 >= 0.5 * dy))
          throw InputError(in + ": the crop window does not overlap the raster");
      }
      wArgs.args.insert(wArgs.args.end(), {"-tr", gdalNumber(dx), gdalNumber(dy), "-te", gdalNumber(x0), gdalNumber(y0),
                                           gdalNumber(x1), gdalNumber(y1)});
    } else if (options.window) {
      const auto& w = *options.window;
      wArgs.args.insert(wArgs.args.end(),
                        {"-te", gdalNumber(w[0]), gdalNumber(w[1]), gdalNumber(w[2]), gdalNumber(w[3])});
    }
    GDALWarpAppOptions* wOpts = GDALWarpAppOptionsNew(wArgs.get(), nullptr);
    GDALDatasetH srcs[1] = {chain};
    CPLErrorReset();
    warped.reset(GDALWarp("", nullptr, 1, srcs, wOpts, &usageError));
    GDALWarpAppOptionsFree(wOpts);
    if (!warped) throw InputError(in + ": cannot warp the raster: " + lastGdalError());
    chain = static_cast<GDALDatasetH>(warped.get());
  }

  // 3. One pass: the staging GeoTIFF, heights scaled, nodata mapped to kTerrainNoData.
  const int cols = GDALGetRasterXSize(chain), rows = GDALGetRasterYSize(chain);
  if (cols < 1 || rows < 1) throw InputError(in + ": the crop window holds no sample");
  const OutputFile stagingFile(out, ".tif", "staging");  // scratch, never committed
  GdalDataset staging(createStaging(stagingFile.tempPath(), cols, rows));
  auto* st = static_cast<GDALDatasetH>(staging.get());
  double gt[6];
  if (frame.georeferenced && GDALGetGeoTransform(chain, gt) == CE_None) GDALSetGeoTransform(st, gt);
  const std::string wkt = crsWkt(chain);
  if (!wkt.empty()) GDALSetProjection(st, wkt.c_str());
  Stats stats;
  {
    const StageProgress passProgress(options.progress, passFrom, options.fillNoData ? 0.5 : 0.6);
    GDALRasterBandH band = GDALGetRasterBand(chain, 1);
    GDALRasterBandH outBand = GDALGetRasterBand(st, 1);
    const BandNoData noData = bandNoData(band);
    std::vector<double> strip;
    std::vector<float> outStrip;
    for (int r0 = 0; r0 < rows; r0 += 512) {
      const int n = std::min(512, rows - r0);
      readRowsFloat64(band, r0, cols, n, strip, in);
      outStrip.resize(strip.size());
      for (std::size_t i = 0; i < strip.size(); ++i) {
        const double v = strip[i];
        float h = kTerrainNoData;
        const bool hole = noData.hole(v);
        if (!warp && !hole && !std::isfinite(v))
          throw InputError(in + ": NaN or infinite sample at column " + std::to_string(i % std::size_t(cols)) +
                           ", row " + std::to_string(r0 + int(i / std::size_t(cols))) +
                           (options.window ? " of the crop window" : "") + " (band " + std::to_string(options.band) +
                           " declares no such nodata value)");
        if (!hole && std::isfinite(v)) {
          const float scaled = float(v * options.verticalScale);
          if (std::isfinite(scaled) && scaled != kTerrainNoData) {
            h = scaled;
            ++stats.valid;
            stats.lo = std::min(stats.lo, h);
            stats.hi = std::max(stats.hi, h);
          }
        }
        outStrip[i] = h;
      }
      stats.total += strip.size();
      if (GDALRasterIO(outBand, GF_Write, 0, r0, cols, n, outStrip.data(), cols, n, GDT_Float32, 0, 0) != CE_None)
        throw InputError(out + ": cannot write the staging file: " + lastGdalError());
      passProgress.report(double(r0 + n) / rows);
    }
  }
  if (stats.valid == 0)
    throw InputError(in + ": every sample " + (options.window ? "inside the crop window " : "") + "is nodata");
  if (options.fillNoData && stats.valid < stats.total) {
    const StageProgress fillProgress(options.progress, 0.5, 0.6);
    CPLErrorReset();
    if (GDALFillNodata(GDALGetRasterBand(st, 1), nullptr, options.fillDistance, 0, 0, nullptr, fillProgress.fn(),
                       fillProgress.data) != CE_None)
      throw InputError(in + ": filling nodata failed: " + lastGdalError());
    GDALFlushCache(st);
    stats = scanStaging(st, stagingFile.tempPath());
  }
  GDALFlushCache(st);

  // 4. The COG, through a temporary file renamed at the end.
  {
    const StageProgress cogProgress(options.progress, 0.6, 0.8), pyramidProgress(options.progress, 0.8, 1.0);
    summary.pyramidLevels = writeCogFrom(st, stagingFile.tempPath(), out, cogProgress, pyramidProgress);
    if (summary.pyramidLevels > 0) summary.pyramidPath = pyramidPathOf(out);
  }

  summary.cols = cols;
  summary.rows = rows;
  summary.georeferenced = frame.georeferenced;
  if (frame.georeferenced && GDALGetGeoTransform(st, gt) == CE_None) {
    summary.dx = std::abs(gt[1]);
    summary.dy = std::abs(gt[5]);
  } else {
    summary.dx = summary.dy = 1.0;
  }
  summary.crsName = crsName(wkt);
  summary.minHeight = stats.lo;
  summary.maxHeight = stats.hi;
  summary.noDataFraction = stats.total ? 1.0 - double(stats.valid) / double(stats.total) : 0.0;
  return summary;
}

void writeTerrainCog(const std::string& out, int cols, int rows, const std::vector<float>& heights, double originX,
                     double originY, double dx, double dy, const std::string& crs, bool overwrite) {
  if (cols < 1 || rows < 1 || heights.size() != std::size_t(cols) * std::size_t(rows))
    throw std::invalid_argument("writeTerrainCog: heights do not match cols x rows");
  writeTerrainCog(
      out, cols, rows,
      [&](int r0, int count, float* h) {
        std::copy_n(heights.begin() + std::ptrdiff_t(std::size_t(r0) * std::size_t(cols)),
                    std::size_t(count) * std::size_t(cols), h);
      },
      originX, originY, dx, dy, crs, overwrite);
}

void writeTerrainCog(const std::string& out, int cols, int rows, const TerrainRowSource& source, double originX,
                     double originY, double dx, double dy, const std::string& crs, bool overwrite) {
  initGdal();
  if (cols < 1 || rows < 1) throw std::invalid_argument("writeTerrainCog: no samples");
  checkOutput({}, out, overwrite);
  const OutputFile stagingFile(out, ".tif", "staging");  // scratch, never committed
  GdalDataset staging(createStaging(stagingFile.tempPath(), cols, rows));
  auto* st = static_cast<GDALDatasetH>(staging.get());
  double gt[6] = {originX - 0.5 * dx, dx, 0, originY + 0.5 * dy, 0, -dy};
  GDALSetGeoTransform(st, gt);
  if (!crs.empty()) {
    OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
    if (OSRSetFromUserInput(srs, crs.c_str()) != OGRERR_NONE) {
      OSRDestroySpatialReference(srs);
      throw InputError(crs + ": not a CRS GDAL knows");
    }
    char* wkt = nullptr;
    OSRExportToWkt(srs, &wkt);
    GDALSetProjection(st, wkt);
    CPLFree(wkt);
    OSRDestroySpatialReference(srs);
  }
  // Stripes of kWriteStripeRows rows (the staging file's tiles' height): bounded memory.
  constexpr int kWriteStripeRows = 512;
  std::vector<float> stripe(std::size_t(cols) * std::size_t(std::min(rows, kWriteStripeRows)));
  GDALRasterBandH band = GDALGetRasterBand(st, 1);
  for (int r0 = 0; r0 < rows; r0 += kWriteStripeRows) {
    const int n = std::min(kWriteStripeRows, rows - r0);
    source(r0, n, stripe.data());
    for (std::size_t k = 0; k < std::size_t(n) * std::size_t(cols); ++k)
      if (!std::isfinite(stripe[k])) stripe[k] = kTerrainNoData;
    if (GDALRasterIO(band, GF_Write, 0, r0, cols, n, stripe.data(), cols, n, GDT_Float32, 0, 0) != CE_None)
      throw InputError(out + ": cannot write the staging file: " + lastGdalError());
  }
  GDALFlushCache(st);
  writeCogFrom(st, stagingFile.tempPath(), out, StageProgress(false, 0, 1), StageProgress(false, 0, 1));
}

}  // namespace nestwalk::terrain
