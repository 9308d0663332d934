// Imagery draped over the terrain (an orthophoto; "imagery" in a scene file): any raster GDAL reads,
// sampled as RGBA8 on a grid of the terrain's map frame, and the engine's own imagery file format.
//
// Input: 1 band (grey), 2 (grey and alpha), 3 (RGB) or 4 (RGBA); the last band of 2 or 4 is the
// alpha whatever its colour interpretation says. A colour-table (paletted) band is refused with a
// hint (gdal_translate -expand rgb), as are complex samples.
// Sample values: 8-bit bands (GDAL's Byte) are taken as they are. Bands of any other type (16-bit,
// 32-bit, floating point) are scaled to 0-255: v' = 255 * (v - lo) / (hi - lo), rounded to the
// nearest and clamped to 0..255, where lo and hi are the smallest minimum and the largest maximum of
// the colour bands (one range for all of them, so the colour balance is kept), as GDAL computes
// them without nodata: exactly for rasters of up to kExactMinMaxPixels pixels, GDAL's approximation
// (from overviews or a subsample) above, so values outside it clamp. A colour range of one value
// (hi == lo) maps to 255. An alpha band of another type than Byte is scaled by its own maximum
// (0 -> 0, the maximum -> 255).
// No data: where the alpha is 0; without an alpha band, where GDAL's mask of band 1 says so (its
// nodata value, or an internal mask). In a reprojected read (below) GDAL's warper decides: without
// an alpha band, a pixel is no data where every colour band holds its nodata value (a colour band
// without one takes band 1's; GDAL's UNIFIED_SRC_NODATA). Colours are averaged over valid pixels
// only, so no-data pixels never bleed into the colour.
//
// Frames and units: every coordinate given to or returned by a TerrainImagery is in the terrain's
// CRS, in its map units (metres for a projected CRS; for a geographic one, degrees with longitude as
// x: GDAL's traditional GIS axis order), x east and y north. The imagery's own frame is GDAL's:
// its geotransform gives pixel corners, and a pixel's colour belongs to its centre.
//  - Same frame: the imagery's CRS is the terrain's (OSRIsSame), or one of them has none (then it is
//    taken to be in the other's frame as it is, with a warning in warnings()). Its geotransform
//    must be north-up (no rotation or shear; south-up or east-to-west storage is fine).
//  - Reprojected: the CRSs differ. The imagery is warped to the terrain's CRS through GDAL's warper,
//    so pixels land where GDAL's own warp (gdalwarp -r bilinear) puts them.
//
// read(x0, y0, spacingX, spacingY, width, height): RGBA8, row-major, row 0 north; pixel (i, j) is
// the imagery's colour at the map point (x0 + i * spacingX, y0 - j * spacingY): a point sample,
// bilinear between the imagery's pixel centres. Where the imagery has no data (beyond its outer
// edge, nodata, alpha 0) the pixel is (0, 0, 0, 0).
//  - Same frame: GDAL's RasterIO (GDALRasterIOEx) with a floating-point source window that puts
//    output pixel i's sample exactly on its point, and bilinear resampling. At a spacing no coarser
//    than the imagery's pixels that is the bilinear point sample; coarser, GDAL widens its bilinear
//    kernel to the spacing (a triangle filter one output pixel in radius, an average around the
//    point) and reads it from the coarsest of the file's overviews still at least as fine as the
//    spacing, so a coarse read costs about what its output size costs. Points between the outermost
//    pixel centres and the imagery's outer edge get the edge pixels' values (GDAL renormalises its
//    weights over the pixels that exist); in a coarse read, a point within half an output pixel of
//    the edge is filtered half an output pixel inward. The alpha (or band 1's mask) is resampled
//    like the colour, so it ramps across one imagery pixel at the edge of no data.
//  - Reprojected: each read runs GDAL's warper (bilinear; the approximate transformer, within
//    kWarpErrorThresholdPixels) from the imagery straight onto the read's own grid, so a read gives
//    what `gdalwarp -r bilinear -te ... -ts width height` gives for that grid, resampled once. A
//    coarse read warps from the overview `gdalwarp -ovr AUTO` would choose: the coarsest whose
//    decimation factor is at most the read's spacing in imagery pixels (at the read's centre) plus
//    kOverviewFactorSlack. The alpha is the warper's destination alpha (255 at a point with any
//    valid imagery pixel among its bilinear neighbours, as GDAL's warper computes it).
//
// Tolerances: positions are exact to rounding in the same frame; a reprojected read's positions
// are within kWarpErrorThresholdPixels imagery pixels of the exact transformation. Colours are
// rounded to the nearest 8-bit level once, at the end.
//
// Errors: the constructor throws InputError naming the file and the problem: the file missing or
// not a raster (openRaster's messages), an unsupported band count, a paletted or complex band, no
// geotransform, a rotated or sheared geotransform, a non-finite or degenerate geotransform, a block
// too large to read (checkBand: kMaxDemBlockBytes), a terrain CRS GDAL cannot read, a
// transformation from the imagery's CRS to the terrain's that GDAL cannot set up. read throws
// std::invalid_argument for a bad request (width or height below 1, more than
// kMaxImageryReadPixels pixels, non-finite coordinates, a spacing not positive and finite) and
// InputError naming the file when GDAL cannot read or warp the data (a truncated file).
//
// Ownership: a TerrainImagery owns its GDAL datasets (the file, opened read-only, and any overview
// levels it opened) and closes them when it goes; read returns a fresh buffer the caller owns.
// Thread safety: one thread at a time, for every member (GDAL datasets are not thread-safe, and read
// caches overview datasets). Separate TerrainImagery objects, even of one file, may be used on
// separate threads. GDAL's process-wide settings are initGdal's (dem_reader.h).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace nestwalk::terrain {

