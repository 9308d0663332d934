// bench_broadphase: the broad-phase benchmark (tools/bench/broadphase_bench.h) as a Google
// Benchmark program. Takes the usual --benchmark_* flags (e.g. --benchmark_filter=btdbvt,
// --benchmark_list_tests), prints Google Benchmark's report while running and then the table of
// nestwalk's BoxTree against btDbvt and FCL. Own flags: --quick (1k and 10k boxes, 10k queries),
// --json (JSON table; the running report goes to stderr), --sizes=N[,N...], --queries=N.
#include "tools/bench/broadphase_bench.h"

#include "tests/bench/bench_main.h"

#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

int main(int argc, char** argv) {
  nestwalk::bench::BroadPhaseBenchOptions opts;
  auto ownFlag = [&opts](const std::string& a) {
    if (a.rfind("--queries=", 0) == 0) {
      opts.queries = std::strtoull(a.c_str() + 10, nullptr, 10);
      if (opts.queries == 0) {
        std::fprintf(stderr, "bench_broadphase: bad %s\n", a.c_str());
        return 1;
      }
    } else if (a.rfind("--sizes=", 0) == 0) {
      std::istringstream in(a.substr(8));
      std::string item;
      while (std::getline(in, item, ',')) {
        const std::size_t n = std::strtoull(item.c_str(), nullptr, 10);
        if (n == 0) {
          std::fprintf(stderr, "bench_broadphase: bad %s\n", a.c_str());
          return 1;
        }
        opts.sizes.push_back(n);
      }
    } else {
      std::fprintf(stderr, "bench_broadphase: unknown argument %s (own flags: --quick --json --sizes=N,N --queries=N)\n",
                   a.c_str());
      return 1;
    }
    return 0;
  };
  return nestwalk::bench::benchMain(argc, argv, opts, ownFlag, nestwalk::bench::runBroadPhaseBench);
}
