#include "nestwalk/terrain/mining_dump.h"
#include "nestwalk/terrain/value_noise.h"

#include "nestwalk/core/angles.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

namespace nestwalk::terrain {
namespace {


/// Uniform in [0, 1) from the generator's raw 64 bits (no library distribution).
double uniform(std::mt19937_64& rng) { return double(rng() >> 11) * 0x1.0p-53; }
double uniform(std::mt19937_64& rng, double lo, double hi) { return lo + (hi - lo) * uniform(rng); }

/// A hash of a lattice point to [-1, 1].
double latticeValue(std::uint64_t seed, std::int64_t i, std::int64_t j) {
  std::uint64_t h = seed * 0x9E3779B97F4A7C15ull ^ (std::uint64_t(i) * 0xBF58476D1CE4E5B9ull) ^
                    (std::uint64_t(j) * 0x94D049BB133111EBull);
  h ^= h >> 31;
  h *= 0xD6E8FEB86659FD93ull;
  h ^= h >> 32;
  return double(h >> 11) * 0x1.0p-52 - 1.0;
}

/// Smooth value noise in [-1, 1] on a lattice of spacing `wavelength` (value_noise.h).
double valueNoise(std::uint64_t seed, double x, double y, double wavelength) {
  return terrain::valueNoise([seed](std::int64_t i, std::int64_t j) { return latticeValue(seed, i, j); }, x, y,
                             wavelength);
}

/// Signed horizontal distance to a rounded rectangle (negative inside), exact.
double roundedBoxDistance(double u, double v, double halfLength, double halfWidth, double radius) {
  const double qx = std::abs(u) - (halfLength - radius), qy = std::abs(v) - (halfWidth - radius);
  const double ox = std::max(qx, 0.0), oy = std::max(qy, 0.0);
  return std::hypot(ox, oy) + std::min(std::max(qx, qy), 0.0) - radius;
}

struct Pit {
  double e, n, radius, depth;
};

}  // namespace

const char* dumpSurfaceName(DumpSurface surface) {
  switch (surface) {
    case DumpSurface::Ground: return "ground";
    case DumpSurface::Ditch: return "ditch";
    case DumpSurface::Pit: return "pit";
    case DumpSurface::Face: return "face";
    case DumpSurface::Berm: return "berm";
    case DumpSurface::Top: return "top";
    case DumpSurface::Ramp: return "ramp";
    case DumpSurface::RampSide: return "ramp side";
  }
  return "unknown";
}

MiningDump generateMiningDump(const MiningDumpParams& p) {
  if (!(p.size > 0 && p.cell > 0 && std::isfinite(p.size) && std::isfinite(p.cell)))
    throw std::invalid_argument("make-terrain: size and cell must be positive");
  const int n = int(std::lround(p.size / p.cell));
  if (n < 16) throw std::invalid_argument("make-terrain: the area needs at least 16 cells a side");
  if (double(n) * double(n) > 4.0e8) throw std::invalid_argument("make-terrain: more than 4e8 samples");

  std::mt19937_64 rng(p.seed);
  MiningDump out;
  out.cols = out.rows = n;
  out.cell = p.cell;
  const double side = n * p.cell;
  out.originX = p.centreE - 0.5 * side + 0.5 * p.cell;
  out.originY = p.centreN + 0.5 * side - 0.5 * p.cell;

  // Natural ground: a gentle plane and slow undulations around baseLevel.
  const double baseLevel = uniform(rng, 40.0, 80.0);
  const double planeAz = uniform(rng, 0.0, 2.0 * std::numbers::pi), planeGrade = uniform(rng, 0.002, 0.008);
  const std::uint64_t groundSeed = rng(), roughSeed = rng();
  auto ground = [&](double e, double nn) {
    const double de = e - p.centreE, dn = nn - p.centreN;
    return baseLevel + planeGrade * (de * std::sin(planeAz) + dn * std::cos(planeAz)) +
           1.5 * valueNoise(groundSeed, de, dn, 0.3 * side);
  };

  // The dump.
  MiningDumpLayout& L = out.layout;
  L.azimuthDeg = uniform(rng, 0.0, 180.0);
  L.centreE = p.centreE + uniform(rng, -0.04, 0.04) * side;
  L.centreN = p.centreN + uniform(rng, -0.04, 0.04) * side;
  L.halfLength = side * uniform(rng, 0.26, 0.30);
  L.halfWidth = side * uniform(rng, 0.16, 0.18);
  const double faceRun = p.benchHeight / std::tan(radians(p.faceSlopeDeg));
  const double period = faceRun + p.bermWidth;
  const int benches = std::max(1, std::min(p.benches, int((L.halfWidth - 0.25 * L.halfWidth) / period)));
  const double radius = std::min(0.3 * L.halfWidth, 60.0);
  L.baseHeight = ground(L.centreE, L.centreN);
  L.topHeight = L.baseHeight + benches * p.benchHeight;
  const double az = radians(L.azimuthDeg);
  const double ae = std::sin(az), an = std::cos(az);  // long axis (u)
  const double be = std::cos(az), bn = -std::sin(az);  // across (v), azimuth az + 90
  auto profile = [&](double s) {                       // height above the toe, s metres inside it
    const int k = int(std::floor(s / period));
    if (k >= benches) return benches * p.benchHeight;
    return k * p.benchHeight + p.benchHeight * std::min((s - k * period) / faceRun, 1.0);
  };

  // The haul ramp: along u on the v < 0 side (azimuth az + 270), from the ground beyond the end to the top.
  const double topHalfWidth = L.halfWidth - (benches - 1) * period - faceRun;
  const double topHalfLength = L.halfLength - (benches - 1) * period - faceRun;
  const double rampV = -0.6 * std::max(topHalfWidth, 5.0), rampHalfWidth = 10.0;
  const double rampStart = -L.halfLength - 40.0, rampEnd = 0.3 * std::max(topHalfLength, 0.0);
  const double rampGrade = (L.topHeight - L.baseHeight) / (rampEnd - rampStart);
  const double sideTan = std::tan(radians(p.faceSlopeDeg));

  // Pits in the natural ground, clear of the dump, the ditch and the ramp's foot.
  std::vector<Pit> pits;
  const int pitCount = 2 + int(uniform(rng) * 3.0);
  for (int tries = 0; tries < 200 && int(pits.size()) < pitCount; ++tries) {
    Pit pit{p.centreE + uniform(rng, -0.45, 0.45) * side, p.centreN + uniform(rng, -0.45, 0.45) * side,
            uniform(rng, 12.0, 25.0), uniform(rng, 3.0, 6.0)};
    const double de = pit.e - L.centreE, dn = pit.n - L.centreN;
    const double u = de * ae + dn * an, v = de * be + dn * bn;
    if (roundedBoxDistance(u, v, L.halfLength, L.halfWidth, radius) < pit.radius + 25.0) continue;
    if (std::hypot(u - rampStart, v - rampV) < pit.radius + 40.0) continue;
    if (std::abs(pit.e - p.centreE) > 0.5 * side - pit.radius || std::abs(pit.n - p.centreN) > 0.5 * side - pit.radius)
      continue;
    bool clear = true;
    for (const Pit& q : pits) clear = clear && std::hypot(q.e - pit.e, q.n - pit.n) > q.radius + pit.radius + 10.0;
    if (clear) pits.push_back(pit);
  }

  // The surface a point of the bench profile lies on, s metres inside the toe.
  auto profileSurface = [&](double s) {
    const int k = int(std::floor(s / period));
    if (k >= benches) return DumpSurface::Top;
    if (s - k * period < faceRun) return DumpSurface::Face;
    return k + 1 < benches ? DumpSurface::Berm : DumpSurface::Top;  // beyond the last crest: the top
  };

  out.heights.resize(std::size_t(n) * std::size_t(n));
  out.surfaces.resize(std::size_t(n) * std::size_t(n));
  for (int r = 0; r < n; ++r) {
    const double nn = out.originY - r * p.cell;
    for (int c = 0; c < n; ++c) {
      const double e = out.originX + c * p.cell;
      const double de = e - L.centreE, dn = nn - L.centreN;
      const double u = de * ae + dn * an, v = de * be + dn * bn;
      const double sd = roundedBoxDistance(u, v, L.halfLength, L.halfWidth, radius);
      double h = ground(e, nn);
      DumpSurface surface = DumpSurface::Ground;
      if (sd < 0 && L.baseHeight + profile(-sd) > h) {
        h = L.baseHeight + profile(-sd);
        surface = profileSurface(-sd);
      }
      // Drainage ditch: 1.5 m deep V, 4 m wide, 8 m outside the toe.
      const double ditchDepth = 1.5 * std::max(0.0, 1.0 - std::abs(sd - 8.0) / 2.0);
      if (ditchDepth > 0) {
        h -= ditchDepth;
        surface = DumpSurface::Ditch;
      }
      // Haul ramp, cut or filled with side slopes.
      const double rampZ = L.baseHeight + rampGrade * std::clamp(u - rampStart, 0.0, rampEnd - rampStart);
      const double off = std::max({std::abs(v - rampV) - rampHalfWidth, rampStart - u, u - rampEnd, 0.0});
      const double onRamp = std::clamp(h, rampZ - off * sideTan, rampZ + off * sideTan);
      if (off == 0) surface = DumpSurface::Ramp;
      else if (onRamp != h) surface = DumpSurface::RampSide;
      h = onRamp;
      for (const Pit& pit : pits) {
        const double d = std::hypot(e - pit.e, nn - pit.n);
        if (d < pit.radius) {
          h -= std::min(pit.depth, (pit.radius - d) * sideTan);
          surface = DumpSurface::Pit;
        }
      }
      h += 0.05 * valueNoise(roughSeed, de, dn, 4.0);
      out.heights[std::size_t(r) * std::size_t(n) + std::size_t(c)] = float(h);
      out.surfaces[std::size_t(r) * std::size_t(n) + std::size_t(c)] = surface;
    }
  }
  return out;
}

}  // namespace nestwalk::terrain
