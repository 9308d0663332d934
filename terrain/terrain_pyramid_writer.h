// Writing a terrain file's pyramid (terrain_pyramid_format.h) in one streaming pass: the import's
// last stage, and what `make-terrain`, `build-scene` and every other writer of a terrain file run
// after it.
//
// The pass reads the fine grid in stripes of T rows (minStripeRows rounded up to a multiple of the
// top level's step 2^(levels - 1), so each stripe holds whole cells of every level), keeping one
// stripe and the accumulators of the unfinished block rows: peak memory about (T + 1) x cols x 4
// bytes plus GDAL's block cache, whatever the number of rows. T grows with the grid's larger side
// (the top step is about side / 64): 256 rows up to 16,384 cells a side, 512 for 32,768 (64 MB a
// stripe), 1,024 for 65,536 (256 MB). Per stripe it
//   - takes every level's kept samples (level L's heights page),
//   - bounds every level-0 block by its lowest and highest valid fine sample, and every coarser
//     block by the level-0 blocks inside it (a max-pyramid, linear),
//   - evaluates every cell of every level >= 1 against the fine samples under it
//     (coarse_cell_error.h): each fine sample about once per level, so the work is about
//     levels x samples, each answer exact.
// Each page goes to a staging file (compressed fast), then the pages are copied in order into the
// sidecar's temporary file with the header, and that is renamed onto the target (core/output_file.h):
// a failure leaves the old sidecar, if any, as it was.
//
// Errors: InputError naming the file that cannot be read or written. Thread safety: as
// terrain_import.h (its own GDAL datasets; one call per target at a time).
#pragma once

#include <functional>
#include <string>

namespace nestwalk::terrain {

/// Stripes are at least this many fine rows (a multiple of 8, for the level-0 blocks): whole rows of
/// GDAL's 256- and 512-row tiles.
inline constexpr int kPyramidStripeRows = 256;

struct PyramidWriteOptions {
  /// Read the samples from this raster instead of the terrain file: the same grid and values (the
  /// import's staging file, faster to decode than the COG). Empty: the terrain file.
  std::string samplesPath;
  /// The stripes' least height, fine rows (a multiple of 8; rounded up to the top step): tests make
  /// it small so that few rows take many stripes.
  int minStripeRows = kPyramidStripeRows;
  /// Called with the fraction done, 0 to 1, now and then (on the calling thread).
  std::function<void(double)> progress;
};

struct PyramidWriteSummary {
  int levels = 0;
  std::size_t stripeBytes = 0;  // the stripe buffer: what the pass holds beyond fixed-size rows
};

/// Writes the pyramid of the terrain file `terrainPath` (a Float32 raster, at least 2 x 2 samples)
/// to `pyramidPath`, replacing it (the caller decides whether it may).
PyramidWriteSummary writeTerrainPyramid(const std::string& terrainPath, const std::string& pyramidPath,
                                        const PyramidWriteOptions& options = {});

}  // namespace nestwalk::terrain
