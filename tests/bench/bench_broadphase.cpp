// bench_broadphase: the broad-phase benchmark (tools/bench/broadphase_bench.h) as a Google
// Benchmark program. Takes the usual --benchmark_* flags (e.g. --benchmark_filter=btdbvt,
// --benchmark_list_tests), prints Google Benchmark's report while running and then the table of
// nestwalk's BoxTree against btDbvt and FCL. Own flags: --quick (1k and 10k boxes, 10k queries),
// --json (the running report goes to stderr), --sizes=N[,N...], --queries=N, and the suites'
// --min-time, --repetitions, --filter.
#include "tools/bench/bench_cli.h"

int main(int argc, char** argv) {
  return nestwalk::bench::benchProgram<nestwalk::bench::BroadPhaseBenchOptions>(argc, argv);
}
