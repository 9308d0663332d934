// Reading any raster GDAL reads into a Heightfield, and the GDAL plumbing the terrain tools share
// (opening with clear errors, the sample-centre frame of a raster).
//
// Georeferencing: GDAL's geotransform gives the CORNER of pixel (0, 0); the heightfield's origin is
// the CENTRE of sample (0, 0), half a pixel in from that corner. Rasters stored south-up or
// east-to-west (negative pixel width, positive pixel height) are flipped on reading so row 0 is
// north. A rotated or sheared geotransform is refused here with an InputError (`nestwalk
// import-terrain` warps such rasters north-up). A raster without a geotransform is read in pixel
// units with a warning: sample (col, row) is then at x = col + 0.5, y = -(row + 0.5).
//
// Units: x and y are whatever the raster's CRS uses. For a geographic CRS (e.g. EPSG:4326, as
// mt_rainier_90m.tif) that means x = longitude and y = latitude in degrees (GDAL's traditional
// GIS axis order: east first), dx and dy are degrees, while heights stay metres. Queries then take
// longitude/latitude; slopes or distances computed from such a heightfield mix degrees and metres
// and are meaningless: import with a projected --crs for geometry.
//
// Nodata: the band's nodata value (and NaN where the nodata value is NaN) become NaN holes in the
// heightfield; the heightfield's noData() reports the band's value. Any other NaN or infinite
// sample is bad input (InputError), as is a raster with no valid sample at all.
//
// Thread safety: initGdal is safe from any thread (std::call_once) but sets GDAL's process-wide
// state, for an embedding program's own GDAL use too: it installs CPLQuietErrorHandler as GDAL's
// error handler, sets GDAL_PAM_ENABLED=NO and, unless GDAL_CACHEMAX is set, a 256 MiB block cache.
// lastGdalError() is per thread (GDAL keeps the last error per thread). A GdalDataset, and every
// function given one, is used by one thread at a time (GDAL datasets are not thread-safe); readDem
// opens and closes its own, so calls on different threads share no dataset.
#pragma once

#include "nestwalk/terrain/heightfield.h"

#include <memory>
#include <optional>
#include <cstdint>
#include <string>
#include <vector>

namespace nestwalk::terrain {

/// Registers GDAL's drivers once, turns off .aux.xml side-car files (inputs are never written to)
/// and keeps GDAL's own messages off stderr (they surface in our InputErrors instead).
void initGdal();

/// The last message GDAL reported (empty when none), for error texts.
std::string lastGdalError();

struct GdalDatasetClose {
  void operator()(void* dataset) const;
};
/// An open GDAL dataset (a GDALDatasetH), closed when it goes.
using GdalDataset = std::unique_ptr<void, GdalDatasetClose>;

/// Opens a raster read-only. InputError naming the file for: missing, a folder, zero size, not a
/// raster GDAL recognises, no bands, zero width or height.
GdalDataset openRaster(const std::string& path);

/// The band's number checked against the raster's band count (InputError otherwise).
void checkBand(void* dataset, int band, const std::string& path);

/// Where a raster's samples are: the centre of the sample that becomes heightfield sample (0, 0)
/// and the spacing, after the flips that make row 0 north and column 0 west.
struct RasterFrame {
  double originX = 0.5, originY = -0.5, dx = 1.0, dy = 1.0;
  bool flipColumns = false, flipRows = false;
  bool georeferenced = false;  // false: pixel units
  bool rotated = false;        // a rotated or sheared geotransform (originX/Y, dx, dy then unset)
  double geoTransform[6] = {0, 1, 0, 0, 0, -1};
};
RasterFrame rasterFrame(void* dataset);

/// The raster's CRS as WKT (empty when it has none) and a short name for messages.
std::string crsWkt(void* dataset);
std::string crsName(const std::string& wkt);

/// Samples readDem holds at most (4 bytes each: 1 GiB): a 16384 x 16384 DEM. Larger rasters are
/// refused before anything is allocated (a corrupt header can claim billions), with a message
/// naming import-terrain's --window and --resolution.
inline constexpr std::uint64_t kMaxDemSamples = 1ull << 28;

/// Bytes of one GDAL block (tile or strip; with pixel interleaving, every band's samples in it) at
/// most: 256 MiB, far above any real DEM's (COG tiles of 256-1024 samples, strips of a few rows),
/// far below what a corrupt header can claim (a 300-byte TIFF of some 58,000 interleaved bands
/// asked GDAL for a 12 GB strip; found by the fuzzer). checkBand refuses larger blocks before
/// GDAL allocates one.
inline constexpr std::uint64_t kMaxDemBlockBytes = 256ull << 20;

struct DemReadOptions {
  int band = 1;
  std::uint64_t maxSamples = kMaxDemSamples;
};

/// The raster's size in samples (columns, rows), from its header alone (openRaster's errors).
std::pair<int, int> rasterSize(const std::string& path);
/// What band 1's header says beyond the size, as text: its data type, nodata value and the
/// geotransform (what a cache keys on when the samples are not read).
std::string rasterHeaderText(const std::string& path);

/// Reads band `options.band` of the raster at `path` into a Heightfield (see above). Warnings (no
/// georeferencing) are appended to `warnings` when given. InputError on any bad input, naming the
/// file: the errors of openRaster, fewer than 2 x 2 samples, a band out of range, a rotated
/// geotransform, more than options.maxSamples samples, unreadable data (a truncated or corrupt
/// file), NaN or infinite samples, no valid sample. The whole band is held in memory (4 bytes a sample): the reader is for queries, the
/// import pipeline streams.
Heightfield readDem(const std::string& path, const DemReadOptions& options = {},
                    std::vector<std::string>* warnings = nullptr);

}  // namespace nestwalk::terrain
