// bench_volumes: the bounding-volume benchmark as a Google Benchmark program. Takes the usual
// --benchmark_* flags (e.g. --benchmark_filter=obb_obb, --benchmark_list_tests), prints Google
// Benchmark's report while running and then the ratio table of `nestwalk bench volumes`.
// Own flags: --quick (20k pairs, short runs), --json (JSON table; the running report goes to
// stderr), --pairs=N.
#include "tools/bench/volume_bench.h"

#include "tests/bench/bench_main.h"

#include <cstdio>
#include <cstdlib>
#include <string>

int main(int argc, char** argv) {
  nestwalk::bench::VolumeBenchOptions opts;
  auto ownFlag = [&opts](const std::string& a) {
    if (a.rfind("--pairs=", 0) == 0) {
      opts.pairs = std::strtoull(a.c_str() + 8, nullptr, 10);
      if (opts.pairs == 0) {
        std::fprintf(stderr, "bench_volumes: bad %s\n", a.c_str());
        return 1;
      }
    } else {
      std::fprintf(stderr, "bench_volumes: unknown argument %s (own flags: --quick --json --pairs=N)\n", a.c_str());
      return 1;
    }
    return 0;
  };
  return nestwalk::bench::benchMain(argc, argv, opts, ownFlag, nestwalk::bench::runVolumeBench);
}
