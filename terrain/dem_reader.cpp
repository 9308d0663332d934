#include "nestwalk/terrain/dem_reader.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/terrain/gdal_util.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <system_error>

namespace nestwalk::terrain {

void initGdal() {
  static std::once_flag once;
  std::call_once(once, [] {
    // Never write .aux.xml side-cars (statistics, metadata) next to any file we open.
    CPLSetConfigOption("GDAL_PAM_ENABLED", "NO");
    CPLSetErrorHandler(CPLQuietErrorHandler);
    // Bounded memory whatever the raster's size: GDAL's block cache defaults to 5 % of the
    // machine's memory; 256 MB is plenty for streaming block rows (GDAL_CACHEMAX still overrides).
    if (!CPLGetConfigOption("GDAL_CACHEMAX", nullptr)) GDALSetCacheMax64(GIntBig(256) << 20);
    GDALAllRegister();
  });
}

std::string lastGdalError() {
  const char* msg = CPLGetLastErrorMsg();
  return msg ? std::string(msg) : std::string();
}

void GdalDatasetClose::operator()(void* dataset) const {
  if (dataset) GDALClose(static_cast<GDALDatasetH>(dataset));
}

GdalDataset openRaster(const std::string& path) {
  initGdal();
  namespace fs = std::filesystem;
  std::error_code ec;
  // Paths GDAL resolves itself (/vsi..., connection strings) skip the file checks.
  const bool plainFile = path.rfind("/vsi", 0) != 0;
  if (plainFile) {
    if (!fs::exists(path, ec)) throw InputError(path + ": no such file");
    if (fs::is_directory(path, ec)) throw InputError(path + ": is a folder, not a raster file");
    if (fs::is_regular_file(path, ec) && fs::file_size(path, ec) == 0)
      throw InputError(path + ": empty file (zero bytes), not a raster");
  }
  CPLErrorReset();
  GDALDatasetH ds = GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr);
  if (!ds) {
    const std::string why = lastGdalError();
    throw InputError(path + ": not a raster GDAL can read" + (why.empty() ? "" : " (" + why + ")"));
  }
  GdalDataset owned(ds);
  if (GDALGetRasterCount(ds) < 1) throw InputError(path + ": the raster has no bands");
  if (GDALGetRasterXSize(ds) < 1 || GDALGetRasterYSize(ds) < 1)
    throw InputError(path + ": empty raster (" + std::to_string(GDALGetRasterXSize(ds)) + " x " +
                     std::to_string(GDALGetRasterYSize(ds)) + " samples)");
  return owned;
}

void checkBand(void* dataset, int band, const std::string& path) {
  const int count = GDALGetRasterCount(static_cast<GDALDatasetH>(dataset));
  if (band < 1 || band > count)
    throw InputError(path + ": band " + std::to_string(band) + " does not exist (the raster has " +
                     std::to_string(count) + (count == 1 ? " band)" : " bands)"));
  GDALRasterBandH b = GDALGetRasterBand(static_cast<GDALDatasetH>(dataset), band);
  int blockX = 0, blockY = 0;
  GDALGetBlockSize(b, &blockX, &blockY);
  // A pixel-interleaved raster stores every band's samples in one block: reading one band reads
  // (and GDAL allocates) all of them.
  const char* interleave = GDALGetMetadataItem(static_cast<GDALDatasetH>(dataset), "INTERLEAVE", "IMAGE_STRUCTURE");
  const std::uint64_t bandsPerBlock = interleave && std::string(interleave) == "PIXEL" ? std::uint64_t(count) : 1u;
  const std::uint64_t blockBytes = std::uint64_t(std::max(blockX, 0)) * std::uint64_t(std::max(blockY, 0)) *
                                   std::uint64_t(std::max(GDALGetDataTypeSizeBytes(GDALGetRasterDataType(b)), 1)) *
                                   bandsPerBlock;
  if (blockBytes > kMaxDemBlockBytes)
    throw InputError(path + ": band " + std::to_string(band) + " is stored in blocks of " + std::to_string(blockX) +
                     " x " + std::to_string(blockY) + " samples" +
                     (bandsPerBlock > 1 ? " x " + std::to_string(bandsPerBlock) + " interleaved bands" : std::string()) +
                     " (" + std::to_string(blockBytes >> 20) +
                     " MiB each, more than the " + std::to_string(kMaxDemBlockBytes >> 20) +
                     " MiB allowed): a corrupt header? (gdal_translate -co TILED=YES rewrites a real one)");
}

