// The walker benchmark (`nestwalk bench walker`):
//  1. walker steps without rendering over 1k, 100k and 1M box-shaped instances scattered over
//     10 km x 10 km of rolling synthetic terrain (poles to containers, random headings): p50 / p99
//     / max µs per step, each step timed on its own, contacts per 1000 steps;
//  2. the broad-phase query side by side with Bullet's btDbvt and FCL's DynamicAABBTree on the same
//     boxes, and build times (tools/bench/broadphase_bench.h);
//  3. BV tests per hierarchy on the bundled flythroughs, printed like Table 2 of the fACT
//     paper ("Bounding volume hierarchies for collision detection"): hierarchy node tests and
//     the three stages per script, and the total as a % of the template hierarchy's; every
//     hierarchy must give the same contacts (checked, reported);
//  4. the narrow phase per query: the scalar nested test against the batch, by candidate count;
//  5. routes and results: each bundled flythrough recorded as `nestwalk run` does, its results
//     layers' share of the run's wall time (target <= 5 %), and a 10,000-fix GPS track turned
//     into a timed script (target well under a second).
#pragma once

#include "tools/bench/bench_runner.h"

#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

namespace nestwalk::bench {

struct WalkerBenchOptions : BenchOptions {
  std::vector<std::size_t> sizes;    // instance counts; empty: 1k, 100k, 1M (quick: 1k, 10k)
  std::size_t steps = 0;             // timed steps per size; 0: 200k (quick 5k)
  std::string scene;                 // scene for the Table-2 counts
  std::vector<std::string> scripts;  // its flythroughs
  bool table2 = true;                // run part 3 (needs scene and scripts)
  bool broadPhase = true;            // run part 2
};

/// Runs the three parts and prints their tables (or one JSON document) to `out`. Returns 0, or 1
/// when the broad phase failed or its hits disagree, or the hierarchies' contacts differ.
int runBenchmark(const WalkerBenchOptions& opts, std::ostream& out);

}  // namespace nestwalk::bench
