// nestwalk bench render [--json] [--quick]: the rendering benchmark (tools/bench/render_bench.h):
// ms per rendered frame along the bundled flythroughs, split into cull, draw and readback, with
// triangles and terrain error, nested against OSG culling, LOD settings against full resolution.
#include "nestwalk/core/input_error.h"
#include "tools/bench/render_bench.h"
#include "tools/nestwalk/commands.h"

#include <filesystem>
#include <iostream>
#include <memory>

namespace nestwalk::tools {

void registerBenchRender(CLI::App& bench) {
  auto opts = std::make_shared<bench::RenderBenchOptions>();
  CLI::App* cmd = bench.add_subcommand(
      "render", "ms per rendered frame along the bundled flythroughs (cull, draw, readback), LOD and culling compared");
  cmd->add_flag("--json", opts->json, "Print the results as JSON instead of tables");
  cmd->add_flag("--quick", opts->quick, "Smoke test: 320x180, 8 frames per flythrough, two configurations");
  cmd->add_option("--width", opts->width, "Frame width (default 1280)")->check(CLI::Range(16, 8192));
  cmd->add_option("--height", opts->height, "Frame height (default 720)")->check(CLI::Range(16, 8192));
  cmd->add_option("--frames", opts->framesPerScript, "Frames per flythrough (default 120)")->check(CLI::Range(1, 100000));
  cmd->add_option("--scene", opts->scene, "Scene file (default: the bundled mining dump)");
  cmd->add_option("--scripts", opts->scripts, "Its flythroughs (default: the bundled ones)");
  cmd->callback([opts] {
    bench::RenderBenchOptions o = *opts;
    if (o.scene.empty()) {
      const std::filesystem::path dir(NESTWALK_BUNDLED_SCENE_DIR);
      o.scene = (dir / "scene.json").string();
      if (!std::filesystem::exists(o.scene))
        throw InputError(o.scene + ": the bundled scene is absent; build it (tools/build.sh) or pass --scene");
      if (o.scripts.empty())
        for (const char* s : {"bench_patrol.txt", "ramp_descent.txt", "low_flight.txt"})
          o.scripts.push_back((dir / "scripts" / s).string());
    }
    if (o.scripts.empty()) throw InputError("--scripts: give the flythroughs to render along");
    const int rc = bench::runRenderBench(o, std::cout);
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
}

}  // namespace nestwalk::tools