RasterFrame rasterFrame(void* dataset) {
  auto* ds = static_cast<GDALDatasetH>(dataset);
  RasterFrame f;
  double gt[6];
  if (GDALGetGeoTransform(ds, gt) != CE_None) return f;  // pixel units
  const bool identity = gt[0] == 0 && gt[1] == 1 && gt[2] == 0 && gt[3] == 0 && gt[4] == 0 && gt[5] == 1;
  if (identity && std::string(GDALGetProjectionRef(ds)).empty()) return f;  // GDAL's default: none
  std::copy(gt, gt + 6, f.geoTransform);
  f.georeferenced = true;
  const double scale = std::max(std::abs(gt[1]), std::abs(gt[5]));
  if (std::abs(gt[2]) > 1e-9 * scale || std::abs(gt[4]) > 1e-9 * scale || gt[1] == 0 || gt[5] == 0) {
    f.rotated = true;
    return f;
  }
  const int cols = GDALGetRasterXSize(ds), rows = GDALGetRasterYSize(ds);
  f.flipColumns = gt[1] < 0;
  f.flipRows = gt[5] > 0;
  const double c0 = f.flipColumns ? cols - 1 : 0, r0 = f.flipRows ? rows - 1 : 0;
  f.originX = gt[0] + (c0 + 0.5) * gt[1];
  f.originY = gt[3] + (r0 + 0.5) * gt[5];
  f.dx = std::abs(gt[1]);
  f.dy = std::abs(gt[5]);
  return f;
}

std::string crsWkt(void* dataset) {
  const char* wkt = GDALGetProjectionRef(static_cast<GDALDatasetH>(dataset));
  return wkt ? std::string(wkt) : std::string();
}

std::string crsName(const std::string& wkt) {
  if (wkt.empty()) return "none";
  OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
  std::string name = "unnamed CRS";
  char* w = const_cast<char*>(wkt.c_str());
  if (OSRImportFromWkt(srs, &w) == OGRERR_NONE) {
    if (const char* n = OSRGetName(srs)) name = n;
    OSRAutoIdentifyEPSG(srs);
    const char* auth = OSRGetAuthorityName(srs, nullptr);
    const char* code = OSRGetAuthorityCode(srs, nullptr);
    if (auth && code) name += std::string(" (") + auth + ":" + code + ")";
  }
  OSRDestroySpatialReference(srs);
  return name;
}

std::string rasterHeaderText(const std::string& path) {
  initGdal();
  const GdalDataset ds = openRaster(path);
  auto* d = static_cast<GDALDatasetH>(ds.get());
  GDALRasterBandH band = GDALGetRasterBand(d, 1);
  const BandNoData nd = bandNoData(band);
  char text[256];
  double gt[6] = {0, 1, 0, 0, 0, 1};
  GDALGetGeoTransform(d, gt);
  std::snprintf(text, sizeof text, "%d %d %s nodata %s%.17g gt %.17g %.17g %.17g %.17g %.17g %.17g",
                GDALGetRasterXSize(d), GDALGetRasterYSize(d), GDALGetDataTypeName(GDALGetRasterDataType(band)),
                nd.has ? "" : "none ", nd.value, gt[0], gt[1], gt[2], gt[3], gt[4], gt[5]);
  return text;
}

std::pair<int, int> rasterSize(const std::string& path) {
  initGdal();
  const GdalDataset ds = openRaster(path);
  return {GDALGetRasterXSize(static_cast<GDALDatasetH>(ds.get())), GDALGetRasterYSize(static_cast<GDALDatasetH>(ds.get()))};
}

