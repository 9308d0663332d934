// Fences and barrier rows from lines: a catalog model repeated along a polyline at its length,
// each piece oriented along its segment (the model's forward axis, +y, along the segment's
// direction).
//
// The rule, per segment of length L with pieces of length `piece`: n pieces (n = floor(L / piece)
// or ceil(L / piece), at least 1: the count whose joints come closest to end to end, among those
// within the limits), centred at (i + 1/2) L / n along it. Inside a segment every joint then leaves
// the same gap (L / n - piece > 0) or overlap (piece - L / n > 0) along the line; at a vertex the
// two segments' half-gaps (or half-overlaps) meet, so a joint there is within the limits whenever
// both segments' joints are. At the open ends of a line the first and last pieces stop short of
// (or pass) the end by half a joint. Gaps and overlaps are measured along the line (its
// centreline); at a corner the pieces also overlap on the inside and open on the outside of the
// turn, by their width times tan(turn / 2) / 2, which the line measure does not count.
// A segment that cannot be covered within the limits (shorter than piece - maxOverlap, or whose
// best count leaves joints beyond them) is reported as a problem and laid out with its best count.
// Thread safety: a pure function.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace nestwalk::gis {

struct FencePiece {
  Eigen::Vector2d centre;  // map x, y
  double headingDeg = 0;   // the segment's direction, clockwise from grid north
  std::size_t segment = 0; // index of the segment (from point i to point i + 1; for a ring the
                           // last one closes it)
};

struct FenceLayout {
  std::vector<FencePiece> pieces;
  double largestGap = 0, largestOverlap = 0;  // along the line, over every joint (metres)
  std::vector<std::string> problems;          // segments not covered within the limits
};

/// Lays pieces along `line` (map x, y; at least two points; `closed`: a ring, its last point joined
/// to the first). pieceLength > 0; maxGap, maxOverlap >= 0 (metres).
FenceLayout layoutFence(std::span<const Eigen::Vector2d> line, bool closed, double pieceLength, double maxGap,
                        double maxOverlap);

}  // namespace nestwalk::gis
