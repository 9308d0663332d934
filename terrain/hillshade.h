// Horn's (1981) hillshade: the slope from the 3 x 3 weighted differences of the sample grid and
// Lambert's cosine towards the sun, the rule of GDAL's `gdaldem hillshade` (GDALDEMProcessing
// "hillshade", algorithm Horn, z factor 1); tests/terrain/hillshade_test.cpp compares the two
// sample by sample. One rule for every picture of the terrain: the report's top-down map shades
// its samples with it, and the renderer bakes it into each terrain chunk at the chunk's level
// (terrain_chunk.h: the same 3 x 3 rule on the level's samples, `step` samples apart).
//
// Frames: the heightfield's (terrain/heightfield.h): columns east, rows south, dx and dy metres;
// heights metres. The sun direction is a unit vector towards the sun in map axes (x east, y north,
// z up).
//
// Where GDAL and this rule differ: a neighbour that is missing (a hole, or beyond the grid) is here
// extrapolated linearly through the centre sample from the opposite neighbour (or taken as the
// centre's height when that is missing too), so that a plane shades exactly to its edges; GDAL
// leaves such samples without a value (or, with -compute_edges, takes the centre's height).
//
// Thread safety: pure functions; the heightfield is only read.
#pragma once

#include "nestwalk/terrain/heightfield.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>

namespace nestwalk::terrain {

/// The unit vector towards a sun at `azimuthDeg` (clockwise from north) and `altitudeDeg` above
/// the horizon, in map axes.
Eigen::Vector3d sunDirection(double azimuthDeg, double altitudeDeg);

/// The shade at the valid sample (col, row): max(0, n · sun) in [0, 1], n the unit normal of the
/// surface from Horn's differences (see above) over the neighbours `step` samples away (step 1:
/// GDAL's rule on the full grid; step 2^k: the same rule on level k's coarser grid).
double hornShade(const Heightfield& hf, int col, int row, const Eigen::Vector3d& sun, int step = 1);

/// The same on samples read by `heightOrNaN(c, r)` (NaN for a hole) from a grid of cols x rows
/// samples dx x dy apart: for a chunk whose samples come from the terrain pyramid's level page.
template <class HeightOrNaN>
double hornShadeOf(const HeightOrNaN& heightOrNaN, int cols, int rows, double dx, double dy, int col, int row,
                   const Eigen::Vector3d& sun, int step = 1) {
  const double centre = heightOrNaN(col, row);
  // Neighbour (col + dc, row + dr); a missing one (a hole, beyond the grid) extrapolated through
  // the centre from the opposite one, or the centre's height.
  auto at = [&](int c, int r) {
    return c >= 0 && r >= 0 && c < cols && r < rows ? double(heightOrNaN(c, r)) : std::numeric_limits<double>::quiet_NaN();
  };
  auto z = [&](int dc, int dr) -> double {
    dc *= step;
    dr *= step;
    if (const double h = at(col + dc, row + dr); !std::isnan(h)) return h;
    if (const double h = at(col - dc, row - dr); !std::isnan(h)) return 2 * centre - h;
    return centre;
  };
  // Rows run south: dr = -1 is the northern neighbour.
  const double dzdx = ((z(1, -1) + 2 * z(1, 0) + z(1, 1)) - (z(-1, -1) + 2 * z(-1, 0) + z(-1, 1))) / (8 * step * dx);
  const double dzdy = ((z(-1, -1) + 2 * z(0, -1) + z(1, -1)) - (z(-1, 1) + 2 * z(0, 1) + z(1, 1))) / (8 * step * dy);
  return std::max(0.0, Eigen::Vector3d(-dzdx, -dzdy, 1).normalized().dot(sun));
}

}  // namespace nestwalk::terrain
