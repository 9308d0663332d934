#include "nestwalk/walker/contact_choice.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <vector>

namespace nestwalk {
namespace {

/// A rectangle on a face of the box: centre, and half sizes along two of the box's axes.
struct Patch {
  Vec3<double> centre;
  Vec3<double> u, v;  // half extents as vectors along the face
  double bound;       // no point of the patch is further than this from the triangles
  bool operator<(const Patch& o) const { return bound < o.bound; }
};

/// The distance from a point to one triangle (a box of no extent at the point).
double pointTriangleDistance(const Vec3<double>& p, const Triangle& t) {
  return triangleBoxDistance(t, Obb<double>{p, Mat3<double>::Identity(), Vec3<double>::Zero()});
}

}  // namespace

GapVerdict obbSurfaceGap(const Obb<double>& box, const NearestTriangleQuery& nearest, double threshold) {
  GapVerdict verdict;
  std::priority_queue<Patch> patches;
  auto add = [&](const Vec3<double>& centre, const Vec3<double>& u, const Vec3<double>& v) {
    std::optional<Triangle> t;
    const double d = nearest(centre, t);
    ++verdict.probes;
    verdict.lowerBound = std::max(verdict.lowerBound, d);
    double bound = d + std::sqrt(u.squaredNorm() + v.squaredNorm());
    if (t) {
      double corners = 0;
      for (double su : {-1.0, 1.0})
        for (double sv : {-1.0, 1.0}) corners = std::max(corners, pointTriangleDistance(centre + su * u + sv * v, *t));
      bound = std::min(bound, corners);
    }
    patches.push({centre, u, v, bound});
  };
  for (int axis = 0; axis < 3; ++axis) {
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    const Vec3<double> normal = box.axes.col(axis) * box.halfExtents[axis];
    const Vec3<double> u = box.axes.col(a) * box.halfExtents[a], v = box.axes.col(b) * box.halfExtents[b];
    for (double side : {-1.0, 1.0}) add(box.center + side * normal, u, v);
  }
  while (!patches.empty()) {
    if (verdict.lowerBound > threshold) return verdict;  // not tight
    const Patch p = patches.top();
    if (p.bound <= threshold) {
      verdict.tight = true;  // no point of any face can be further
      return verdict;
    }
    const double radius = std::sqrt(p.u.squaredNorm() + p.v.squaredNorm());
    if (radius < kGapResolution || verdict.probes >= kMaxGapProbes) return verdict;  // undecided: not tight
    patches.pop();
    const Vec3<double> u = 0.5 * p.u, v = 0.5 * p.v;
    for (double su : {-1.0, 1.0})
      for (double sv : {-1.0, 1.0}) add(p.centre + su * u + sv * v, u, v);
  }
  verdict.tight = true;
  return verdict;
}

}  // namespace nestwalk
