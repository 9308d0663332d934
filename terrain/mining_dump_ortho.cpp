#include "nestwalk/terrain/mining_dump_ortho.h"
#include "nestwalk/terrain/value_noise.h"

#include "nestwalk/core/random.h"
#include "nestwalk/terrain/terrain_imagery.h"

#include <algorithm>
#include <cmath>
#include <numbers>
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

/// How much of map point (e, n) of the ramp's running surface a tyre track covers, in [0, 1], and
/// the tread's factor there (see kOrthoLaneOffsetM).
struct TrackCover {
  double weight = 0, tread = 1;
};
TrackCover tyreTrackCover(const MiningDumpLayout& L, std::uint64_t salted, double e, double n, bool tread) {
  const double az = L.azimuthDeg * std::numbers::pi / 180.0;
  const double de = e - L.centreE, dn = n - L.centreN;
  const double u = de * std::sin(az) + dn * std::cos(az), across = de * std::cos(az) - dn * std::sin(az) - L.rampV;
  TrackCover cover;
  int path = 0;
  for (const double lane : {-kOrthoLaneOffsetM, kOrthoLaneOffsetM})
    for (const double side : {-0.5, 0.5}) {
      const double centre =
          lane + side * kOrthoWheelGaugeM + kOrthoTrackWanderM * valueNoise(salted ^ (0x7A0 + std::uint64_t(path++)), u, 0.0,
                                                                            kOrthoTrackWanderWavelengthM);
      const double inside = 0.5 * kOrthoTrackWidthM - std::abs(across - centre);
      cover.weight = std::max(cover.weight, std::clamp(inside / kOrthoTrackEdgeM + 0.5, 0.0, 1.0));
    }
  if (tread) cover.tread = 1.0 + kOrthoTreadAmplitude * (std::sin(2 * std::numbers::pi * u / kOrthoTreadPitchM) > 0 ? 1 : -1);
  return cover;
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

void writeFineMiningDumpOrtho(const std::string& out, const MiningDumpParams& params, double pixel,
                              const std::string& crs, bool overwrite) {
  MiningDumpParams fine = params;
  fine.cell = pixel;
  fine.fineRelief = false;  // the materials alone are wanted
  const MiningDumpGenerator generator(fine);
  const int n = generator.cols();
  const std::uint64_t salted = params.seed ^ kOrthoSeedSalt;
  const bool textured = pixel < kOrthoTextureBelowPixelM;
  const bool tread = pixel <= kOrthoTreadBelowPixelM;
  SplitMix64 grain(salted ^ 0x6A7E);
  std::vector<float> heights;
  std::vector<DumpSurface> surfaces;
  writeImageryCog(
      out, n, n,
      [&](int r0, int count, std::uint8_t* rgb) {
        heights.resize(std::size_t(count) * std::size_t(n));
        surfaces.resize(heights.size());
        generator.generateRows(r0, count, heights.data(), surfaces.data());
        for (int r = 0; r < count; ++r) {
          const double y = -(r0 + r) * pixel;
          for (int c = 0; c < n; ++c) {
            const double x = c * pixel;
            const std::size_t at = std::size_t(r) * std::size_t(n) + std::size_t(c);
            const DumpSurface surface = surfaces[at];
            double factor = 1.0 + kOrthoPatchAmplitude * valueNoise(salted, x, y, kOrthoPatchWavelength);
            double colour[3];
            for (int k = 0; k < 3; ++k) colour[k] = kDumpSurfaceColours[std::size_t(surface)][std::size_t(k)];
            if (textured) {
              factor *= 1.0 + kOrthoGravelAmplitude * valueNoise(salted ^ 1, x, y, kOrthoGravelWavelengthM) +
                        kOrthoGritAmplitude * valueNoise(salted ^ 2, x, y, kOrthoGritWavelengthM);
              const TrackCover track = surface == DumpSurface::Ramp
                                           ? tyreTrackCover(generator.layout(), salted, generator.originX() + x,
                                                            generator.originY() + y, tread)
                                           : TrackCover{};
              if (track.weight < 1 && surface != DumpSurface::Ground && surface != DumpSurface::Ditch &&
                  valueNoise(salted ^ 3, x, y, kOrthoStoneWavelengthM) > kOrthoStoneThreshold)
                factor *= valueNoise(salted ^ 4, x, y, 2 * kOrthoStoneWavelengthM) > 0 ? 1.3 : 0.65;
              factor *= 1.0 + track.weight * (kOrthoTrackDarkening * track.tread - 1.0);
              if (surface == DumpSurface::Ground || surface == DumpSurface::Top) {
                const double v = valueNoise(salted ^ 5, x, y, kOrthoVegetationWavelengthM) +
                                 0.3 * valueNoise(salted ^ 6, x, y, kOrthoVegetationWavelengthM / 4);
                const double w = std::clamp((v - kOrthoVegetationThreshold) / 0.2, 0.0, 1.0);
                for (int k = 0; k < 3; ++k)
                  colour[k] = (1 - w) * colour[k] + w * kOrthoVegetationColour[std::size_t(k)];
              }
            }
            for (int k = 0; k < 3; ++k) {
              const double v = colour[k] * factor + kOrthoGrainLevels * grain.gaussian();
              rgb[at * 3u + std::size_t(k)] = std::uint8_t(std::clamp(std::round(v), 0.0, 255.0));
            }
          }
        }
      },
      generator.originX(), generator.originY(), pixel, pixel, crs, overwrite, ImageryCompression::Jpeg);
}

}  // namespace nestwalk::terrain
