// bench_terrain: the terrain benchmark (tools/bench/terrain_bench.h) as a Google Benchmark program.
// Takes the usual --benchmark_* flags (e.g. --benchmark_filter=embree, --benchmark_list_tests),
// prints Google Benchmark's report while running and then the ratio table of `nestwalk bench
// terrain`, whose options it takes too (--quick, --json, --rays=N, --grid=N, ...).
#include "tools/bench/bench_cli.h"

int main(int argc, char** argv) {
  return nestwalk::bench::benchProgram<nestwalk::bench::TerrainBenchOptions>(argc, argv);
}
