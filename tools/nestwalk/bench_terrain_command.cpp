// nestwalk bench terrain [--json] [--quick]: the terrain benchmark (tools/bench/terrain_bench.h),
// nestwalk's ground-height and ray queries against a direct grid lookup, Embree, Bullet and
// OpenSceneGraph on the same rays, printed as a table.
#include "tools/bench/terrain_bench.h"
#include "tools/nestwalk/commands.h"

#include <iostream>
#include <memory>

namespace nestwalk::tools {

void registerBenchTerrain(CLI::App& bench) {
  auto opts = std::make_shared<bench::TerrainBenchOptions>();
  auto verbose = std::make_shared<bool>(false);
  CLI::App* cmd = bench.add_subcommand(
      "terrain", "Ground height and ray queries in ns/ray against a direct lookup, Embree, Bullet and OSG");
  cmd->add_flag("--json", opts->json, "Print the results as JSON instead of a table");
  cmd->add_flag("--quick", opts->quick, "Smoke test: 257 x 257 grid, 20k rays, short runs (a few seconds)");
  cmd->add_option("--grid", opts->gridSamples, "Samples per side of the synthetic DEM (default 2049)")
      ->check(CLI::Range(3, 20000));
  cmd->add_option("--rays", opts->rays, "Rays per set (default 1000000)")
      ->check(CLI::Range(std::size_t(1), std::size_t(100'000'000)));
  cmd->add_option("--slow-rays", opts->slowRays,
                  "Rays per set for OSG, and for Bullet's oblique rays (default min(rays, 50000))")
      ->check(CLI::Range(std::size_t(1), std::size_t(100'000'000)));
  cmd->add_option("--min-time", opts->minTimeSeconds, "Minimum time per benchmark in seconds (default 0.5)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--repetitions", opts->repetitions, "Runs per benchmark; the table shows the median (default 1)")
      ->check(CLI::Range(1, 100));
  cmd->add_option("--filter", opts->filter, "Regular expression on the benchmark names (terrain/<method>/<set>)");
  cmd->add_flag("--verbose", *verbose, "Also print Google Benchmark's own report to stderr while running");
  cmd->callback([opts, verbose] {
    bench::TerrainBenchOptions o = *opts;
    if (*verbose) o.googleBenchmarkOutput = &std::cerr;
    const int rc = bench::runTerrainBench(o, std::cout);
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
}

}  // namespace nestwalk::tools
