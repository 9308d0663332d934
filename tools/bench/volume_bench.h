// The bounding-volume benchmark: nestwalk's overlap tests (sat.h, nested.h, obb_batch.h) timed in
// nanoseconds per test on fixed, seeded sets of random box pairs, next to three peers answering the
// same OBB-OBB question on the same pairs: FCL (fcl::OBB<double>::overlap), libccd (MPR with box
// support functions) and Bullet (btBoxBoxDetector, the ODE box-box test).
//
// Pair sets: 1M pairs (20k with quick) of randomly sized and rotated boxes, the centre distance
// scaled so that ~50% or ~5% of the pairs overlap by satObbObb<double>. One-vs-many: one viewer
// against 1M stored boxes (NestedBoxSet::queryOverlaps), sized so that ~1% or ~10% of the stored
// boxes survive the AABB stage. Benchmarks are named "volumes/<test>/<set>" and are registered
// with Google Benchmark; runVolumeBench runs them and prints a table of ns/op and of the ratio
// peer / nestwalk (or JSON).
#pragma once

#include <cstddef>
#include <iosfwd>
#include <string>

namespace nestwalk::bench {

struct VolumeBenchOptions {
  bool json = false;   // print JSON instead of the table
  bool quick = false;  // smoke test: 20k pairs and stored boxes, short minimum time
  std::size_t pairs = 0;        // pairs per set; 0: 1'000'000 (20'000 with quick)
  std::size_t storedBoxes = 0;  // boxes of the one-vs-many sets; 0: as pairs
  double minTimeSeconds = 0;    // Google Benchmark minimum time per benchmark; 0: 0.5 (0.02 quick)
  int repetitions = 0;  // runs per benchmark, the table shows the median; 0: --benchmark_repetitions (1)
  /// Regular expression on benchmark names (Google Benchmark's --benchmark_filter); empty, "all"
  /// or ".": every "volumes/" benchmark.
  std::string filter;
  /// Also send Google Benchmark's own report (console, or --benchmark_format) to this stream
  /// while running; null: print nothing but the final table or JSON.
  std::ostream* googleBenchmarkOutput = nullptr;
};

/// Registers the "volumes/..." benchmarks with Google Benchmark (once per process; later calls only
/// update the sizes and minimum time taken from `opts`).
void registerVolumeBenchmarks(const VolumeBenchOptions& opts);

/// Registers the benchmarks, runs those that match the filter through
/// benchmark::RunSpecifiedBenchmarks with a collecting reporter, and prints to `out` the table
/// (rows per test and set; columns nestwalk, FCL, ccd MPR, Bullet in ns/op and the ratios
/// peer / nestwalk), the build and machine information, the peers' disagreements with
/// satObbObb<double> and the targets; with opts.json the same as one JSON document.
/// Returns 0, or 1 when no benchmark matched or one reported an error.
int runVolumeBench(const VolumeBenchOptions& opts, std::ostream& out);

}  // namespace nestwalk::bench
