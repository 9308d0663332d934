// Percentiles and means of one figure of a benchmark's records (its frames, steps or queries): the
// figure read from every record by a member pointer or a function, as a double (integers exactly up
// to 2^53) in the record's own unit, then core/statistics.h's percentile (nearest rank) or mean. A
// benchmark keeps its records whole instead of one list per figure it reports.
// Thread safety: pure functions.
#pragma once

#include "nestwalk/core/statistics.h"

#include <functional>
#include <vector>

namespace nestwalk::bench {

/// figure(record) of every record, as a double.
template <class Record, class Figure>
std::vector<double> figureOf(const std::vector<Record>& records, const Figure& figure) {
  std::vector<double> values;
  values.reserve(records.size());
  for (const Record& r : records) values.push_back(double(std::invoke(figure, r)));
  return values;
}

/// The nearest-rank percentile of the records' figure (p 0: the least, 100: the largest; 0 when
/// there are no records).
template <class Record, class Figure>
double percentileOf(const std::vector<Record>& records, double p, const Figure& figure) {
  return percentile(figureOf(records, figure), p);
}

/// The mean of the records' figure (0 when there are no records).
template <class Record, class Figure>
double meanOf(const std::vector<Record>& records, const Figure& figure) {
  return mean(figureOf(records, figure));
}

}  // namespace nestwalk::bench
