#include "nestwalk/terrain/mining_dump_ortho.h"
#include "nestwalk/terrain/value_noise.h"

#include "nestwalk/core/random.h"
#include "nestwalk/terrain/terrain_imagery.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace nestwalk::terrain {
namespace {

/// Keeps the orthophoto's draws apart from the terrain's, which use the same seed.
constexpr std::uint64_t kOrthoSeedSalt = 0x0A7E0F07011Bull;

/// A lattice point's value in [-1, 1], from its own SplitMix64 stream.
double latticeValue(std::uint64_t seed, std::int64_t i, std::int64_t j) {
  SplitMix64 rng(seed ^ (std::uint64_t(i) * 0x9E3779B97F4A7C15ull) ^ (std::uint64_t(j) * 0xC2B2AE3D27D4EB4Full));
  return rng.uniform(-1.0, 1.0);
}

/// Smooth value noise in [-1, 1] on a lattice of spacing `wavelength` (value_noise.h).
double valueNoise(std::uint64_t seed, double x, double y, double wavelength) {
  return terrain::valueNoise([seed](std::int64_t i, std::int64_t j) { return latticeValue(seed, i, j); }, x, y,
                             wavelength);
}

}  // namespace

std::vector<std::uint8_t> miningDumpOrtho(const MiningDump& dump, std::uint64_t seed) {
  const std::size_t n = std::size_t(dump.cols) * std::size_t(dump.rows);
  if (dump.cols < 1 || dump.rows < 1 || dump.surfaces.size() != n)
    throw std::invalid_argument("miningDumpOrtho: the dump has no surface for every sample");
  const std::uint64_t salted = seed ^ kOrthoSeedSalt;
  SplitMix64 grain(salted);
  std::vector<std::uint8_t> rgb(n * 3u);
  for (int r = 0; r < dump.rows; ++r) {
    // Patches in map coordinates relative to the area's first sample (whole lattice cells from there).
    const double y = -r * dump.cell;
    for (int c = 0; c < dump.cols; ++c) {
      const std::size_t at = std::size_t(r) * std::size_t(dump.cols) + std::size_t(c);
      const auto& base = kDumpSurfaceColours[std::size_t(dump.surfaces[at])];
      const double brightness = 1.0 + kOrthoPatchAmplitude * valueNoise(salted, c * dump.cell, y, kOrthoPatchWavelength);
      for (int k = 0; k < 3; ++k) {
        const double v = base[std::size_t(k)] * brightness + kOrthoGrainLevels * grain.gaussian();
        rgb[at * 3u + std::size_t(k)] = std::uint8_t(std::clamp(std::round(v), 0.0, 255.0));
      }
    }
  }
  return rgb;
}

void writeMiningDumpOrtho(const std::string& out, const MiningDump& dump, std::uint64_t seed, const std::string& crs,
                          bool overwrite) {
  writeImageryCog(out, dump.cols, dump.rows, miningDumpOrtho(dump, seed), dump.originX, dump.originY, dump.cell,
                  dump.cell, crs, overwrite);
}

}  // namespace nestwalk::terrain
