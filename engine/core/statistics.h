// Order statistics of measured values (timings, errors), as every summary and report prints them.
// Thread safety: pure functions.
#pragma once

#include <vector>

namespace nestwalk {

/// The nearest-rank percentile of `values`, p in [0, 100] (clamped): the smallest value with at
/// least p % of the values at or below it; p = 0 gives the minimum, 100 the maximum. 0 for an
/// empty list. Takes a copy (it reorders it).
double percentile(std::vector<double> values, double p);

/// The arithmetic mean; 0 for an empty list.
double mean(const std::vector<double>& values);

}  // namespace nestwalk
