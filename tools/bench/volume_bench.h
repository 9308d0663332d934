// The bounding-volume benchmark: nestwalk's overlap tests (sat.h, nested.h, obb_batch.h) timed in
// nanoseconds per test on fixed, seeded sets of random box pairs, next to three peers answering the
// same OBB-OBB question on the same pairs: FCL, libccd and Bullet (peers/box_peers.h). The product's
// own path comes first: testBoxPairs, what `query overlap` runs (both SIMD paths), then the scalar
// testBoxPair it replaced, on the same pairs in the same run.
//
// Pair sets: 1M pairs (20k with quick) of randomly sized and rotated boxes, the centre distance
// scaled so that ~50% or ~5% of the pairs overlap by satObbObb<double>. (The one-vs-many sets went
// with the nested set the product never ran; their generator is still here, unused by any set.)
// Benchmarks are named "volumes/<test>/<set>".
// The output: a table of ns/op per test and set with the peers' figures and the ratios peer /
// nestwalk, each test's disagreements with satObbObb<double> (testNested<double> for the queries),
// the machine, and the targets (bench_document.h).
#pragma once

#include "tools/bench/bench_runner.h"

#include <cstddef>
#include <iosfwd>

namespace nestwalk::bench {

struct VolumeBenchOptions : SuiteOptions {
  std::size_t pairs = 0;        // pairs per set; 0: 1'000'000 (20'000 with quick)
};

/// Registers the "volumes/..." benchmarks (once per process), runs those that match the filter and
/// prints the table, or with opts.json the same as one JSON document, to `out`. Minimum time per
/// benchmark: opts.minTimeSeconds, else 0.5 s (0.02 s quick). Returns 0, or 1 when no benchmark
/// matched or one reported an error.
int runBenchmark(const VolumeBenchOptions& opts, std::ostream& out);

}  // namespace nestwalk::bench
