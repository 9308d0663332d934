// nestwalk bench terrain: the terrain benchmark (tools/bench/terrain_bench.h): nestwalk's ground-
// height and ray queries against a direct grid lookup, Embree, Bullet and OpenSceneGraph on the
// same rays. Its options are declared with the other benchmarks' in tools/bench/bench_cli.cpp.
#include "tools/bench/bench_cli.h"
#include "tools/nestwalk/commands.h"

void nestwalk::tools::registerBenchTerrain(CLI::App& bench) {
  bench::addBenchCommand<bench::TerrainBenchOptions>(
      bench, "terrain",
      "Ground height and ray queries in ns/ray against a direct lookup, Embree, Bullet and OSG");
}
