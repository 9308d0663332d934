#include "tools/bench/bench_cli.h"

#include "assets/generators/bundled_scene.h"

#include "nestwalk/core/input_error.h"

#include <filesystem>

namespace nestwalk::bench {
namespace {

/// Sizes and counts given on the command line: at least 1, at most this.
constexpr std::size_t kMaxCount = 100'000'000;

void declareCommon(CLI::App& cmd, BenchOptions& o, const std::string& quick) {
  cmd.add_flag("--json", o.json, "Print the results as one JSON document instead of tables");
  cmd.add_flag("--quick", o.quick, "Smoke test: " + quick);
}

void declareSuite(CLI::App& cmd, SuiteOptions& o, const std::string& quick, const std::string& defaultMinTime,
                  const std::string& names) {
  declareCommon(cmd, o, quick);
  cmd.add_option("--min-time", o.minTimeSeconds,
                 "Minimum time per benchmark in seconds (default " + defaultMinTime + ")")
      ->check(CLI::PositiveNumber);
  cmd.add_option("--repetitions", o.repetitions, "Runs per benchmark; the tables show the median (default 1)")
      ->check(CLI::Range(1, 100));
  cmd.add_option("--filter", o.filter, "Regular expression on the benchmark names (" + names + ")");
}

CLI::Option* addCount(CLI::App& cmd, const std::string& name, std::size_t& value, const std::string& what) {
  return cmd.add_option(name, value, what)->check(CLI::Range(std::size_t(1), kMaxCount));
}

CLI::Option* addCounts(CLI::App& cmd, const std::string& name, std::vector<std::size_t>& values,
                       const std::string& what) {
  return cmd.add_option(name, values, what)->delimiter(',')->check(CLI::Range(std::size_t(1), kMaxCount));
}

/// A list of metres (the sweep's terrains), at least `least` of them; given at all (even bare, when
/// CLI11 hands the callback one empty value), it turns `on` on.
CLI::Option* addMetres(CLI::App& cmd, const std::string& name, std::vector<double>& values, bool& on,
                       const std::string& what, int least, const std::string& help) {
  auto parse = [name, what, &values, &on](const std::vector<std::string>& given) {
    on = true;
    values.clear();
    for (const std::string& v : given) {
      if (v.empty()) continue;
      double x = 0;
      if (!CLI::detail::lexical_cast(v, x)) throw InputError(name + ": '" + v + "' is not " + what);
      values.push_back(x);
    }
  };
  return cmd.add_option_function<std::vector<std::string>>(name, parse, help)
      ->expected(least, CLI::detail::expected_max_vector_size)
      ->delimiter(',')
      ->type_name("METRES");
}

void declareScene(CLI::App& cmd, std::string& scene, std::vector<std::string>& scripts, const std::string& use) {
  cmd.add_option("--scene", scene, "Scene file for " + use + " (default: the bundled mining dump)");
  cmd.add_option("--scripts", scripts, "Its flythroughs (default: the bundled ones)");
}

}  // namespace

void declareOptions(CLI::App& cmd, VolumeBenchOptions& o) {
  declareSuite(cmd, o, "20k pairs per set, short runs (a few seconds)", "0.5", "volumes/<test>/<set>");
  addCount(cmd, "--pairs", o.pairs, "Pairs per set (default 1000000)");
}

void declareOptions(CLI::App& cmd, TerrainBenchOptions& o) {
  declareSuite(cmd, o, "257 x 257 grid, 20k rays, short runs (a few seconds)", "0.5", "terrain/<method>/<set>");
  cmd.add_option("--grid", o.gridSamples, "Samples per side of the synthetic DEM (default 2049)")
      ->check(CLI::Range(3, 20000));
  addCount(cmd, "--rays", o.rays, "Rays per set (default 1000000)");
  addCount(cmd, "--slow-rays", o.slowRays,
           "Rays per set for OSG, and for Bullet's oblique rays (default min(rays, 50000))");
}

void declareOptions(CLI::App& cmd, BroadPhaseBenchOptions& o) {
  declareSuite(cmd, o, "1k and 10k boxes, 10k queries, short runs", "0.3", "broadphase/<method>/<boxes>");
  addCounts(cmd, "--sizes", o.sizes, "Box counts (default 1000 10000 100000 1000000)");
  addCount(cmd, "--queries", o.queries, "Queries per size (default 100000)");
}

void declareOptions(CLI::App& cmd, WalkerBenchOptions& o) {
  declareCommon(cmd, o, "1k and 10k instances, 5k steps");
  addCounts(cmd, "--sizes", o.sizes, "Instance counts (default 1000 100000 1000000)");
  addCount(cmd, "--steps", o.steps, "Timed walker steps per size (default 200000)");
  declareScene(cmd, o.scene, o.scripts, "the BV-test table");
  cmd.add_flag("!--no-table2", o.table2, "Skip the BV-test table");
  cmd.add_flag("!--no-broad-phase", o.broadPhase, "Skip the broad-phase comparison");
}

void declareOptions(CLI::App& cmd, RenderBenchOptions& o) {
  declareCommon(cmd, o,
                "320x180, 8 frames per flythrough, two configurations (the terrain-size sweep: sizes 250 and 500 "
                "unless given)");
  cmd.add_option("--width", o.width, "Frame width (default 1280)")->check(CLI::Range(16, 8192));
  cmd.add_option("--height", o.height, "Frame height (default 720)")->check(CLI::Range(16, 8192));
  cmd.add_option("--frames", o.framesPerScript, "Frames per flythrough (default 120)")->check(CLI::Range(1, 100000));
  declareScene(cmd, o.scene, o.scripts, "the flythroughs");
  addMetres(cmd, "--terrain-sizes", o.terrainSizes, o.terrainSweep, "a size in metres", 0,
            "Instead of the configurations, the terrain-size sweep: generated mining dumps of these sides in "
            "metres at 1 m cells (sizes round to whole cells), each measured in a child process (given bare: 1000 "
            "4000 10000, 1 M, 16 M and 100 M samples)");
  addMetres(cmd, "--terrain-cells", o.terrainCells, o.terrainSweep, "a cell size in metres", 1,
            "Instead of the configurations, the finer terrain sweep (the drone case): the 1000 m mining dump with "
            "relief down to the cell (make-terrain --fine-relief) at these cell sizes in metres, e.g. 1 0.1 0.032 "
            "(1 M, 100 M and 1 G samples)");
  cmd.add_option("--terrain-cache", o.terrainCache,
                 "Folder of the sweep's generated DEMs, reused while they exist (default: "
                 "nestwalk-terrain-cache in the system's temporary folder)");
  cmd.add_option("--imagery", o.imagery,
                 "Orthophotos to drape instead of the scene's (e.g. the bundled dump's at 10 and 3 cm: make-terrain "
                 "--ortho FILE --ortho-pixel 0.1): a settled row each, beside the scene's imagery at the DEM's resolution, "
                 "after the two default rows (the other configurations are left out)")
      ->check(CLI::ExistingFile);
  cmd.add_option("--terrain-sweep-child", o.sweepChild, "The sweep's measuring child (internal)")->group("");
}

void declareOptions(CLI::App& cmd, ModelReadBenchOptions& o) {
  declareCommon(cmd, o, "3 reads of each kind per model");
  cmd.add_option("--repetitions", o.repetitions, "Reads of each kind per model (default 15)")->check(CLI::Range(1, 1000));
  cmd.add_option("--models", o.models, "Model files (default: the bundled, GIS-sample and shared models)")
      ->check(CLI::ExistingFile);
}

void declareOptions(CLI::App& cmd, ContactBenchOptions& o) {
  declareCommon(cmd, o, "4 sides, 2 calls per sweep");
  cmd.add_option("--repetitions", o.repetitions, "Timed calls per sweep and method (default 5)")->check(CLI::Range(1, 1000));
  cmd.add_option("--sides", o.sides, "Approach directions per model (default 16)")->check(CLI::Range(1, 360));
  cmd.add_option("--models", o.models,
                 "Models as FILE[:UNITS[:UP]]: metres per file unit (default 1), up axis x, y, z, -x, -y or -z "
                 "(default z); default: the bundled drill rig and the shared dump truck and excavator");
}

void completeOptions(WalkerBenchOptions& o) {
  if (!o.table2) return;
  try {
    assets::defaultSceneAndScripts(o.scene, o.scripts);
  } catch (const InputError& e) {
    std::cerr << "nestwalk: note: " << e.what() << "; skipping the BV-test table\n";
    o.table2 = false;
  }
}

void completeOptions(RenderBenchOptions& o) {
  if (!o.sweepChild.empty()) return;  // the sweep's child measures a terrain of its request's
  assets::defaultSceneAndScripts(o.scene, o.scripts);
}

}  // namespace nestwalk::bench
