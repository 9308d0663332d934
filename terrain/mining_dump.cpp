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

/// Metres: half the haul ramp's running width (20 m: two lanes of a haul truck's width).
constexpr double kRampHalfWidthM = 10.0;

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

MiningDumpGenerator::MiningDumpGenerator(const MiningDumpParams& p) : p_(p) {
  if (!(p.size > 0 && p.cell > 0 && std::isfinite(p.size) && std::isfinite(p.cell)))
    throw std::invalid_argument("make-terrain: size and cell must be positive");
  const double cells = std::round(p.size / p.cell);
  if (cells < 16) throw std::invalid_argument("make-terrain: the area needs at least 16 cells a side");
  if (cells > double(kMaxMiningDumpCellsPerSide))
    throw std::invalid_argument("make-terrain: more than " + std::to_string(kMaxMiningDumpCellsPerSide) + " cells a side");
  const int n = int(cells);
  std::mt19937_64 rng(p.seed);
  n_ = n;
  const double side = n * p.cell;
  side_ = side;
  originX_ = p.centreE - 0.5 * side + 0.5 * p.cell;
  originY_ = p.centreN + 0.5 * side - 0.5 * p.cell;

  // Natural ground: a gentle plane and slow undulations around baseLevel.
  baseLevel_ = uniform(rng, 40.0, 80.0);
  planeAz_ = uniform(rng, 0.0, 2.0 * std::numbers::pi);
  planeGrade_ = uniform(rng, 0.002, 0.008);
  groundSeed_ = rng();
  roughSeed_ = rng();

  // The dump.
  MiningDumpLayout& L = layout_;
  L.azimuthDeg = uniform(rng, 0.0, 180.0);
  L.centreE = p.centreE + uniform(rng, -0.04, 0.04) * side;
  L.centreN = p.centreN + uniform(rng, -0.04, 0.04) * side;
  L.halfLength = side * uniform(rng, 0.26, 0.30);
  L.halfWidth = side * uniform(rng, 0.16, 0.18);
  faceRun_ = p.benchHeight / std::tan(radians(p.faceSlopeDeg));
  period_ = faceRun_ + p.bermWidth;
  benches_ = std::max(1, std::min(p.benches, int((L.halfWidth - 0.25 * L.halfWidth) / period_)));
  radius_ = std::min(0.3 * L.halfWidth, 60.0);
  L.baseHeight = ground(L.centreE, L.centreN);
  L.topHeight = L.baseHeight + benches_ * p.benchHeight;
  const double az = radians(L.azimuthDeg);
  ae_ = std::sin(az), an_ = std::cos(az);  // long axis (u)
  be_ = std::cos(az), bn_ = -std::sin(az);  // across (v), azimuth az + 90

  // The haul ramp: along u on the v < 0 side (azimuth az + 270), from the ground beyond the end to the top.
  const double topHalfWidth = L.halfWidth - (benches_ - 1) * period_ - faceRun_;
  const double topHalfLength = L.halfLength - (benches_ - 1) * period_ - faceRun_;
  rampV_ = -0.6 * std::max(topHalfWidth, 5.0);
  rampStart_ = -L.halfLength - 40.0;
  rampEnd_ = 0.3 * std::max(topHalfLength, 0.0);
  rampGrade_ = (L.topHeight - L.baseHeight) / (rampEnd_ - rampStart_);
  sideTan_ = std::tan(radians(p.faceSlopeDeg));
  L.rampV = rampV_;
  L.rampHalfWidth = kRampHalfWidthM;
  L.rampStartU = rampStart_;
  L.rampEndU = rampEnd_;

  // Pits in the natural ground, clear of the dump, the ditch and the ramp's foot.
  const int pitCount = 2 + int(uniform(rng) * 3.0);
  for (int tries = 0; tries < 200 && int(pits_.size()) < pitCount; ++tries) {
    Pit pit{p.centreE + uniform(rng, -0.45, 0.45) * side, p.centreN + uniform(rng, -0.45, 0.45) * side,
            uniform(rng, 12.0, 25.0), uniform(rng, 3.0, 6.0)};
    const double de = pit.e - L.centreE, dn = pit.n - L.centreN;
    const double u = de * ae_ + dn * an_, v = de * be_ + dn * bn_;
    if (roundedBoxDistance(u, v, L.halfLength, L.halfWidth, radius_) < pit.radius + 25.0) continue;
    if (std::hypot(u - rampStart_, v - rampV_) < pit.radius + 40.0) continue;
    if (std::abs(pit.e - p.centreE) > 0.5 * side - pit.radius || std::abs(pit.n - p.centreN) > 0.5 * side - pit.radius)
      continue;
    bool clear = true;
    for (const Pit& q : pits_) clear = clear && std::hypot(q.e - pit.e, q.n - pit.n) > q.radius + pit.radius + 10.0;
    if (clear) pits_.push_back(pit);
  }
  // Fine relief: octaves from kFineReliefLongestM down to two cells.
  if (p.fineRelief)
    for (double w = kFineReliefLongestM; w >= 2.0 * p.cell; w *= 0.5) ++fineOctaves_;
}

