// bench_terrain: the terrain benchmark as a Google Benchmark program. Takes the usual
// --benchmark_* flags (e.g. --benchmark_filter=embree, --benchmark_list_tests), prints Google
// Benchmark's report while running and then the ratio table of `nestwalk bench terrain`.
// Own flags: --quick (257 x 257 grid, 20k rays, short runs), --json (JSON table; the running report
// goes to stderr), --rays=N, --grid=N.
#include "tools/bench/terrain_bench.h"

#include "tests/bench/bench_main.h"

#include <cstdio>
#include <cstdlib>
#include <string>

int main(int argc, char** argv) {
  nestwalk::bench::TerrainBenchOptions opts;
  auto ownFlag = [&opts](const std::string& a) {
    if (a.rfind("--rays=", 0) == 0) {
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
    return 0;
  };
  return nestwalk::bench::benchMain(argc, argv, opts, ownFlag, nestwalk::bench::runTerrainBench);
}
