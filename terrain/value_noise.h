// Smooth value noise for the synthetic terrain and its orthophoto: values at the points of a square
// lattice, blended with a smoothstep in each direction. The lattice's values come from the caller
// (each generator hashes its own seed), so the noise is what that hash makes it, bit for bit.
// Thread safety: a pure function.
#pragma once

#include <cmath>
#include <cstdint>

namespace nestwalk::terrain {

/// Noise at (x, y) on a lattice of spacing `wavelength` (same units as x and y): `lattice(i, j)`
/// gives the value at lattice point (i, j); the result lies within the range of those values.
template <class Lattice>
double valueNoise(const Lattice& lattice, double x, double y, double wavelength) {
  const double fx = x / wavelength, fy = y / wavelength;
  const double ix = std::floor(fx), iy = std::floor(fy);
  auto smooth = [](double t) { return t * t * (3.0 - 2.0 * t); };
  const double tx = smooth(fx - ix), ty = smooth(fy - iy);
  const auto i = std::int64_t(ix), j = std::int64_t(iy);
  const double a = lattice(i, j), b = lattice(i + 1, j);
  const double c = lattice(i, j + 1), d = lattice(i + 1, j + 1);
  const double south = a + tx * (b - a), north = c + tx * (d - c);
  return south + ty * (north - south);
}

}  // namespace nestwalk::terrain
