// nestwalk bench volumes: the bounding-volume benchmark (tools/bench/volume_bench.h): nestwalk's
// overlap tests against FCL, libccd and Bullet on the same pairs. Its options are declared with the
// other benchmarks' in tools/bench/bench_cli.cpp.
#include "tools/bench/bench_cli.h"
#include "tools/nestwalk/commands.h"

void nestwalk::tools::registerBenchVolumes(CLI::App& bench) {
  bench::addBenchCommand<bench::VolumeBenchOptions>(
      bench, "volumes",
      "Overlap tests (AABB, OBB, nested, batch, one-vs-many) in ns/op against FCL, libccd MPR and Bullet");
}
