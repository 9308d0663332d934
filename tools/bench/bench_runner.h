// What the Google Benchmark based benchmarks (volume_bench, terrain_bench) share: a collecting
// reporter (ns per item from items_per_second, median over repetitions, errors), the running of
// the registered benchmarks that match a filter, and small helpers for the tables and JSON.
#pragma once

#include "nestwalk/core/machine.h"
#include "nestwalk/core/random.h"
#include "nestwalk/core/statistics.h"
#include "nestwalk/report/number_text.h"
#include "nestwalk/report/targets.h"

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

namespace nestwalk::bench {

/// Collects ns per item (1e9 / items_per_second) per benchmark name and the errors, forwarding
/// everything to an optional reporter (Google Benchmark's own report).
class Collector : public benchmark::BenchmarkReporter {
 public:
  explicit Collector(benchmark::BenchmarkReporter* forward = nullptr) : forward_(forward) {}

  bool ReportContext(const Context& context) override;
  void ReportRuns(const std::vector<Run>& runs) override;
  void Finalize() override;

  /// ns per item of a benchmark (median over repetitions), NaN when it did not run.
  double ns(const std::string& name) const;
  /// The largest number of samples of any benchmark (the repetitions that ran).
  std::size_t repetitions() const;

  std::map<std::string, std::vector<double>> samples;
  std::map<std::string, std::string> errors;

 private:
  friend std::size_t runBenchmarks(const std::string&, std::ostream*, Collector&);
  benchmark::BenchmarkReporter* forward_;
};

/// The Google Benchmark filter for `filter`: empty, "all" or "." give `all`.
std::string benchmarkSpec(const std::string& filter, const char* all);

/// Runs the registered benchmarks matching `spec` through benchmark::RunSpecifiedBenchmarks with
/// `collector`; Google Benchmark's own report goes to `googleBenchmarkOutput` when not null.
/// Returns the number of matching benchmarks.
std::size_t runBenchmarks(const std::string& spec, std::ostream* googleBenchmarkOutput, Collector& collector);

/// Sets the unit (ms), minimum time and, when > 0, the repetitions of the registered `benchmarks`.
void configureBenchmarks(const std::vector<benchmark::internal::Benchmark*>& benchmarks, double minTime,
                         int repetitions);

/// Adds the collector's errors (name: message) to `j` as "errors", when there are any.
void addErrors(nlohmann::ordered_json& j, const Collector& collector);

}  // namespace nestwalk::bench