/// Pixels one read returns at most (width * height): 4096 x 4096, a 64 MiB RGBA8 result (a reprojected read
/// holds the warper's buffers besides). A draped tile is far smaller; a larger request is a bug.
inline constexpr std::int64_t kMaxImageryReadPixels = 4096ll * 4096ll;

/// Imagery pixels: the largest error of the warper's approximate transformer (a line of destination
/// pixels is transformed exactly at its ends and middle and interpolated in between where that stays
/// within this). gdalwarp's default; an eighth of a pixel is below what bilinear 8-bit colour shows
/// except at the sharpest edges.
inline constexpr double kWarpErrorThresholdPixels = 0.125;

/// Dimensionless: a reprojected read uses an overview whose decimation factor is at most the read's
/// spacing in imagery pixels plus this (gdalwarp's -ovr AUTO rule: an overview within a tenth of the
/// wanted factor counts as matching it).
inline constexpr double kOverviewFactorSlack = 0.1;

/// Pixels: up to this size (4096 x 4096) the colour range of non-8-bit imagery is computed exactly
/// (one pass over the file when it is opened); above it GDAL's approximate range (overviews or a
/// subsample) keeps opening a large file cheap.
inline constexpr std::uint64_t kExactMinMaxPixels = 1ull << 24;

/// Source pixels: sample positions within this of the imagery's outer edge count as on it (rounding
/// of the map-to-pixel conversion at UTM-sized coordinates is about 1e-10 pixel).
inline constexpr double kImageryEdgeTolerancePixels = 1e-6;

/// An axis-aligned box in the terrain's map frame (map units).
struct ImageryExtent {
  double minX = 0, minY = 0, maxX = 0, maxY = 0;
};

class TerrainImagery {
 public:
  /// Opens the imagery at `path` for draping on a terrain in the CRS `terrainCrsWkt` (WKT, as
  /// Heightfield::crsWkt() gives it; empty: the terrain has no CRS). See above for what is refused.
  TerrainImagery(const std::string& path, const std::string& terrainCrsWkt);
  ~TerrainImagery();
  TerrainImagery(TerrainImagery&&) noexcept;
  TerrainImagery& operator=(TerrainImagery&&) noexcept;
  TerrainImagery(const TerrainImagery&) = delete;
  TerrainImagery& operator=(const TerrainImagery&) = delete;

