// The skeleton every Google Benchmark suite (volumes, terrain, broadphase) shares: its options, the
// registration of its benchmarks ("<suite>/<method>/<set>", once per process), the timed loop (one
// pass of a method over a whole data set per iteration), the facts of a benchmark (counted once, on
// the answers of one pass, outside the timed loop) and the running of the benchmarks that match a
// filter with a collecting reporter: ns per item from items_per_second, the median over
// repetitions, and the errors. Each suite keeps its run's settings and data in one static Config of
// its own file; the data are freed at the end of the run by a ReleaseAtEnd. BenchOptions::orDefault
// (also used by bench walker) picks an option's given value, else its quick or full default.
#pragma once

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <map>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

namespace nestwalk::bench {

/// What every benchmark's command line sets (bench_cli.h declares the flags).
struct BenchOptions {
  bool json = false;   // print one JSON document instead of the tables
  bool quick = false;  // smoke run: small data sets, short runs

  /// `given` when the command line set it (not 0, not empty), else the smoke run's default with
  /// quick, else the full run's.
  template <class T>
  T orDefault(const T& given, const std::type_identity_t<T>& quickDefault, const std::type_identity_t<T>& full) const {
    return given != T{} ? given : quick ? quickDefault : full;
  }
};

/// What the Google Benchmark suites add.
struct SuiteOptions : BenchOptions {
  double minTimeSeconds = 0;  // Google Benchmark minimum time per benchmark; 0: the suite's default
  int repetitions = 0;  // runs per benchmark, the tables show the median; 0: --benchmark_repetitions (1)
  /// Regular expression on benchmark names (Google Benchmark's --benchmark_filter); empty, "all"
  /// or ".": every benchmark of the suite.
  std::string filter;
  /// Also send Google Benchmark's own report to this stream while running; null: print nothing
  /// but the final tables or JSON.
  std::ostream* googleBenchmarkOutput = nullptr;

  /// The minimum time per benchmark: minTimeSeconds when given, else 0.02 s with quick (a smoke
  /// run), else the suite's `full` default.
  double minTime(double full) const { return minTimeSeconds > 0 ? minTimeSeconds : (quick ? 0.02 : full); }
};

/// Facts of one benchmark: named values counted once outside the timed loop (fraction of hits,
/// disagreements with the reference, build seconds, ...). They are also Google Benchmark counters.
using Facts = std::map<std::string, double>;

/// One pass of a method over a data set: answers every item once, writes item k's answer to
/// answers[k] when `answers` is not null, and returns a checksum of the answers (the timed loop
/// keeps it, so that the compiler cannot drop the work). A pass binds what its loop reads to local
/// references first: its closure lives on the heap, where a member read after a call in the loop
/// would be read again at every item.
template <class Answer>
using Pass = std::function<double(Answer* answers)>;

/// The number of true answers (bool), or the sum of the answers that are not NaN (double).
inline double checksum(double answer) { return std::isnan(answer) ? 0.0 : answer; }

/// The timed loop of a pass: the checksum of f(k) for k in [0, n), with no store. Flattened: every
/// inline function f calls is inlined here, as at a hot call site of the engine, whatever the
/// compiler's inlining budget would decide for an f that also has the untimed loop's call site.
template <class F>
[[gnu::flatten]] double timedLoop(std::size_t n, const F& f) {
  if constexpr (std::is_same_v<decltype(f(n)), bool>) {
    std::size_t hits = 0;
    for (std::size_t k = 0; k < n; ++k) hits += f(k) ? 1 : 0;
    return double(hits);
  } else {
    double sum = 0;
    for (std::size_t k = 0; k < n; ++k) sum += checksum(f(k));
    return sum;
  }
}

/// The loop of a pass: f(k) for k in [0, n) (bool, or double with NaN for "no answer"), stored to
/// answers[k] when `answers` is not null (else timedLoop); returns the checksum of the answers.
template <class Answer, class F>
double answerAll(std::size_t n, Answer* answers, const F& f) {
  if (!answers) return timedLoop(n, f);
  double sum = 0;
  for (std::size_t k = 0; k < n; ++k) sum += checksum(double(answers[k] = f(k)));
  return sum;
}

/// The benchmarks of one suite, registered with Google Benchmark once per process, and what their
/// last run measured.
class Suite {
 public:
  /// The body of a benchmark: the state and the benchmark's facts (kept between its runs).
  using Body = std::function<void(benchmark::State&, Facts&)>;

