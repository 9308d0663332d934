// The nearest-rank percentile computed the slow, obvious way (sort, then integer arithmetic): the
// reference the summaries' percentiles are checked against.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace nestwalk::test {

/// The value at rank ceil(p n / 100) (1-based, at least 1) of the sorted list, p an integer.
inline double nearestRank(std::vector<double> v, int p) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  std::size_t rank = (std::size_t(p) * n + 99) / 100;
  if (rank < 1) rank = 1;
  return v[rank - 1];
}

}  // namespace nestwalk::test
