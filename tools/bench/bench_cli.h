// The command line of every benchmark, declared once for its two front ends: the `nestwalk bench
// NAME` subcommand (tools/nestwalk/bench_*_command.cpp) and, for the Google Benchmark suites, the
// program in tests/bench, which also takes Google Benchmark's --benchmark_* flags. Every benchmark
// takes --json and --quick; the suites also --min-time, --repetitions and --filter (and the
// subcommand --verbose); then the benchmark's own options. The bundled scene
// (assets/generators/bundled_scene.h) is the default of the benchmarks that play flythroughs.
#pragma once

#include "tools/bench/broadphase_bench.h"
#include "tools/bench/contact_bench.h"
#include "tools/bench/model_read_bench.h"
#include "tools/bench/render_bench.h"
#include "tools/bench/terrain_bench.h"
#include "tools/bench/volume_bench.h"
#include "tools/bench/walker_bench.h"

#include <CLI/CLI.hpp>

#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>
#include <type_traits>

namespace nestwalk::bench {

/// Declares the benchmark's options on `cmd`, to be written into `o` when it parses.
void declareOptions(CLI::App& cmd, VolumeBenchOptions& o);
void declareOptions(CLI::App& cmd, TerrainBenchOptions& o);
void declareOptions(CLI::App& cmd, BroadPhaseBenchOptions& o);
void declareOptions(CLI::App& cmd, WalkerBenchOptions& o);
void declareOptions(CLI::App& cmd, RenderBenchOptions& o);
void declareOptions(CLI::App& cmd, ModelReadBenchOptions& o);
void declareOptions(CLI::App& cmd, ContactBenchOptions& o);

/// What the parsed options leave to be decided: the bundled scene and its flythroughs where none
/// was given (the render benchmark: InputError when it is absent; the walker benchmark: skips its
/// BV-test table then, with a note on stderr).
inline void completeOptions(BenchOptions&) {}
void completeOptions(WalkerBenchOptions& o);
void completeOptions(RenderBenchOptions& o);

/// Adds `nestwalk bench NAME`: its options, and a callback that runs the benchmark on stdout and
/// ends the program with its status (CLI::RuntimeError) when that is not 0.
template <class Options>
void addBenchCommand(CLI::App& bench, const std::string& name, const std::string& description) {
  auto opts = std::make_shared<Options>();
  auto verbose = std::make_shared<bool>(false);
  CLI::App* cmd = bench.add_subcommand(name, description);
  declareOptions(*cmd, *opts);
  if constexpr (std::is_base_of_v<SuiteOptions, Options>)
    cmd->add_flag("--verbose", *verbose, "Also print Google Benchmark's own report to stderr while running");
  cmd->callback([opts, verbose] {
    Options o = *opts;
    completeOptions(o);
    if constexpr (std::is_base_of_v<SuiteOptions, Options>)
      if (*verbose) o.googleBenchmarkOutput = &std::cerr;
    const int rc = runBenchmark(o, std::cout);
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
}

/// main() of a suite's Google Benchmark program: Google Benchmark takes its --benchmark_* flags
/// (--benchmark_min_time sets the minimum time: the benchmarks carry their own, which would override
/// the flag; --benchmark_filter is the filter unless --filter is given), the rest are the
/// subcommand's options. Google Benchmark's report goes to stdout while running (stderr with
/// --json), then the tables or the JSON to stdout. Returns the benchmark's status.
template <class Options>
int benchProgram(int argc, char** argv) {
  static_assert(std::is_base_of_v<SuiteOptions, Options>);
  Options o;
  const std::string minTimeFlag = "--benchmark_min_time=";
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]).rfind(minTimeFlag, 0) == 0)
      o.minTimeSeconds = std::strtod(argv[i] + minTimeFlag.size(), nullptr);
  benchmark::Initialize(&argc, argv);
  CLI::App app{std::string(argv[0]) + ": a nestwalk benchmark; also takes Google Benchmark's --benchmark_* flags"};
  declareOptions(app, o);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (o.filter.empty()) o.filter = benchmark::GetBenchmarkFilter();
  o.googleBenchmarkOutput = o.json ? &std::cerr : &std::cout;
  const int rc = runBenchmark(o, std::cout);
  std::cout.flush();
  benchmark::Shutdown();
  return rc;
}

}  // namespace nestwalk::bench
