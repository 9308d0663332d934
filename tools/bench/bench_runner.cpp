#include "tools/bench/bench_runner.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <ostream>
#include <sstream>

namespace nestwalk::bench {

bool Collector::ReportContext(const Context& context) {
  if (forward_) forward_->ReportContext(context);
  return true;
}

void Collector::ReportRuns(const std::vector<Run>& runs) {
  if (forward_) forward_->ReportRuns(runs);
  for (const Run& r : runs) {
    if (r.run_type != Run::RT_Iteration) continue;
    const std::string& name = r.run_name.function_name;
    if (r.error_occurred) {
      errors[name] = r.error_message;
      continue;
    }
    const auto it = r.counters.find("items_per_second");
    if (it != r.counters.end() && it->second.value > 0) samples[name].push_back(1e9 / it->second.value);
  }
}

void Collector::Finalize() {
  if (forward_) forward_->Finalize();
}

double Collector::ns(const std::string& name) const {
  const auto it = samples.find(name);
  if (it == samples.end() || it->second.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::vector<double> v = it->second;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

std::size_t Collector::repetitions() const {
  std::size_t n = 0;
  for (const auto& [k, v] : samples) n = std::max(n, v.size());
  return n;
}

std::string benchmarkSpec(const std::string& filter, const char* all) {
  if (filter.empty() || filter == "all" || filter == ".") return all;
  return filter;
}

std::size_t runBenchmarks(const std::string& spec, std::ostream* googleBenchmarkOutput, Collector& collector) {
  benchmark::BenchmarkReporter* forward = nullptr;
  if (googleBenchmarkOutput) {
    forward = benchmark::CreateDefaultDisplayReporter();
    forward->SetOutputStream(googleBenchmarkOutput);
    forward->SetErrorStream(googleBenchmarkOutput);
  }
  collector.forward_ = forward;
  return benchmark::RunSpecifiedBenchmarks(&collector, spec);
}

void configureBenchmarks(const std::vector<benchmark::internal::Benchmark*>& benchmarks, double minTime,
                         int repetitions) {
  for (auto* b : benchmarks) {
    b->Unit(benchmark::kMillisecond)->MinTime(minTime);
    if (repetitions > 0) b->Repetitions(repetitions);
  }
}

void addErrors(nlohmann::ordered_json& j, const Collector& collector) {
  nlohmann::ordered_json errs = nlohmann::ordered_json::object();
  for (const auto& [k, v] : collector.errors) errs[k] = v;
  if (!errs.empty()) j["errors"] = errs;
}

}  // namespace nestwalk::bench
