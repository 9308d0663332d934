// nestwalk bench walker [--json] [--quick]: the walker benchmark (tools/bench/walker_bench.h):
// walker steps over 1k..1M instances, the broad phase against btDbvt and FCL, and the BV-test
// counts of each hierarchy on the bundled flythroughs (fACT's Table 2).
#include "tools/bench/walker_bench.h"
#include "tools/nestwalk/commands.h"

#include <filesystem>
#include <iostream>
#include <memory>

namespace nestwalk::tools {

void registerBenchWalker(CLI::App& bench) {
  auto opts = std::make_shared<bench::WalkerBenchOptions>();
  auto noTable2 = std::make_shared<bool>(false);
  CLI::App* cmd = bench.add_subcommand(
      "walker", "Walker steps at 1k-1M instances, broad phase vs btDbvt and FCL, BV tests per hierarchy");
  cmd->add_flag("--json", opts->json, "Print the results as JSON instead of tables");
  cmd->add_flag("--quick", opts->quick, "Smoke test: 1k and 10k instances, 5k steps");
  cmd->add_option("--sizes", opts->sizes, "Instance counts (default 1000 100000 1000000)");
  cmd->add_option("--steps", opts->steps, "Timed walker steps per size (default 200000)");
  cmd->add_option("--scene", opts->scene, "Scene for the BV-test table (default: the bundled mining dump)");
  cmd->add_option("--scripts", opts->scripts, "Its flythroughs (default: the bundled ones)");
  cmd->add_flag("--no-table2", *noTable2, "Skip the BV-test table");
  cmd->add_flag("!--no-broad-phase", opts->broadPhase, "Skip the broad-phase comparison");
  cmd->callback([opts, noTable2] {
    bench::WalkerBenchOptions o = *opts;
    if (*noTable2) {
      o.scene.clear();
      o.scripts.clear();
    } else if (o.scene.empty()) {
      const std::filesystem::path dir(NESTWALK_BUNDLED_SCENE_DIR);
      o.scene = (dir / "scene.json").string();
      if (o.scripts.empty())
        for (const char* s : {"bench_patrol.txt", "ramp_descent.txt", "low_flight.txt"})
          o.scripts.push_back((dir / "scripts" / s).string());
      if (!std::filesystem::exists(o.scene)) {
        std::cerr << "nestwalk: note: " << o.scene << " is absent (build the bundled scene); skipping the BV-test table\n";
        o.scene.clear();
      }
    }
    const int rc = bench::runWalkerBench(o, std::cout);
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
}

}  // namespace nestwalk::tools
