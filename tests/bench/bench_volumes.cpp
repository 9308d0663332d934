// bench_volumes: the bounding-volume benchmark as a Google Benchmark program. Takes the usual
// --benchmark_* flags (e.g. --benchmark_filter=obb_obb, --benchmark_list_tests), prints Google
// Benchmark's report while running and then the ratio table of `nestwalk bench volumes`.
// Own flags: --quick (20k pairs, short runs), --json (JSON table; the running report goes to
// stderr), --pairs=N.
#include "tools/bench/volume_bench.h"

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>

int main(int argc, char** argv) {
  nestwalk::bench::VolumeBenchOptions opts;
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
    } else if (a.rfind("--pairs=", 0) == 0) {
      opts.pairs = std::strtoull(a.c_str() + 8, nullptr, 10);
      if (opts.pairs == 0) {
        std::fprintf(stderr, "bench_volumes: bad %s\n", a.c_str());
        return 1;
      }
    } else {
      std::fprintf(stderr, "bench_volumes: unknown argument %s (own flags: --quick --json --pairs=N)\n", a.c_str());
      return 1;
    }
  }
  opts.filter = benchmark::GetBenchmarkFilter();
  opts.googleBenchmarkOutput = opts.json ? &std::cerr : &std::cout;
  const int rc = nestwalk::bench::runVolumeBench(opts, std::cout);
  if (!opts.json) std::cout.flush();
  benchmark::Shutdown();
  return rc;
}
