// The terrain-size sweep of the rendering benchmark, in two shapes: wider (`nestwalk bench render
// --terrain-sizes [METRES ...]`: generated mining-dump terrains of several sides at 1 m cells,
// default 1000, 4000 and 10000 m: 1 M, 16 M and 100 M samples, 32768 m for 1 G; --quick: 250 and
// 500 m at 320 x 180) and finer (`--terrain-cells METRES ...`: the 1000 m dump with relief down to
// the cell, make-terrain --fine-relief, at each cell size: 1 0.1 0.032 for 1 M, 100 M and 1 G, the
// drone case). The bundled flythroughs' poses are rendered over each, to show that what the
// view-bounded terrain (engine/render/paged_terrain.h) costs grows with the view, not with the DEM.
//
// Poses: sampled from the bundled scene's flythroughs as the rest of `bench render` samples them
// (render_bench.h: the walker on the bundled scene, no GL). Each pose keeps its x, y, heading,
// pitch and its height above the bundled terrain's ground; on each size its z is that size's own
// ground at (x, y) plus that height (the generated dumps differ in shape with the size, so this
// keeps the eye above the ground). Every size has the generator's default centre, so the bundled
// poses lie on every terrain at least as large as the bundled one (1000 m); on a smaller one
// (--quick) a pose outside it takes the ground at the nearest point of the terrain's extent.
//
// DEMs: terrain::MiningDumpGenerator (seed 1, the default centre), streamed stripe by stripe into the
// engine's terrain COG and its pyramid (terrain_import.h) in the cache folder (--terrain-cache,
// default <system temp>/nestwalk-terrain-cache), as mining_dump_seed1_cell<CELL>_size<METRES>[_fine].tif, and
// reused while that file exists (it is written under a temporary name and renamed, so an existing
// one is complete; remove the folder after changing the generator).
//
// Measuring: each size in a child process (this program run again with a hidden option,
// --terrain-sweep-child REQUEST.json, its stdout sent to stderr), so that its peak resident memory
// (VmHWM of the child, read from /proc/self/status at its end: the whole run, terrain load
// included) is that size's alone and no GL context ever exists in the parent. The child loads a
// scene with just that terrain (loadScene: "DEM load s"), then times the first frame from there
// (ViewRenderer construction, whose paged terrain builds its root chunk, and the first render),
// then renders every pose once, back to back, with TerrainLoading::Background (frames never wait
// for the loader). Per size: ms per frame p50 / p95 (RenderFrameStats::totalMs over all poses), the
// worst frame while loading (the largest frame time among frames with chunks still wanted), the
// most chunks and MiB resident, chunks loaded per second (chunks built during the timed frames /
// their wall-clock seconds), the largest projected error drawn once settled (at the last pose of
// each flythrough, after the timed frames: rendered again until nothing is wanted, waiting for the
// loader in between; with the seconds that took and the median time of the settled frames) and the
// peak RSS (also as it stood once the scene was loaded: the DEM's share). A size whose timed frames
// were mostly still loading gets a note under the table (its frames drew a coarser terrain than the
// settled view). The child then plays every flythrough with the walker on that terrain alone (no
// equipment), at 10 times its real pace: the step time's p99 and the ground reads a step waited
// for after the first (a paged terrain's prefetch falling behind). Then the ratios of p50 and p95 to the smallest size's, and the targets for
// the largest size: p50 within 1.25x and p95 within 1.5x of the smallest, the settled view within
// 1.25x (finer) or 1.5x (wider) of the smallest's, peak RSS at most 1.5 GB, the scene opened in at
// most 1 s, the first frame at most 1.5 s after it, the settle poses settled within 3 s, the
// walker's step p99 at most 2 us and no ground read waited for.
//
// Errors: a size (or cell) giving fewer than 16 or more than 65,536 cells a side, or given twice,
// is an InputError naming --terrain-sizes (--terrain-cells; both at once too); a cache folder that
// cannot be made, one naming --terrain-cache.
// A child that fails is reported as the benchmark's error for that size (its own message went to
// stderr), and the program then ends with status 1.
//
// Thread safety: call from one thread, before any GL context exists in the process (it spawns
// children with posix_spawn).
#pragma once

#include "tools/bench/render_bench.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace nestwalk::bench {

/// The sweep's terrain sizes (side of the square area, metres) when --terrain-sizes gives none: the
/// issue's 1 M, 16 M and 100 M samples at 1 m cells; --quick: small enough for a test.
inline const std::vector<double> kSweepDefaultSizesM = {1000.0, 4000.0, 10000.0};
inline const std::vector<double> kSweepQuickSizesM = {250.0, 500.0};

/// The cache folder of the generated DEMs when --terrain-cache is not given.
std::string defaultTerrainCacheFolder();

/// Runs the sweep (see above) and prints its table and targets (or one JSON document) to `out`.
/// Returns 0, or 1 when a size's measurement failed.
int runTerrainSweep(const RenderBenchOptions& opts, std::ostream& out);

/// The child's side: measures the one size its request file describes and writes the result file
/// the request names. Returns 0 (failures throw: InputError for a bad terrain, std::runtime_error
/// when no GL context can be had).
int runTerrainSweepChild(const std::string& requestFile);

}  // namespace nestwalk::bench