  /// RGBA8 samples of the grid whose pixel (i, j) is at map (x0 + i * spacingX, y0 - j * spacingY),
  /// width * height * 4 bytes, row-major from the north row (see above).
  std::vector<std::uint8_t> read(double x0, double y0, double spacingX, double spacingY, int width, int height);

  /// The file as given.
  const std::string& path() const;
  /// What was assumed on opening (a missing CRS), each naming the file.
  const std::vector<std::string>& warnings() const;
  /// Whether reads are warped from the imagery's CRS to the terrain's.
  bool reprojected() const;
  /// 1 (grey, drawn as R = G = B) or 3 (RGB).
  int colourBands() const;
  bool hasAlpha() const;
  /// The imagery's footprint in the terrain's frame: its outer edges in the same frame; reprojected,
  /// the bounding box of its warped outline as GDAL's warper computes it (GDALSuggestedWarpOutput2).
  /// Reads outside it return no data.
  ImageryExtent extent() const;
  /// The imagery's pixel size in the terrain's map units: the smaller of its two pixel sides in the
  /// same frame; reprojected, the square pixel GDAL's warper suggests for it.
  double pixelSize() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// Throws InputError naming the imagery's file when its extent does not overlap the terrain's
/// samples' extent [x0, x1] x [y0, y1] (map units, the terrain's CRS): an orthophoto of another
/// place, or in a CRS read wrongly, would drape nothing.
void requireImageryOverlap(const TerrainImagery& imagery, double x0, double y0, double x1, double y1);

/// Writes an RGB 8-bit image (`rgb`: cols x rows pixels, row-major from the north row, 3 bytes each)
/// as the engine's imagery file: a Cloud-Optimized GeoTIFF (512 x 512 tiles, DEFLATE with the
/// horizontal predictor, lossless; overviews averaged down to one tile, so a coarse read is cheap),
/// north-up, pixel (0, 0) centred at (originX, originY), pixels dx by dy map units, in `crs`
/// (anything OSRSetFromUserInput reads; empty: none). Written to a temporary file beside `out` and
/// renamed (core/output_file.h); an existing `out` is replaced only with `overwrite`. InputError
/// naming the file on failure (an existing file without `overwrite`, a missing folder, GDAL unable
/// to write), std::invalid_argument when `rgb` does not hold cols x rows pixels.
void writeImageryCog(const std::string& out, int cols, int rows, const std::vector<std::uint8_t>& rgb, double originX,
                     double originY, double dx, double dy, const std::string& crs, bool overwrite);

/// Rows [r0, r0 + count) of an RGB 8-bit image: count * cols pixels, 3 bytes each, row-major.
using ImageryRowSource = std::function<void(int r0, int count, std::uint8_t* rgb)>;
enum class ImageryCompression { Deflate, Jpeg };
/// Rows a stripe of the streamed writer asks its source for (a tile row).
inline constexpr int kImageryStripeRows = 512;
/// JPEG quality (0-100) of the engine's JPEG imagery files (import-terrain --imagery,
/// imagery_import.h; generated fine orthophotos): 90 keeps a drone orthophoto's texture (tyre
/// tracks, gravel) at about a fifth of its lossless size.
inline constexpr int kImageryJpegQuality = 90;
/// The same, for images too large to hold: the rows asked for kImageryStripeRows at a time into a
/// tiled scratch GeoTIFF beside `out` (removed afterwards), then copied to the COG with its
/// overviews; memory is a stripe. Deflate is lossless; Jpeg (quality kImageryJpegQuality) is what a
/// drone survey's orthophoto usually is, a fifth of the size.
void writeImageryCog(const std::string& out, int cols, int rows, const ImageryRowSource& source, double originX,
                     double originY, double dx, double dy, const std::string& crs, bool overwrite,
                     ImageryCompression compression);

}  // namespace nestwalk::terrain
