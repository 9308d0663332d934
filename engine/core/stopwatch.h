// Wall-clock timing for the reports and benchmarks that time whole plays or loops themselves (the
// Google Benchmark programs time their own loops).
// Thread safety: pure functions over std::chrono::steady_clock; leastSeconds calls `run` on the
// calling thread.
#pragma once

#include <algorithm>
#include <chrono>
#include <limits>

namespace nestwalk {

/// Seconds since `start` on the steady clock.
inline double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Microseconds from `start` to `end` on the steady clock.
inline double microsBetween(std::chrono::steady_clock::time_point start, std::chrono::steady_clock::time_point end) {
  return std::chrono::duration<double, std::micro>(end - start).count();
}

/// The least wall-clock time, in seconds, of `repetitions` calls of `run` (at least one call): the
/// call least disturbed by the rest of the machine.
template <class Run>
double leastSeconds(int repetitions, const Run& run) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < std::max(repetitions, 1); ++i) {
    const auto start = std::chrono::steady_clock::now();
    run();
    best = std::min(best, secondsSince(start));
  }
  return best;
}

/// Keeps the compiler from dropping a computation whose result is otherwise unused (a timed loop's
/// sum).
template <class T>
inline void keepResult(const T& value) {
  asm volatile("" : : "r,m"(value) : "memory");
}

}  // namespace nestwalk
