// A rough deterministic test grid shared by the terrain chunk and terrain cut tests.
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>
#include <random>
#include <vector>

namespace nestwalk::test {

/// Smooth hills plus per-sample noise (+-1.5 m), row-major, `holeFraction` of the samples NaN.
inline std::vector<float> roughHeights(int cols, int rows, unsigned seed, double holeFraction = 0.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-1.5, 1.5), unit(0.0, 1.0);
  std::vector<float> h(std::size_t(cols) * std::size_t(rows));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      double v = 100 + 20 * std::sin(0.11 * c) * std::cos(0.07 * r) + 0.3 * c - 0.2 * r + noise(rng);
      if (holeFraction > 0 && unit(rng) < holeFraction) v = std::numeric_limits<double>::quiet_NaN();
      h[std::size_t(r) * std::size_t(cols) + std::size_t(c)] = float(v);
    }
  return h;
}

}  // namespace nestwalk::test
