// The terrain benchmark: nestwalk's heightfield queries (Heightfield::groundHeight and
// Heightfield::intersectRay) timed in nanoseconds per ray next to peers answering the same rays on
// the same triangulated surface: Embree (rtcIntersect1 on the grid's triangles as float), Bullet
// (btHeightfieldTerrainShape::performRaycast, without its accelerator, which misses hits here), OpenSceneGraph
// (osgUtil::LineSegmentIntersector on a geometry with a KdTree) and a plain direct lookup (bilinear
// read of the grid, no triangle logic: the floor a ground query can hope for).
//
// Data: a deterministic rough synthetic DEM of 2049 x 2049 samples at 1 m (~8.4M triangles; 257 x 257
// with quick) at a UTM-like origin, and three ray sets of 1M rays each (20k with quick):
// vertical rays at uniform random positions, vertical rays along a walking path (consecutive
// positions 0.1 m apart, smoothly turning) and oblique rays (from 1.5 to 50 m above the ground,
// 5 to 60 degrees below the horizontal, 500 m long). OSG, and Bullet on the oblique set, answer
// only the first 50k rays of a set (they take microseconds per ray).
// Benchmarks are named "terrain/<method>/<set>"; runTerrainBench prints ns per ray and the ratios
// peer ns / nestwalk ns, the targets, each peer's hit/miss disagreements and largest height
// difference against nestwalk (counted outside the timed loops), and the per-level error table of
// the grid's terrain mesh (terrain/terrain_mesh.h).
#pragma once

#include <cstddef>
#include <iosfwd>
#include <string>

namespace nestwalk::bench {

struct TerrainBenchOptions {
  bool json = false;   // print JSON instead of the table
  bool quick = false;  // smoke test: 257 x 257 grid, 20k rays, short minimum time
  int gridSamples = 0;  // samples per side; 0: 2049 (257 with quick)
  std::size_t rays = 0;     // rays per set; 0: 1'000'000 (20'000 with quick)
  std::size_t slowRays = 0;  // rays per set for OSG and Bullet's oblique rays; 0: min(rays, 50'000)
  double minTimeSeconds = 0;  // Google Benchmark minimum time per benchmark; 0: 0.5 (0.02 quick)
  int repetitions = 0;        // runs per benchmark, the table shows the median
  /// Regular expression on benchmark names; empty, "all" or ".": every "terrain/" benchmark.
  std::string filter;
  /// Also send Google Benchmark's own report to this stream while running.
  std::ostream* googleBenchmarkOutput = nullptr;
};

/// Registers the "terrain/..." benchmarks (once per process; later calls update sizes and times).
void registerTerrainBenchmarks(const TerrainBenchOptions& opts);

/// Runs the matching benchmarks and prints the table (or JSON) to `out`. Returns 0, or 1 when no
/// benchmark matched or one reported an error.
int runTerrainBench(const TerrainBenchOptions& opts, std::ostream& out);

}  // namespace nestwalk::bench
