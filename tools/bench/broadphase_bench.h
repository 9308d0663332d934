// The broad-phase benchmark (part 2 of `nestwalk bench walker`, also the program bench_broadphase):
// nestwalk's BoxTree::query (engine/hierarchy/box_tree.h) timed in µs per query next to two peers
// answering the same queries on the same boxes: Bullet's btDbvt (insert per box, then
// btDbvt::collideTV with a callback collecting the leaves) and FCL's
// DynamicAABBTreeCollisionManager (registerObjects + setup over fcl::Box objects whose AABBs equal
// the boxes, manager->collide(queryObject, data, callback) with a callback that only records the
// pair: FCL runs no narrow phase unless the callback does).
//
// Data, per size n (1k, 10k, 100k, 1M; quick: 1k, 10k): n unit boxes scattered uniformly over
// 10 km x 10 km (local frame, centred on the origin), base z 0-50 m: 30% poles (0.05-0.3 m square,
// 2-12 m tall), 40% cabinets (0.5-3 m per side), 30% containers (2.4 x 6-12 x 2.6 m at a random
// heading, their AABB); all coordinates are floats (exactly representable), so the float peers see
// the very boxes nestwalk sees in double, and every method must give the same hits. Queries: the
// viewer's swept AABB (0.5 x 0.5 x 1.8 m at two consecutive positions up to 1 m apart) along walks
// of 1000 steps, each walk starting next to a random box; 100k queries (10k with quick).
// Benchmarks are named "broadphase/<method>/<n>"; each iteration answers all queries.
// The table prints, per n and nestwalk hierarchy, µs per query with btDbvt's and FCL's figures and
// the ratios peer / nestwalk on the same line, the hit counts of every method and the number of
// queries whose hit set differs from nestwalk's (counted outside the timed loops), then the build
// times. Targets (issue): query >= 2x faster than btDbvt at every n (default hierarchy delta = 4
// longest/median); build of 1M boxes < 1 s.
#pragma once

#include "tools/bench/bench_runner.h"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

namespace nestwalk::bench {

struct BroadPhaseBenchOptions {
  bool json = false;                // print JSON instead of the table
  bool quick = false;               // 1k and 10k boxes, 10k queries, short minimum time
  std::vector<std::size_t> sizes;   // box counts; empty: 1k, 10k, 100k, 1M (quick: 1k, 10k)
  std::size_t queries = 0;          // queries per size; 0: 100'000 (10'000 with quick)
  double minTimeSeconds = 0;        // Google Benchmark minimum time per benchmark; 0: 0.3 (0.02 quick)
  int repetitions = 0;              // runs per benchmark, the table shows the median
  /// Regular expression on benchmark names; empty, "all" or ".": every "broadphase/" benchmark.
  std::string filter;
  /// Also send Google Benchmark's own report to this stream while running.
  std::ostream* googleBenchmarkOutput = nullptr;
};

/// What a run measured, for embedding in another report (the walker benchmark).
struct BroadPhaseReport {
  std::string table;           // the printed table (what runBroadPhaseBench prints without --json)
  nlohmann::ordered_json json;  // the same as JSON (what it prints with --json)
  std::vector<Target> targets;
  int rc = 0;                  // 0, or 1 when nothing matched, a benchmark failed or hits disagree
};

/// Registers the "broadphase/..." benchmarks for the sizes of `opts` (names already registered are
/// kept; later calls update sizes and times).
void registerBroadPhaseBenchmarks(const BroadPhaseBenchOptions& opts);

/// Runs the matching benchmarks and returns the table, JSON and targets. Frees the boxes and the
/// structures (~1.5 GB at 1M, most of it FCL's objects) before returning.
BroadPhaseReport measureBroadPhase(const BroadPhaseBenchOptions& opts);

/// measureBroadPhase, printing the table (or the JSON with opts.json) to `out`; returns its rc.
int runBroadPhaseBench(const BroadPhaseBenchOptions& opts, std::ostream& out);

}  // namespace nestwalk::bench