double MiningDumpGenerator::ground(double e, double nn) const {
  const double de = e - p_.centreE, dn = nn - p_.centreN;
  return baseLevel_ + planeGrade_ * (de * std::sin(planeAz_) + dn * std::cos(planeAz_)) +
         1.5 * valueNoise(groundSeed_, de, dn, 0.3 * side_);
}

void MiningDumpGenerator::generateRows(int r0, int count, float* heights, DumpSurface* surfaces) const {
  if (r0 < 0 || count < 0 || r0 + count > n_) throw std::out_of_range("MiningDumpGenerator::generateRows: rows outside the grid");
  const MiningDumpLayout& L = layout_;
  auto profile = [&](double s) {  // height above the toe, s metres inside it
    const int k = int(std::floor(s / period_));
    if (k >= benches_) return benches_ * p_.benchHeight;
    return k * p_.benchHeight + p_.benchHeight * std::min((s - k * period_) / faceRun_, 1.0);
  };
  // The surface a point of the bench profile lies on, s metres inside the toe.
  auto profileSurface = [&](double s) {
    const int k = int(std::floor(s / period_));
    if (k >= benches_) return DumpSurface::Top;
    if (s - k * period_ < faceRun_) return DumpSurface::Face;
    return k + 1 < benches_ ? DumpSurface::Berm : DumpSurface::Top;  // beyond the last crest: the top
  };
  for (int r = r0; r < r0 + count; ++r) {
    const double nn = originY_ - r * p_.cell;
    for (int c = 0; c < n_; ++c) {
      const double e = originX_ + c * p_.cell;
      const double de = e - L.centreE, dn = nn - L.centreN;
      const double u = de * ae_ + dn * an_, v = de * be_ + dn * bn_;
      const double sd = roundedBoxDistance(u, v, L.halfLength, L.halfWidth, radius_);
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
      const double rampZ = L.baseHeight + rampGrade_ * std::clamp(u - rampStart_, 0.0, rampEnd_ - rampStart_);
      const double off = std::max({std::abs(v - rampV_) - kRampHalfWidthM, rampStart_ - u, u - rampEnd_, 0.0});
      const double onRamp = std::clamp(h, rampZ - off * sideTan_, rampZ + off * sideTan_);
      if (off == 0) surface = DumpSurface::Ramp;
      else if (onRamp != h) surface = DumpSurface::RampSide;
      h = onRamp;
      for (const Pit& pit : pits_) {
        const double d = std::hypot(e - pit.e, nn - pit.n);
        if (d < pit.radius) {
          h -= std::min(pit.depth, (pit.radius - d) * sideTan_);
          surface = DumpSurface::Pit;
        }
      }
      h += 0.05 * valueNoise(roughSeed_, de, dn, 4.0);
      double amplitude = kFineReliefAmplitudeM, w = kFineReliefLongestM;
      for (int o = 0; o < fineOctaves_; ++o, amplitude *= 0.5, w *= 0.5)
        h += amplitude * valueNoise(roughSeed_ + 1 + std::uint64_t(o), de, dn, w);
      const std::size_t k = std::size_t(r - r0) * std::size_t(n_) + std::size_t(c);
      heights[k] = float(h);
      if (surfaces) surfaces[k] = surface;
    }
  }
}

MiningDump generateMiningDump(const MiningDumpParams& p) {
  if (std::round(p.size / p.cell) * std::round(p.size / p.cell) > kMaxHeldMiningDumpSamples)
    throw std::invalid_argument("make-terrain: more than 4e8 samples");
  const MiningDumpGenerator g(p);
  MiningDump out;
  out.cols = out.rows = g.cols();
  out.cell = p.cell;
  out.originX = g.originX();
  out.originY = g.originY();
  out.layout = g.layout();
  out.heights.resize(std::size_t(g.cols()) * std::size_t(g.rows()));
  out.surfaces.resize(out.heights.size());
  g.generateRows(0, g.rows(), out.heights.data(), out.surfaces.data());
  return out;
}

}  // namespace nestwalk::terrain
