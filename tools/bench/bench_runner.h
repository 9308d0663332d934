// What the Google Benchmark based benchmarks (volume_bench, terrain_bench) share: a collecting
// reporter (ns per item from items_per_second, median over repetitions, errors), the running of
// the registered benchmarks that match a filter, and small helpers for the tables and JSON.
#pragma once

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <map>
#include <numbers>
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

/// A target of the benchmark's issue and whether this run met it.
struct Target {
  std::string name, what;
  double value;
  bool met;
};

/// The targets as a JSON array of {name, target, value, met}.
nlohmann::ordered_json targetsJson(const std::vector<Target>& targets);

/// Prints "targets:" and one line a target (name and what in columns of the given widths), after
/// an empty line; nothing when there are none.
void printTargets(std::ostream& out, const std::vector<Target>& targets, int nameWidth, int whatWidth);

/// Adds the collector's errors (name: message) to `j` as "errors", when there are any.
void addErrors(nlohmann::ordered_json& j, const Collector& collector);

/// splitmix64 (Steele, Lea & Flood 2014) with explicit transforms: identical sequences everywhere.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : s_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (s_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  double gaussian() {  // Box-Muller
    const double u1 = 1.0 - uniform(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }

 private:
  std::uint64_t s_;
};

/// The processor's name from /proc/cpuinfo, "unknown" where there is none.
std::string cpuModel();

/// Fixed-point with `prec` decimals, "-" for NaN.
std::string fmt(double v, int prec = 2);

/// The number, or JSON null for NaN.
nlohmann::ordered_json numOrNull(double v);

}  // namespace nestwalk::bench
