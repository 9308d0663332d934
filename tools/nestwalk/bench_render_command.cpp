// nestwalk bench render: the rendering benchmark (tools/bench/render_bench.h): ms per rendered
// frame along the bundled flythroughs, split into cull, draw and readback, with triangles and
// terrain error, nested against OSG culling, LOD settings against full resolution. Its options are
// declared with the other benchmarks' in tools/bench/bench_cli.cpp.
#include "tools/bench/bench_cli.h"
#include "tools/nestwalk/commands.h"

void nestwalk::tools::registerBenchRender(CLI::App& bench) {
  bench::addBenchCommand<bench::RenderBenchOptions>(
      bench, "render",
      "ms per rendered frame along the bundled flythroughs (cull, draw, readback), LOD and culling compared");
}