  explicit Suite(std::string name) : name_(std::move(name)) {}
  /// The suite of that name, one per process (Google Benchmark's registrations are too).
  static Suite& named(const std::string& name);

  /// "<suite>/<method>/<set>".
  std::string benchName(const std::string& method, const std::string& set) const;
  /// Registers the benchmark, unless a benchmark of that name already is.
  void add(const std::string& method, const std::string& set, Body body);
  /// Registers "<method.key>/<set.key>" for every set and method that applies(set, method), set after
  /// set (the order they run in: a suite keeps one set's data at a time); run(set, method, state,
  /// facts) is the benchmark. The sets and methods must outlive the process's benchmarks.
  template <class Sets, class Methods, class Applies, class Run>
  void addEach(const Sets& sets, const Methods& methods, const Applies& applies, const Run& run) {
    for (const auto& set : sets)
      for (const auto& m : methods)
        if (applies(set, m))
          add(m.key, set.key, [&set, &m, run](benchmark::State& state, Facts& facts) { run(set, m, state, facts); });
  }

  /// Runs the registered benchmarks matching opts.filter (`all`: the regular expression when it
  /// selects the whole suite) with unit ms, minimum time `minTime` and opts.repetitions, through
  /// benchmark::RunSpecifiedBenchmarks with a collecting reporter. Clears the facts first. Returns
  /// the exit status when there is nothing to report: 1 when no benchmark matched (after printing
  /// so to `out`), 0 when they were only listed (--benchmark_list_tests).
  std::optional<int> run(const SuiteOptions& opts, double minTime, const std::string& all, std::ostream& out);

  /// ns per item of the benchmark (median over repetitions), NaN when it did not run.
  double ns(const std::string& method, const std::string& set) const;
  /// The benchmark's facts; null when it did not run.
  const Facts* facts(const std::string& method, const std::string& set) const;
  /// One fact of the benchmark; NaN when it did not run or has no such fact.
  double fact(const std::string& method, const std::string& set, const std::string& key) const;
  /// The largest number of repetitions any benchmark ran.
  std::size_t repetitions() const;
  /// Benchmark name -> error message, of the benchmarks that failed.
  const std::map<std::string, std::string>& errors() const { return errors_; }

 private:
  friend class SuiteCollector;
  std::string name_;
  std::map<std::string, benchmark::internal::Benchmark*> registered_;
  std::map<std::string, Facts> facts_;
  std::map<std::string, std::vector<double>> samples_;  // ns per item, per repetition
  std::map<std::string, std::string> errors_;
};

/// The name of the fact timePasses records the number of items in (the mark that the facts were
/// counted).
inline constexpr const char* kItemsFact = "items";

/// The timed loop of every suite: on the benchmark's first run one pass with answers, `judge`
/// turning them (std::vector<Answer>&, its own to reorder) into facts; then pass(nullptr) once per iteration, with
/// SetItemsProcessed(iterations * items), so ns per item = 1e9 / items_per_second. The facts become
/// counters (and a time_per_item counter shows the time per item in the console report).
template <class Answer, class Judge>
void timePasses(benchmark::State& state, Facts& facts, std::size_t items, const Pass<Answer>& pass,
                const Judge& judge) {
  if (!facts.count(kItemsFact)) {
    std::vector<Answer> answers(items);
    pass(answers.data());
    judge(answers, facts);
    facts[kItemsFact] = double(items);
  }
  for (auto _ : state) benchmark::DoNotOptimize(pass(nullptr));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(items));
  state.counters["time_per_item"] =
      benchmark::Counter(double(items), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  for (const auto& [key, value] : facts)
    if (!std::isnan(value)) state.counters[key] = value;
}

/// Calls `release` when it goes out of scope, also when the run throws: a suite frees the data its
/// benchmarks kept (a few GB at full size) at the end of its run.
class ReleaseAtEnd {
 public:
  explicit ReleaseAtEnd(std::function<void()> release) : release_(std::move(release)) {}
  ~ReleaseAtEnd() { release_(); }
  ReleaseAtEnd(const ReleaseAtEnd&) = delete;
  ReleaseAtEnd& operator=(const ReleaseAtEnd&) = delete;

 private:
  std::function<void()> release_;
};

/// CPU time of this thread in seconds: build times measured like the queries' CPU times, unaffected
/// by other processes on a shared machine (wall time there can be twice as long).
double threadSeconds();

}  // namespace nestwalk::bench
