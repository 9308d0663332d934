// The imagery import behind `nestwalk import-terrain ... --imagery ORTHO`: an orthophoto (any
// raster GDAL reads: RGB, RGBA, grey, 8- or 16-bit) becomes a Cloud-Optimized GeoTIFF in the
// terrain's CRS, ready for draping (terrain_imagery.h) and for the imagery levels of the survey
// pipeline: 8-bit RGB (or grey), tiled kImageryTileSize, JPEG at kImageryJpegQuality with the
// imagery's holes as a mask (GDAL's COG driver turns an alpha band into one), and overviews down to
// one tile, averaged (the COG driver's). An orthophoto that already is such a file in every way the
// drape needs (a single-file GeoTIFF, 8-bit, in the terrain's CRS, tiled with overviews:
// imageryReadyToDrape) is copied byte for byte instead, whatever its compression and tile size:
// encoding it again would only lose detail.
//
// Stages: the orthophoto is opened as a drape would open it (TerrainImagery: its CRS checked
// against the terrain's, what is refused there is refused here); a virtual chain then warps it to
// the terrain's CRS at its own resolution where the two CRSs differ (bilinear, holes as alpha) and
// scales other than 8-bit colours to 0-255 from each band's range; the COG driver writes it to a
// temporary file beside OUT, renamed at the end. ORTHO is never written to; OUT is replaced only
// with `overwrite`. Every problem is an InputError naming the file.
// Thread safety: as terrain_import.h (GDAL's progress bar keeps static state).
#pragma once

#include "nestwalk/terrain/terrain_imagery.h"  // kImageryJpegQuality

#include <string>
#include <vector>

namespace nestwalk::terrain {

/// Pixels per side of the COG's tiles.
inline constexpr int kImageryTileSize = 512;

struct ImageryImportSummary {
  int cols = 0, rows = 0, bands = 0;  // bands: 3 (RGB) or 1 (grey), plus the mask
  double pixelSize = 0;               // metres (terrain CRS units) per pixel
  bool reprojected = false;           // warped from the orthophoto's CRS to the terrain's
  bool masked = false;                // holes kept (a mask, an alpha band or a nodata value)
  int overviews = 0;
  bool copied = false;                // already a tiled GeoTIFF ready to drape: copied as it is
  std::string crsName;
  std::vector<std::string> warnings;  // what was assumed (a missing CRS), naming the file
};

/// Writes `in` as the imagery COG `out` in the CRS `terrainCrsWkt` (WKT; empty: the terrain has
/// none, and the imagery is taken as it is, as a drape would), or copies it (see above).
ImageryImportSummary importImagery(const std::string& in, const std::string& out, const std::string& terrainCrsWkt,
                                   bool overwrite = false, bool progress = false);

/// Pixels: imagery up to this many a side is drawn as it is, however it is stored (a few reads of
/// the whole of it cost little); larger imagery must be tiled with overviews (below).
inline constexpr int kImageryReadySide = 4096;

/// Whether `path` can be draped over a terrain in `terrainCrsWkt` as it is, fast at every view: a
/// raster of 8-bit bands in the terrain's CRS (or without one), and either at most kImageryReadySide
/// pixels a side or tiled (blocks narrower than its width) with overviews. False for anything else,
/// including a file GDAL cannot open (the drape's own opening says why). What the terrain cache
/// imports once instead (scene/terrain_cache.h).
bool imageryReadyToDrape(const std::string& path, const std::string& terrainCrsWkt);

/// Where import-terrain writes OUT's imagery: OUT without its extension, then "_imagery.tif".
std::string imageryPathOf(const std::string& terrainOut);

}  // namespace nestwalk::terrain
