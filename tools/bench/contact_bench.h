// The contact benchmark (`nestwalk bench contact`): the exact stage of the walker's mesh methods
// as the walker runs it (MeshTree::sweep of the k-DOP-18 tree, mesh_tree.h: the first time a
// translating box touches a model's triangles, through one mover's CoherentSweep,
// coherent_sweep.h, which answers the steps inside a free path it proved earlier without opening
// the tree) against FCL's continuous collision and Bullet's convex sweep on the same sweeps
// (peers/contact_peers.h), on heavy models: the bundled scene's generated drill rig (40k
// triangles) and the shared data's dump truck and excavator.
// Sweeps: the viewer's body box (0.25 x 0.25 x 0.9 m half extents, upright) walks at 1.4 m/s in
// 60 Hz steps toward the model's centre from `sides` directions, on the ground and at half the
// model's height (flying into it), from a metre outside its box; every step whose swept box
// reaches the model's box is a sweep, up to the first contact; then four sweeps pressing on from
// 0.5 mm short of the contact, turned 10 and 20 degrees either way (a walker held at a face,
// turning). Models in metres, upright (each file's units and up axis).
// Each method plays the sweeps in order (as a walker steps: what one step brings into the cache,
// the next finds there), `repetitions` times, the methods taking turns; per sweep its least time,
// less the clock's own cost (the least time of an empty timed call, about 20 ns here: two clock
// reads, which would otherwise cap the ratio of any sweep that costs less than they do);
// per model and method the p50, p99 and mean microseconds, and the peers' ratios to ours. Agreement:
// the time of contact of each peer against ours, as a distance along the step (mm); where they
// differ by more than 0.1 mm, conservative advancement on the tree's exact distances decides who
// is right. Targets (issue 27): each peer at least 5x our time at p50 and p99, its time of contact
// within 0.1 mm of ours or of the advancement where they disagree.
#pragma once

#include "tools/bench/bench_runner.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace nestwalk::bench {

struct ContactBenchOptions : BenchOptions {
  int repetitions = 5;  // timed calls per sweep and method; quick: 2
  int sides = 16;       // approach directions; quick: 4
  /// Model files as FILE[:UNITS[:UP]] (UNITS: metres per file unit, default 1; UP: x, y, z, -x,
  /// -y or -z, default z); empty: the bundled scene's drill rig, the shared dump truck and
  /// excavator, those present.
  std::vector<std::string> models;
};

/// Times the sweeps and prints the table and the targets (or one JSON document) to `out`. Returns
/// 0, or 1 when a model could not be read.
int runBenchmark(const ContactBenchOptions& opts, std::ostream& out);

}  // namespace nestwalk::bench
