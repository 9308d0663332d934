// nestwalk bench volumes [--json] [--quick]: the bounding-volume benchmark (tools/bench/volume_bench.h),
// nestwalk's overlap tests against FCL, libccd and Bullet on the same pairs, printed as a table.
#include "tools/bench/volume_bench.h"
#include "tools/nestwalk/commands.h"

#include <iostream>
#include <memory>

namespace nestwalk::tools {

void registerBenchVolumes(CLI::App& bench) {
  auto opts = std::make_shared<bench::VolumeBenchOptions>();
  auto verbose = std::make_shared<bool>(false);
  CLI::App* cmd = bench.add_subcommand(
      "volumes", "Overlap tests (AABB, OBB, nested, batch, one-vs-many) in ns/op against FCL, libccd MPR and Bullet");
  cmd->add_flag("--json", opts->json, "Print the results as JSON instead of a table");
  cmd->add_flag("--quick", opts->quick, "Smoke test: 20k pairs and stored boxes, short runs (a few seconds)");
  cmd->add_option("--pairs", opts->pairs, "Pairs per set, and stored boxes per query set (default 1000000)")
      ->check(CLI::Range(std::size_t(1), std::size_t(100'000'000)));
  cmd->add_option("--min-time", opts->minTimeSeconds, "Minimum time per benchmark in seconds (default 0.5)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--repetitions", opts->repetitions, "Runs per benchmark; the table shows the median (default 1)")
      ->check(CLI::Range(1, 100));
  cmd->add_option("--filter", opts->filter, "Regular expression on the benchmark names (volumes/<test>/<set>)");
  cmd->add_flag("--verbose", *verbose, "Also print Google Benchmark's own report to stderr while running");
  cmd->callback([opts, verbose] {
    bench::VolumeBenchOptions o = *opts;
    if (*verbose) o.googleBenchmarkOutput = &std::cerr;
    const int rc = bench::runVolumeBench(o, std::cout);
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
}

}  // namespace nestwalk::tools
