// bench_terrain: the terrain benchmark as a Google Benchmark program. Takes the usual
// --benchmark_* flags (e.g. --benchmark_filter=embree, --benchmark_list_tests), prints Google
// Benchmark's report while running and then the ratio table of `nestwalk bench terrain`.
// Own flags: --quick (257 x 257 grid, 20k rays, short runs), --json (JSON table; the running report
// goes to stderr), --rays=N, --grid=N.
#include "tools/bench/terrain_bench.h"

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>

int main(int argc, char** argv) {
  nestwalk::bench::TerrainBenchOptions opts;
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
    } else if (a.rfind("--rays=", 0) == 0) {
      opts.rays = std::strtoull(a.c_str() + 7, nullptr, 10);
      if (opts.rays == 0) {
        std::fprintf(stderr, "bench_terrain: bad %s\n", a.c_str());
        return 1;
      }
    } else if (a.rfind("--grid=", 0) == 0) {
      opts.gridSamples = std::atoi(a.c_str() + 7);
      if (opts.gridSamples < 3) {
        std::fprintf(stderr, "bench_terrain: bad %s\n", a.c_str());
        return 1;
      }
    } else {
      std::fprintf(stderr, "bench_terrain: unknown argument %s (own flags: --quick --json --rays=N --grid=N)\n",
                   a.c_str());
      return 1;
    }
  }
  opts.filter = benchmark::GetBenchmarkFilter();
  opts.googleBenchmarkOutput = opts.json ? &std::cerr : &std::cout;
  const int rc = nestwalk::bench::runTerrainBench(opts, std::cout);
  if (!opts.json) std::cout.flush();
  benchmark::Shutdown();
  return rc;
}
