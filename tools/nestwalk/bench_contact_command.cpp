// nestwalk bench contact: the walker's exact stage against FCL's continuous collision and
// Bullet's convex sweep on heavy models (tools/bench/contact_bench.h). Its options are declared
// with the other benchmarks' in tools/bench/bench_cli.cpp.
#include "tools/bench/bench_cli.h"
#include "tools/nestwalk/commands.h"

void nestwalk::tools::registerBenchContact(CLI::App& bench) {
  bench::addBenchCommand<bench::ContactBenchOptions>(
      bench, "contact", "us per body-box sweep into heavy models: the k-DOP tree vs FCL and Bullet, time-of-contact agreement");
}
