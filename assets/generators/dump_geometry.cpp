#include "assets/generators/dump_geometry.h"

#include "nestwalk/core/angles.h"

#include <algorithm>
#include <cmath>

namespace nestwalk::assets {
namespace {
}  // namespace

DumpGeometry dumpGeometry(const terrain::MiningDumpParams& p, const terrain::MiningDumpLayout& L) {
  // The same formulas as terrain/mining_dump.cpp (kept in step by tests/assets).
  DumpGeometry g;
  g.layout = L;
  g.benchHeight = p.benchHeight;
  g.bermWidth = p.bermWidth;
  g.benches = int(std::lround((L.topHeight - L.baseHeight) / p.benchHeight));
  g.faceRun = p.benchHeight / std::tan(radians(p.faceSlopeDeg));
  g.period = g.faceRun + p.bermWidth;
  g.cornerRadius = std::min(0.3 * L.halfWidth, 60.0);
  g.rampV = L.rampV;  // the generator's own ramp (mining_dump.h)
  g.rampHalfWidth = L.rampHalfWidth;
  g.rampStart = L.rampStartU;
  g.rampEnd = L.rampEndU;
  g.rampGrade = (L.topHeight - L.baseHeight) / (g.rampEnd - g.rampStart);
  return g;
}

Eigen::Vector2d DumpGeometry::uAxis() const {
  return {std::sin(radians(layout.azimuthDeg)), std::cos(radians(layout.azimuthDeg))};
}
Eigen::Vector2d DumpGeometry::vAxis() const {
  return {std::cos(radians(layout.azimuthDeg)), -std::sin(radians(layout.azimuthDeg))};
}
Eigen::Vector2d DumpGeometry::toMap(double u, double v) const {
  return Eigen::Vector2d(layout.centreE, layout.centreN) + u * uAxis() + v * vAxis();
}
Eigen::Vector2d DumpGeometry::toDump(const Eigen::Vector2d& m) const {
  const Eigen::Vector2d d = m - Eigen::Vector2d(layout.centreE, layout.centreN);
  return {d.dot(uAxis()), d.dot(vAxis())};
}
double DumpGeometry::rampHeight(double u) const {
  return layout.baseHeight + rampGrade * std::clamp(u - rampStart, 0.0, rampEnd - rampStart);
}

}  // namespace nestwalk::assets
