// The footprint of a placed piece of the bundled scene, seen from above: the rectangle of its
// model's bounds turned to its heading. The generator keeps pieces of different groups apart with
// it, and the equipment tours check their approach corridors against it.
#pragma once

#include "assets/generators/scene_generator.h"
#include "nestwalk/core/angles.h"
#include "nestwalk/geometry/volumes.h"

#include <Eigen/Core>

#include <cmath>
#include <string>

namespace nestwalk::assets {

/// A rectangle: centre, unit axes (the model's x and y in map axes), half sizes along them.
struct Rect {
  Eigen::Vector2d c, ax, ay;
  double hx = 0, hy = 0;
  std::string group, name;

  /// Half its extent along a unit direction.
  double reach(const Eigen::Vector2d& dir) const { return hx * std::abs(ax.dot(dir)) + hy * std::abs(ay.dot(dir)); }
};

/// Whether the rectangles, each grown by `inflate` on every side, overlap (separating axes).
inline bool rectsOverlap(const Rect& a, const Rect& b, double inflate) {
  const Eigen::Vector2d d = b.c - a.c;
  for (const Eigen::Vector2d& n : {a.ax, a.ay, b.ax, b.ay}) {
    const double ra = (a.hx + inflate) * std::abs(a.ax.dot(n)) + (a.hy + inflate) * std::abs(a.ay.dot(n));
    const double rb = (b.hx + inflate) * std::abs(b.ax.dot(n)) + (b.hy + inflate) * std::abs(b.ay.dot(n));
    if (std::abs(d.dot(n)) > ra + rb) return false;
  }
  return true;
}

/// The footprint of `p`, its model's bounds being `bounds` (model frame).
inline Rect footprintRect(const Placement& p, const Aabb<double>& bounds) {
  Rect r;
  r.ay = Eigen::Vector2d(std::sin(radians(p.headingDeg)), std::cos(radians(p.headingDeg)));  // model +y
  r.ax = Eigen::Vector2d(r.ay.y(), -r.ay.x());                                           // model +x
  const Eigen::Vector3d c = bounds.center(), h = bounds.halfExtents();
  r.c = p.position + c.x() * r.ax + c.y() * r.ay;
  r.hx = h.x();
  r.hy = h.y();
  r.group = p.group;
  r.name = p.name;
  return r;
}

}  // namespace nestwalk::assets
