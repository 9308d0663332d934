// The broad-phase benchmark (part 2 of `nestwalk bench walker`, also the program bench_broadphase):
// nestwalk's BoxTree::query (engine/hierarchy/box_tree.h) timed in µs per query next to two peers
// answering the same queries on the same boxes: Bullet's btDbvt and FCL's
// DynamicAABBTreeCollisionManager (peers/broadphase_peers.h).
//
// Data, per size n (1k, 10k, 100k, 1M; quick: 1k, 10k): n boxes scattered uniformly over 10 km x
// 10 km (local frame, centred on the origin), base z 0-50 m: 30% poles (0.05-0.3 m square, 2-12 m
// tall), 40% cabinets (0.5-3 m per side), 30% containers (2.4 x 6-12 x 2.6 m at a random heading,
// their AABB); all coordinates are floats (exactly representable), so the float peers see the very
// boxes nestwalk sees in double, and every method must give the same hits. Queries: the viewer's
// swept AABB (0.5 x 0.5 x 1.8 m at two consecutive positions up to 1 m apart) along walks of 1000
// steps, each walk starting next to a random box; 100k queries (10k with quick). Benchmarks are
// named "broadphase/<method>/<n>"; each iteration answers all queries.
// The output: per n and nestwalk hierarchy, µs per query with btDbvt's and FCL's figures and the
// ratios peer / nestwalk on the same line, the hit counts of every method and the number of queries
// whose hit set differs from nestwalk's (counted outside the timed loops), then the build times.
// Targets (issue): query >= 2x faster than btDbvt at every n (the default hierarchy, delta = 8
// longest/median); build of 1M boxes < 1 s.
#pragma once

#include "tools/bench/bench_document.h"
#include "tools/bench/bench_runner.h"

#include <cstddef>
#include <iosfwd>
#include <vector>

namespace nestwalk::bench {

struct BroadPhaseBenchOptions : SuiteOptions {
  std::vector<std::size_t> sizes;  // box counts; empty: 1k, 10k, 100k, 1M (quick: 1k, 10k)
  std::size_t queries = 0;         // queries per size; 0: 100'000 (10'000 with quick)
};

/// Registers the "broadphase/..." benchmarks for the sizes of `opts` (names already registered are
/// kept), runs those that match and returns the output: tables, JSON and targets. A method whose
/// hits differ from nestwalk's, or nestwalk's from brute force, is an error of the document. Frees
/// the boxes and the structures (~1.5 GB at 1M, most of it FCL's objects) before returning.
/// Minimum time per benchmark: opts.minTimeSeconds, else 0.3 s (0.02 s quick).
Document measureBroadPhase(const BroadPhaseBenchOptions& opts);

/// measureBroadPhase, written to `out` (the tables, or JSON with opts.json); returns its status
/// (0, or 1 when nothing matched, a benchmark failed or hits disagree).
int runBenchmark(const BroadPhaseBenchOptions& opts, std::ostream& out);

}  // namespace nestwalk::bench
