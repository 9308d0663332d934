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

nlohmann::ordered_json targetsJson(const std::vector<Target>& targets) {
  nlohmann::ordered_json t = nlohmann::ordered_json::array();
  for (const Target& x : targets)
    t.push_back({{"name", x.name}, {"target", x.what}, {"value", x.value}, {"met", x.met}});
  return t;
}

void printTargets(std::ostream& out, const std::vector<Target>& targets, int nameWidth, int whatWidth) {
  if (targets.empty()) return;
  out << "\ntargets:\n";
  for (const Target& x : targets)
    out << "  " << std::left << std::setw(nameWidth) << x.name << std::setw(whatWidth) << x.what << std::right
        << std::setw(8) << fmt(x.value) << "  " << (x.met ? "met" : "NOT met") << "\n";
}

void addErrors(nlohmann::ordered_json& j, const Collector& collector) {
  nlohmann::ordered_json errs = nlohmann::ordered_json::object();
  for (const auto& [k, v] : collector.errors) errs[k] = v;
  if (!errs.empty()) j["errors"] = errs;
}

std::string cpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) {
        std::string s = line.substr(colon + 1);
        s.erase(0, s.find_first_not_of(" \t"));
        return s;
      }
    }
  }
  return "unknown";
}

std::string fmt(double v, int prec) {
  if (std::isnan(v)) return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision(prec) << v;
  return s.str();
}

nlohmann::ordered_json numOrNull(double v) {
  return std::isnan(v) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(v);
}

}  // namespace nestwalk::bench
