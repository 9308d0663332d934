// The terrain benchmark: nestwalk's heightfield queries (Heightfield::groundHeight and
// Heightfield::intersectRay) timed in nanoseconds per ray next to peers answering the same rays on
// the same triangulated surface: Embree, Bullet and OpenSceneGraph (peers/terrain_peers.h), and a
// plain direct lookup (bilinear read of the grid, no triangle logic: the floor a ground query can
// hope for).
//
// Data: a deterministic rough synthetic DEM of 2049 x 2049 samples at 1 m (~8.4M triangles; 257 x
// 257 with quick) at a UTM-like origin, and three ray sets of 1M rays each (20k with quick):
// vertical rays at uniform random positions, vertical rays along a walking path (consecutive
// positions 0.1 m apart, smoothly turning) and oblique rays (from 1.5 to 50 m above the ground, 5 to
// 60 degrees below the horizontal, 500 m long). OSG, and Bullet on the oblique set, answer only the
// first 50k rays of a set (they take microseconds per ray). nestwalk is given map coordinates, the
// peers the grid's local frame (their native precision). Benchmarks are named
// "terrain/<method>/<set>". The output: ns per ray with the ratios peer ns / nestwalk ns, each
// method's hit/miss disagreements and largest height difference against nestwalk (groundHeight on
// the vertical sets, intersectRay on the oblique one; counted outside the timed loops), the
// per-level error table of the grid's chunk quadtree as the renderer cuts it (terrain/terrain_chunk.h)
// and the targets.
#pragma once

#include "tools/bench/bench_runner.h"

#include <cstddef>
#include <iosfwd>

namespace nestwalk::bench {

struct TerrainBenchOptions : SuiteOptions {
  int gridSamples = 0;       // samples per side; 0: 2049 (257 with quick)
  std::size_t rays = 0;      // rays per set; 0: 1'000'000 (20'000 with quick)
  std::size_t slowRays = 0;  // rays per set for OSG and Bullet's oblique rays; 0: min(rays, 50'000)
};

/// Registers the "terrain/..." benchmarks (once per process), runs those that match the filter and
/// prints the tables (or one JSON document) to `out`. Minimum time per benchmark:
/// opts.minTimeSeconds, else 0.5 s (0.02 s quick). Returns 0, or 1 when no benchmark matched or one
/// reported an error.
int runBenchmark(const TerrainBenchOptions& opts, std::ostream& out);

}  // namespace nestwalk::bench
