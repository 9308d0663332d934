#include "nestwalk/terrain/footprint_ground.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

namespace nestwalk::terrain {
namespace {

/// The polygon in grid units: u east from sample column 0, v south from sample row 0.
struct Grid {
  const Heightfield& hf;
  Eigen::Vector2d toGrid(const Eigen::Vector2d& map) const {
    return {(map.x() - hf.origin().x()) / hf.dx(), (hf.origin().y() - map.y()) / hf.dy()};
  }
  Eigen::Vector2d toMap(const Eigen::Vector2d& g) const {
    return {hf.origin().x() + g.x() * hf.dx(), hf.origin().y() - g.y() * hf.dy()};
  }
};

void add(GroundSpan& span, std::optional<double> z) {
  if (!z) {
    ++span.missing;
    return;
  }
  if (span.points == 0) span.lowest = span.highest = *z;
  span.lowest = std::min(span.lowest, *z);
  span.highest = std::max(span.highest, *z);
  ++span.points;
}

/// Whether grid point p lies in the convex polygon (closed; either orientation).
bool inside(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
  if (poly.size() < 3) return false;
  int sign = 0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Eigen::Vector2d a = poly[i], b = poly[(i + 1) % poly.size()];
    const double cross = (b.x() - a.x()) * (p.y() - a.y()) - (b.y() - a.y()) * (p.x() - a.x());
    if (cross == 0.0) continue;
    const int s = cross > 0 ? 1 : -1;
    if (sign == 0) sign = s;
    else if (s != sign) return false;
  }
  return true;
}

}  // namespace

GroundSpan groundUnderPolygon(const Heightfield& hf, std::span<const Eigen::Vector2d> polygon) {
  GroundSpan span;
  const Grid grid{hf};
  auto at = [&](const Eigen::Vector2d& g) {
    const Eigen::Vector2d m = grid.toMap(g);
    add(span, hf.groundHeight(m.x(), m.y()));
  };
  std::vector<Eigen::Vector2d> poly;
  for (const Eigen::Vector2d& p : polygon) {
    poly.push_back(grid.toGrid(p));
    add(span, hf.groundHeight(p.x(), p.y()));  // the vertices themselves, at their exact map position
  }
  if (poly.empty()) return span;

  // Samples inside.
  Eigen::Vector2d lo = poly[0], hi = poly[0];
  for (const Eigen::Vector2d& p : poly) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  for (double v = std::ceil(lo.y()); v <= hi.y(); v += 1.0)
    for (double u = std::ceil(lo.x()); u <= hi.x(); u += 1.0)
      if (inside(poly, {u, v})) at({u, v});

  // Edge crossings with the columns (u = i), rows (v = j) and cell diagonals (u - v = k).
  for (std::size_t e = 0; e < poly.size() && poly.size() > 1; ++e) {
    const Eigen::Vector2d a = poly[e], b = poly[(e + 1) % poly.size()];
    auto crossings = [&](double fa, double fb) {  // points where the linear f goes through an integer
      if (fa == fb) return;
      for (double k = std::ceil(std::min(fa, fb)); k <= std::max(fa, fb); k += 1.0) at(a + (b - a) * ((k - fa) / (fb - fa)));
    };
    crossings(a.x(), b.x());
    crossings(a.y(), b.y());
    crossings(a.x() - a.y(), b.x() - b.y());
  }
  return span;
}

}  // namespace nestwalk::terrain
