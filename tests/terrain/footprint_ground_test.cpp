// The ground under a footprint (terrain/footprint_ground.h) against brute force: on a rough
// random terrain, the heights at a dense grid of points inside each polygon (every one through
// Heightfield::groundHeight) never go below the computed lowest nor above the highest, and come
// within the surface's slope times the grid spacing of both; on a plane the extremes are the
// plane's own at the polygon's corners. At the origin and at UTM magnitudes; holes are counted.
#include "nestwalk/terrain/footprint_ground.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace nestwalk::terrain {
namespace {

Heightfield roughTerrain(double originX, double originY, unsigned seed, bool holes = false) {
  const int n = 40;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  std::vector<float> h(std::size_t(n) * n);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) h[std::size_t(r) * n + std::size_t(c)] = 100.0f + 0.3f * float(c) + u(rng);
  if (holes) h[std::size_t(20) * n + 20] = -9999.0f;
  return Heightfield(n, n, std::move(h), originX, originY, 0.5, 0.5, holes ? std::optional<float>(-9999.0f) : std::nullopt);
}

/// A rectangle w x l turned by `yawDeg` about (cx, cy), as the map outline of a placed box.
std::vector<Eigen::Vector2d> turnedRectangle(double cx, double cy, double w, double l, double yawDeg) {
  const double a = yawDeg * std::numbers::pi / 180.0, c = std::cos(a), s = std::sin(a);
  std::vector<Eigen::Vector2d> out;
  for (const auto& [x, y] : {std::pair{-w / 2, -l / 2}, {w / 2, -l / 2}, {w / 2, l / 2}, {-w / 2, l / 2}})
    out.push_back({cx + c * x - s * y, cy + s * x + c * y});
  return out;
}

bool insideConvex(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Eigen::Vector2d a = poly[i], b = poly[(i + 1) % poly.size()];
    if ((b.x() - a.x()) * (p.y() - a.y()) - (b.y() - a.y()) * (p.x() - a.x()) < 0) return false;
  }
  return true;
}

class FootprintGround : public ::testing::TestWithParam<Eigen::Vector2d> {};

TEST_P(FootprintGround, ExtremesAgainstDenseSampling) {
  const Heightfield hf = roughTerrain(GetParam().x(), GetParam().y(), 7);
  const double step = 0.01;               // metres between brute-force points
  const double maxSlope = 2 * 4.0 / 0.5 + 0.6;  // steepest possible triangle: 8 m per 0.5 m cell, plus the trend
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> pos(3.0, 16.0), size(0.2, 3.0), yaw(0.0, 360.0);
  for (int k = 0; k < 40; ++k) {
    const double cx = GetParam().x() + pos(rng), cy = GetParam().y() - pos(rng);
    const auto poly = turnedRectangle(cx, cy, size(rng), size(rng), yaw(rng));
    const GroundSpan span = groundUnderPolygon(hf, poly);
    ASSERT_TRUE(span.complete()) << k;
    double lo = INFINITY, hi = -INFINITY;
    Eigen::Vector2d bmin = poly[0], bmax = poly[0];
    for (const auto& p : poly) {
      bmin = bmin.cwiseMin(p);
      bmax = bmax.cwiseMax(p);
    }
    for (double x = bmin.x(); x <= bmax.x(); x += step)
      for (double y = bmin.y(); y <= bmax.y(); y += step)
        if (insideConvex(poly, {x, y})) {
          const double z = *hf.groundHeight(x, y);
          lo = std::min(lo, z);
          hi = std::max(hi, z);
        }
    // Exact extremes: no dense point beyond them (to rounding), and dense points close to them.
    EXPECT_GE(lo, span.lowest - 1e-9) << k;
    EXPECT_LE(hi, span.highest + 1e-9) << k;
    EXPECT_LE(lo - span.lowest, maxSlope * step * std::sqrt(2.0)) << k;
    EXPECT_LE(span.highest - hi, maxSlope * step * std::sqrt(2.0)) << k;
  }
}

TEST_P(FootprintGround, PlaneExtremesAtTheCorners) {
  // z = 50 + 0.5 u - 0.25 v in grid units (u east, v south), exact in float.
  const int n = 30;
  std::vector<float> h;
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) h.push_back(50.0f + 0.5f * float(c) - 0.25f * float(r));
  const Heightfield hf(n, n, std::move(h), GetParam().x(), GetParam().y(), 1.0, 1.0);
  auto plane = [&](const Eigen::Vector2d& p) {
    return 50.0 + 0.5 * (p.x() - GetParam().x()) - 0.25 * (GetParam().y() - p.y());
  };
  const auto poly = turnedRectangle(GetParam().x() + 12.3, GetParam().y() - 14.6, 3.0, 7.0, 33.0);
  const GroundSpan span = groundUnderPolygon(hf, poly);
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& p : poly) {
    lo = std::min(lo, plane(p));
    hi = std::max(hi, plane(p));
  }
  EXPECT_NEAR(span.lowest, lo, 1e-9);
  EXPECT_NEAR(span.highest, hi, 1e-9);
  EXPECT_NEAR(span.rise(), hi - lo, 1e-9);
  // A point and a segment.
  const std::vector<Eigen::Vector2d> point{poly[0]};
  EXPECT_NEAR(groundUnderPolygon(hf, point).lowest, plane(poly[0]), 1e-9);
  const std::vector<Eigen::Vector2d> segment{poly[0], poly[2]};
  const GroundSpan s = groundUnderPolygon(hf, segment);
  EXPECT_NEAR(s.lowest, std::min(plane(poly[0]), plane(poly[2])), 1e-9);
}

TEST_P(FootprintGround, HolesAndTheEdgeAreMissingGround) {
  const Heightfield hf = roughTerrain(GetParam().x(), GetParam().y(), 9, true);
  // Around the hole at sample (20, 20): 10 m, 10 m from the corner.
  const auto overHole = turnedRectangle(GetParam().x() + 10.0, GetParam().y() - 10.0, 1.5, 1.5, 20.0);
  EXPECT_GT(groundUnderPolygon(hf, overHole).missing, 0u);
  EXPECT_GT(groundUnderPolygon(hf, overHole).points, 0u);
  const auto offEdge = turnedRectangle(GetParam().x() - 0.2, GetParam().y() - 5.0, 1.0, 1.0, 0.0);
  const GroundSpan e = groundUnderPolygon(hf, offEdge);
  EXPECT_FALSE(e.complete());
  EXPECT_GT(e.points, 0u);
  const auto away = turnedRectangle(GetParam().x() - 50.0, GetParam().y() + 50.0, 1.0, 1.0, 0.0);
  EXPECT_EQ(groundUnderPolygon(hf, away).points, 0u);
}

INSTANTIATE_TEST_SUITE_P(Places, FootprintGround,
                         ::testing::Values(Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(550123.25, 4650987.75)),
                         [](const auto& info) { return info.param.x() == 0.0 ? std::string("origin") : std::string("utm"); });

}  // namespace
}  // namespace nestwalk::terrain
