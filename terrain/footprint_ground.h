// The ground under a footprint: the lowest and highest terrain height over a convex polygon of map
// positions (an instance's outline seen from above), for standing equipment on the ground.
//
// Exact for the heightfield's surface (heightfield.h: triangles split along each cell's NW-SE
// diagonal, linear on each): over a convex polygon a piecewise-linear surface takes its extremes at
// a polygon vertex, at a sample inside the polygon, or where a polygon edge crosses a grid line
// (a sample row or column) or a cell diagonal. Every such point is evaluated with
// Heightfield::groundHeight, so the lowest height is the exact minimum over the polygon (to the
// rounding of the crossing points). Points without ground (holes, beyond the outermost samples)
// are counted, not used.
// Thread safety: a pure function; the heightfield is only read.
#pragma once

#include "nestwalk/terrain/heightfield.h"

#include <Eigen/Core>

#include <cstddef>
#include <span>

namespace nestwalk::terrain {

struct GroundSpan {
  double lowest = 0, highest = 0;  // map z over the points with ground (0 when there is none)
  std::size_t points = 0;          // points evaluated that have ground
  std::size_t missing = 0;         // points evaluated without ground
  bool complete() const { return points > 0 && missing == 0; }
  double rise() const { return highest - lowest; }
};

/// The ground under `polygon` (map x, y, convex, either orientation; a single point or a segment
/// are allowed too).
GroundSpan groundUnderPolygon(const Heightfield& hf, std::span<const Eigen::Vector2d> polygon);

}  // namespace nestwalk::terrain
