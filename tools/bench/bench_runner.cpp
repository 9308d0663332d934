#include "tools/bench/bench_runner.h"

#include <algorithm>
#include <ctime>
#include <limits>
#include <memory>
#include <ostream>

namespace nestwalk::bench {

/// Collects ns per item (1e9 / items_per_second) per benchmark name and the errors into a Suite,
/// forwarding everything to an optional reporter (Google Benchmark's own report).
class SuiteCollector : public benchmark::BenchmarkReporter {
 public:
  SuiteCollector(Suite& suite, benchmark::BenchmarkReporter* forward) : suite_(suite), forward_(forward) {}
  bool ReportContext(const Context& context) override {
    if (forward_) forward_->ReportContext(context);
    return true;
  }
  void ReportRuns(const std::vector<Run>& runs) override {
    if (forward_) forward_->ReportRuns(runs);
    for (const Run& r : runs) {
      if (r.run_type != Run::RT_Iteration) continue;
      const std::string& name = r.run_name.function_name;
      if (r.error_occurred) {
        suite_.errors_[name] = r.error_message;
        continue;
      }
      const auto it = r.counters.find("items_per_second");
      if (it != r.counters.end() && it->second.value > 0) suite_.samples_[name].push_back(1e9 / it->second.value);
    }
  }
  void Finalize() override {
    if (forward_) forward_->Finalize();
  }

 private:
  Suite& suite_;
  benchmark::BenchmarkReporter* forward_;
};

Suite& Suite::named(const std::string& name) {
  static std::map<std::string, Suite> suites;
  return suites.try_emplace(name, name).first->second;
}

std::string Suite::benchName(const std::string& method, const std::string& set) const {
  return name_ + "/" + method + "/" + set;
}

void Suite::add(const std::string& method, const std::string& set, Body body) {
  const std::string name = benchName(method, set);
  if (registered_.count(name)) return;
  registered_[name] = benchmark::RegisterBenchmark(
      name.c_str(), [this, name, body = std::move(body)](benchmark::State& st) { body(st, facts_[name]); });
}

std::optional<int> Suite::run(const SuiteOptions& opts, double minTime, const std::string& all, std::ostream& out) {
  for (auto& [name, b] : registered_) {
    b->Unit(benchmark::kMillisecond)->MinTime(minTime);
    if (opts.repetitions > 0) b->Repetitions(opts.repetitions);
  }
  facts_.clear();
  samples_.clear();
  errors_.clear();
  const std::string& f = opts.filter;
  const std::string spec = f.empty() || f == "all" || f == "." ? all : f;
  std::unique_ptr<benchmark::BenchmarkReporter> forward;
  if (opts.googleBenchmarkOutput) {
    forward.reset(benchmark::CreateDefaultDisplayReporter());
    forward->SetOutputStream(opts.googleBenchmarkOutput);
    forward->SetErrorStream(opts.googleBenchmarkOutput);
  }
  SuiteCollector collector(*this, forward.get());
  if (benchmark::RunSpecifiedBenchmarks(&collector, spec) == 0) {
    out << "nestwalk bench " << name_ << ": no benchmark matches '" << spec << "'\n";
    return 1;
  }
  if (samples_.empty() && errors_.empty()) return 0;
  return std::nullopt;
}

double Suite::ns(const std::string& method, const std::string& set) const {
  const auto it = samples_.find(benchName(method, set));
  if (it == samples_.end() || it->second.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::vector<double> v = it->second;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

const Facts* Suite::facts(const std::string& method, const std::string& set) const {
  const auto it = facts_.find(benchName(method, set));
  return it == facts_.end() ? nullptr : &it->second;
}

double Suite::fact(const std::string& method, const std::string& set, const std::string& key) const {
  const Facts* f = facts(method, set);
  const auto it = f ? f->find(key) : Facts::const_iterator();
  return f && it != f->end() ? it->second : std::numeric_limits<double>::quiet_NaN();
}

std::size_t Suite::repetitions() const {
  std::size_t n = 0;
  for (const auto& [name, v] : samples_) n = std::max(n, v.size());
  return n;
}

double threadSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

}  // namespace nestwalk::bench
