// nestwalk bench models: what the guard around model files costs on good models
// (tools/bench/model_read_bench.h). Its options are declared with the other benchmarks' in
// tools/bench/bench_cli.cpp.
#include "tools/bench/bench_cli.h"
#include "tools/nestwalk/commands.h"

void nestwalk::tools::registerBenchModels(CLI::App& bench) {
  bench::addBenchCommand<bench::ModelReadBenchOptions>(
      bench, "models", "ms per model read, guarded (child process) against direct, on good models");
}
