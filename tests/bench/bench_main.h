// The command line of the Google Benchmark programs (bench_volumes, bench_terrain): the usual
// --benchmark_* flags, the own flags --quick and --json, and those of one program.
#pragma once

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <iostream>
#include <string>

namespace nestwalk::bench {

/// Parses the arguments into `opts` (a VolumeBenchOptions or TerrainBenchOptions), runs
/// `run(opts, std::cout)` and returns its exit status. `ownFlag(arg)` takes the program's other
/// flags: 0 when it took `arg`, non-zero (after printing why) for a bad or unknown one, which ends
/// the program with 1.
template <class Options, class OwnFlag, class Run>
int benchMain(int argc, char** argv, Options& opts, OwnFlag&& ownFlag, Run&& run) {
  // The benchmarks carry their own minimum time (it would override the flag): take the flag's value.
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--benchmark_min_time=", 0) == 0) opts.minTimeSeconds = std::strtod(a.c_str() + 21, nullptr);
  }
  benchmark::Initialize(&argc, argv);
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") {
      opts.quick = true;
    } else if (a == "--json") {
      opts.json = true;
    } else if (ownFlag(a) != 0) {
      return 1;
    }
  }
  opts.filter = benchmark::GetBenchmarkFilter();
  opts.googleBenchmarkOutput = opts.json ? &std::cerr : &std::cout;
  const int rc = run(opts, std::cout);
  if (!opts.json) std::cout.flush();
  benchmark::Shutdown();
  return rc;
}

}  // namespace nestwalk::bench
