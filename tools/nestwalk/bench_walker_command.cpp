// nestwalk bench walker: the walker benchmark (tools/bench/walker_bench.h): walker steps over
// 1k..1M instances, the broad phase against btDbvt and FCL, and the BV-test counts of each
// hierarchy on the bundled flythroughs (fACT's Table 2). Its options are declared with the other
// benchmarks' in tools/bench/bench_cli.cpp.
#include "tools/bench/bench_cli.h"
#include "tools/nestwalk/commands.h"

void nestwalk::tools::registerBenchWalker(CLI::App& bench) {
  bench::addBenchCommand<bench::WalkerBenchOptions>(
      bench, "walker",
      "Walker steps at 1k-1M instances, broad phase vs btDbvt and FCL, BV tests per hierarchy");
}
