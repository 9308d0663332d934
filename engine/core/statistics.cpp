#include "nestwalk/core/statistics.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace nestwalk {

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  const double n = double(values.size());
  // p * n first, so that integer p and n give an exact product (95 * 20 / 100 is 19, not
  // 19.000000000000004).
  double rank = std::ceil(std::clamp(p, 0.0, 100.0) * n / 100.0);
  rank = std::clamp(rank, 1.0, n);
  const auto k = static_cast<std::ptrdiff_t>(rank) - 1;
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[std::size_t(k)];
}

double mean(const std::vector<double>& values) {
  if (values.empty()) return 0.0;
  double sum = 0.0;
  for (double v : values) sum += v;
  return sum / double(values.size());
}

}  // namespace nestwalk
