// A translating box against a triangle at rest: 13 slabs clipped in time (triangle_sweep.h).
#include "nestwalk/geometry/triangle_sweep.h"

#include "nestwalk/geometry/slab_clip.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>

namespace nestwalk {
namespace {

/// The slack per unit of |L|_1 on every slab, relative to the magnitudes in play: the frame map's
/// rounding (relative to the corners' distance from the centre) and the slabs' own.
constexpr double kRelativeSlack = kRoundingSlack<double> + 3 * kFrameRounding;

}  // namespace

double sweepBoxTriangleSlack(const Obb<double>& box, const Vec3<double>& d, double reach) {
  // A corner v = A^T (p - c) has |v|_1 <= sqrt(3) |v|_2 <= sqrt(3) sqrt(3) (reach + |c|_inf); the
  // slab's slack over |L|_2 is at most sqrt(3) times its slack per |L|_1. A 2x margin on top.
  const double corners = 3 * 3.0 * (reach + box.center.cwiseAbs().maxCoeff());
  const double magnitude = corners + std::sqrt(3.0) * d.norm() + box.halfExtents.sum();
  return 2 * std::sqrt(3.0) * kRelativeSlack * magnitude;
}

SweepResult sweepBoxTriangle(const Obb<double>& box, const Vec3<double>& d, const Triangle& triangle,
                             double windowStart, double windowEnd) {
  using V3 = Vec3<double>;
  // The box's frame: the box is [-h, h], the triangle's corners v, the motion dv.
  const Mat3<double> At = box.axes.transpose();
  const std::array<V3, 3> v = {At * (triangle[0] - box.center), At * (triangle[1] - box.center),
                               At * (triangle[2] - box.center)};
  const V3 dv = At * d;
  const V3& h = box.halfExtents;
  const std::array<V3, 3> edge = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  const double magnitude = v[0].cwiseAbs().sum() + v[1].cwiseAbs().sum() + v[2].cwiseAbs().sum() +
                           dv.cwiseAbs().sum() + h.sum();
  const double slack = kRelativeSlack * magnitude;

  SlabClip clip;
  clip.windowStart = windowStart;
  clip.windowEnd = windowEnd;
  std::array<V3, 13> axes;
  int count = 0;
  for (int i = 0; i < 3; ++i) axes[count++] = V3::Unit(i);
  axes[count++] = edge[0].cross(edge[1]);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) axes[count++] = V3::Unit(i).cross(edge[j]);

  bool alive = true;
  for (int k = 0; k < count && alive; ++k) {
    const V3& L = axes[k];
    const double p0 = L.dot(v[0]), p1 = L.dot(v[1]), p2 = L.dot(v[2]);
    const double lo = std::min({p0, p1, p2}), hi = std::max({p0, p1, p2});
    const double radius = h[0] * std::abs(L[0]) + h[1] * std::abs(L[1]) + h[2] * std::abs(L[2]);
    // |L| scales the slack with the axis (the cross products are not unit).
    const double axisSlack = slack * L.cwiseAbs().sum();
    alive = clip.clip(0.5 * (lo + hi), L.dot(dv), radius + 0.5 * (hi - lo) + axisSlack, std::int8_t(k), k);
  }
  SweepResult out;
  out.enter = clip.enter;
  out.exit = clip.exit;
  out.axis = alive ? clip.enterAxis : clip.decidingAxis;
  if (alive && clip.enterSlot >= 0) {
    const double n = axes[clip.enterSlot].norm();
    if (n > 0) out.normal = box.axes * ((clip.enterSign / n) * axes[clip.enterSlot]);
  }
  return out;
}

}  // namespace nestwalk
