// Test terrains of 513 x 513 samples at 1 m (every level's cells square) shared by the paged terrain
// tests: hills (smooth hills, a gentle tilt and +-0.4 m of noise per sample, optionally holes) and
// terraces (benches with centimetre waves, the surface level 0's refinements are for).
#pragma once

#include "nestwalk/terrain/heightfield.h"

#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <random>
#include <vector>

namespace nestwalk::test {

inline constexpr int kHillsSamples = 513;  // per side, 1 m apart

/// `holeFraction` of the samples NaN; bigHole: also columns 256..400 of rows 100..300.
inline std::shared_ptr<const terrain::Heightfield> hills(double holeFraction = 0.0, bool bigHole = false) {
  constexpr int n = kHillsSamples;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-0.4, 0.4), unit(0, 1);
  std::vector<float> h(std::size_t(n) * n);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      double v = 300 + 25 * std::sin(0.031 * c) * std::cos(0.023 * r) + 0.05 * c + noise(rng);
      if (unit(rng) < holeFraction || (bigHole && c >= 256 && c <= 400 && r >= 100 && r <= 300))
        v = std::numeric_limits<double>::quiet_NaN();
      h[std::size_t(r) * n + std::size_t(c)] = float(v);
    }
  return std::make_shared<const terrain::Heightfield>(n, n, std::move(h), 500000.0, 6900000.0, 1.0, 1.0);
}

/// Benches around (230, -280): flat treads 12 m deep, faces rising 6 m over 8 m, centimetre waves.
inline std::shared_ptr<const terrain::Heightfield> terraces() {
  constexpr int n = kHillsSamples;
  std::vector<float> h(std::size_t(n) * n);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      const double d = std::hypot(c - 230.0, r - 280.0);
      const double step = std::floor(d / 20.0), within = d - 20.0 * step;
      const double v = 300.0 - 6.0 * step - (within > 12.0 ? 6.0 * (within - 12.0) / 8.0 : 0.0) +
                       0.05 * std::sin(0.8 * c) * std::cos(0.6 * r);
      h[std::size_t(r) * n + std::size_t(c)] = float(v);
    }
  return std::make_shared<const terrain::Heightfield>(n, n, std::move(h), 500000.0, 6900000.0, 1.0, 1.0);
}

}  // namespace nestwalk::test