Heightfield readDem(const std::string& path, const DemReadOptions& options, std::vector<std::string>* warnings) {
  GdalDataset owned = openRaster(path);
  auto* ds = static_cast<GDALDatasetH>(owned.get());
  checkBand(ds, options.band, path);
  const RasterFrame frame = rasterFrame(ds);
  if (frame.rotated)
    throw InputError(path + ": rotated or sheared geotransform; the heightfield needs a north-up grid "
                            "(nestwalk import-terrain warps it north-up)");
  {
    // A header can claim any numbers: the grid must have finite corners and pixel sizes whose
    // inverses are finite (a denormal size makes every position-to-sample division infinite).
    const int c = GDALGetRasterXSize(ds), r = GDALGetRasterYSize(ds);
    const bool usable = std::isfinite(frame.originX) && std::isfinite(frame.originY) && std::isfinite(1.0 / frame.dx) &&
                        std::isfinite(1.0 / frame.dy) && std::isfinite(frame.originX + c * frame.dx) &&
                        std::isfinite(frame.originY - r * frame.dy);
    if (!usable) {
      char what[160];
      std::snprintf(what, sizeof what, "pixel size %g x %g at origin (%g, %g)", frame.dx, frame.dy, frame.originX,
                    frame.originY);
      throw InputError(path + ": unusable geotransform: " + what + " (non-finite, zero or too small to divide by)");
    }
  }
  if (!frame.georeferenced && warnings)
    warnings->push_back(path + ": no georeferencing; coordinates are pixel units (sample column c, row r is at x = c + "
                               "0.5, y = -(r + 0.5))");

  GDALRasterBandH band = GDALGetRasterBand(ds, options.band);
  const BandNoData noData = bandNoData(band);
  const int cols = GDALGetRasterXSize(ds), rows = GDALGetRasterYSize(ds);
  if (cols < 2 || rows < 2)
    throw InputError(path + ": " + std::to_string(cols) + " x " + std::to_string(rows) +
                     " samples; a ground surface needs at least 2 x 2");

  if (std::uint64_t(cols) * std::uint64_t(rows) > options.maxSamples)
    throw InputError(path + ": " + std::to_string(cols) + " x " + std::to_string(rows) + " samples, more than the " +
                     std::to_string(options.maxSamples) +
                     " this reader holds in memory (nestwalk import-terrain --window or --resolution takes a part)");
  std::vector<float> heights(std::size_t(cols) * std::size_t(rows));
  std::vector<double> strip;
  const int stripRows = std::max(1, int(std::min<long>(rows, (1 << 22) / std::max(cols, 1))));
  std::size_t valid = 0;
  for (int r0 = 0; r0 < rows; r0 += stripRows) {
    const int n = std::min(stripRows, rows - r0);
    readRowsFloat64(band, r0, cols, n, strip, path);
    for (int i = 0; i < n; ++i) {
      const int srcRow = r0 + i;
      const int dstRow = frame.flipRows ? rows - 1 - srcRow : srcRow;
      for (int c = 0; c < cols; ++c) {
        const double v = strip[std::size_t(i) * std::size_t(cols) + std::size_t(c)];
        const int dstCol = frame.flipColumns ? cols - 1 - c : c;
        float h = std::numeric_limits<float>::quiet_NaN();
        if (noData.hole(v)) {
          // a hole
        } else if (!std::isfinite(v)) {
          throw InputError(path + ": NaN or infinite sample at column " + std::to_string(c) + ", row " +
                           std::to_string(srcRow) + " (band " + std::to_string(options.band) +
                           " declares no such nodata value)");
        } else {
          h = float(v);
          ++valid;
        }
        heights[std::size_t(dstRow) * std::size_t(cols) + std::size_t(dstCol)] = h;
      }
    }
  }
  if (valid == 0) throw InputError(path + ": every sample is nodata (no ground at all)");
  std::optional<float> nd;
  if (noData.has) nd = float(noData.value);
  return Heightfield(cols, rows, std::move(heights), frame.originX, frame.originY, frame.dx, frame.dy, nd,
                     frame.georeferenced ? crsWkt(ds) : std::string());
}

}  // namespace nestwalk::terrain
