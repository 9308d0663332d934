// The terrain import pipeline behind `nestwalk import-terrain IN OUT`: any raster GDAL reads becomes
// the engine's terrain format, a Cloud-Optimized GeoTIFF of Float32 heights in metres (tiled 512 x
// 512, DEFLATE with the horizontal predictor, overviews, the CRS; nodata = kTerrainNoData).
//
// Stages, all streaming block by block so memory stays bounded whatever the raster's size:
//   1. IN is opened read-only and its samples checked: unreadable data (truncated file), NaN or
//      infinite samples (unless NaN is the declared nodata) and an all-nodata band are refused.
//      When warping, IN's band is scanned first; otherwise the pass of stage 3 checks as it copies.
//   2. A virtual chain: gdal_translate to VRT (band choice; crop when not warping), then, when a
//      target CRS or resolution is asked for, or the geotransform is rotated/sheared, GDAL's warper
//      (bilinear, to a north-up grid) as a warped VRT, cropped to the window there. A grid stored
//      south-up or east-to-west goes through the warper with nearest neighbour (sample-exact), so
//      every terrain file is north-up.
//   3. One pass over the chain writes a tiled staging GeoTIFF (vertical scale applied, nodata mapped
//      to kTerrainNoData), then GDALFillNodata fills holes when asked.
//   4. The COG driver's CreateCopy writes the result to a temporary file in OUT's folder.
//   5. The terrain pyramid (terrain_pyramid_format.h) is written from the staging file in one
//      streaming pass to its sidecar pyramidPathOf(OUT), renamed into place; then the COG is
//      renamed to OUT. OUT and its sidecar are replaced only with `overwrite`; IN is never written to.
// Every problem is an InputError naming the file; on any failure OUT is left as it was.
// Thread safety: each call opens its own GDAL datasets (initGdal's process-wide settings apply,
// dem_reader.h). Two calls at once in one process must not write the same OUT (the temporary names
// depend only on OUT and the process id, core/output_file.h), and `progress` uses GDAL's
// GDALTermProgress, which keeps static state: one import with progress at a time.
#pragma once

#include <array>
#include <optional>
#include <functional>
#include <string>
#include <vector>

namespace nestwalk::terrain {

/// The nodata value of every terrain file nestwalk writes.
inline constexpr float kTerrainNoData = -32768.0f;

struct ImportOptions {
  int band = 1;
  /// Crop window in map coordinates of the output CRS: minX, minY, maxX, maxY.
  std::optional<std::array<double, 4>> window;
  /// Output cell size (square cells) in the output CRS's units; unset: keep the input's.
  std::optional<double> resolution;
  /// Output CRS, anything GDAL's SetFromUserInput accepts ("EPSG:32651", WKT, PROJ); empty: keep.
  std::string targetCrs;
  /// Fill nodata holes by interpolation (GDALFillNodata) up to fillDistance pixels from valid data.
  bool fillNoData = false;
  double fillDistance = 100.0;
  /// Heights are multiplied by this (0.3048 for feet).
  double verticalScale = 1.0;
  bool overwrite = false;
  /// GDAL's terminal progress bar on stderr.
  bool progress = false;
};

struct ImportSummary {
  int cols = 0, rows = 0;
  double dx = 0, dy = 0;
  bool georeferenced = false;
  std::string crsName;  // "none" when the output has no CRS
  float minHeight = 0, maxHeight = 0;
  double noDataFraction = 0;
  std::string pyramidPath;  // the terrain pyramid written beside OUT (empty for a grid of one row or column)
  int pyramidLevels = 0;
  std::vector<std::string> warnings;
};

/// Whether `path` is already in the engine's terrain format: a GeoTIFF with the COG layout, one
/// Float32 band, georeferenced. (build-scene uses such a DEM as it is instead of importing it.)
bool isTerrainCog(const std::string& path);

/// Imports `in` to `out` (see above).
ImportSummary importTerrain(const std::string& in, const std::string& out, const ImportOptions& options);

/// Writes a north-up Float32 grid (row 0 north, heights row-major, NaN = hole) as the terrain COG
/// and its pyramid, through the same temporary-file-and-rename path. originX/Y: centre of sample (0, 0).
void writeTerrainCog(const std::string& out, int cols, int rows, const std::vector<float>& heights, double originX,
                     double originY, double dx, double dy, const std::string& crs, bool overwrite);

/// Rows [r0, r0 + count) of a grid, row-major, NaN = hole.
using TerrainRowSource = std::function<void(int r0, int count, float* heights)>;
/// The same, the rows asked for stripe by stripe (a grid too large to hold: make-terrain's).
void writeTerrainCog(const std::string& out, int cols, int rows, const TerrainRowSource& source, double originX,
                     double originY, double dx, double dy, const std::string& crs, bool overwrite);

}  // namespace nestwalk::terrain
