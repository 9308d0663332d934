// bench_volumes: the bounding-volume benchmark (tools/bench/volume_bench.h) as a Google Benchmark
// program. Takes the usual --benchmark_* flags (e.g. --benchmark_filter=obb_obb,
// --benchmark_list_tests), prints Google Benchmark's report while running and then the ratio table
// of `nestwalk bench volumes`, whose options it takes too (--quick, --json, --pairs=N, ...).
#include "tools/bench/bench_cli.h"

int main(int argc, char** argv) {
  return nestwalk::bench::benchProgram<nestwalk::bench::VolumeBenchOptions>(argc, argv);
}
