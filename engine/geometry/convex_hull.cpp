// Convex hull through qhull (reentrant C interface, libqhull_r), with the dimension of the input
// detected first so that qhull only ever sees full-dimensional input. (Not libqhullcpp: Debian
// 12's qhull 8.0.2 C++ headers do not compile as C++20 -- `QhullSet<T>(...)` constructors.)
//
// Dimension detection (the same idea as qhull's own initial simplex, but with our tolerance):
//   p0 = the point farthest from the centroid, p1 = the point farthest from p0; L = |p1 - p0| is
//   between half and all of the set's diameter. p2 = the point farthest from the line p0 p1, p3 =
//   the point farthest from the plane p0 p1 p2. The set is collinear when dist(p2, line) <=
//   kFlatnessTolerance * L, coplanar when dist(p3, plane) <= kFlatnessTolerance * L.
// All the work is done on points minus their centroid, so models at map coordinates (UTM,
// 1e6..1e7 m) lose no digits in the differences.
#include "nestwalk/geometry/convex_hull.h"

#include <Eigen/Geometry>
#include <libqhull_r/qhull_ra.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace nestwalk {

namespace {

// Thickness below which a point set counts as flat (coplanar) or thin (collinear), relative to
// its extent L (unitless: metres per metre of extent). 1e-9 is ~1e7 double ulps, far above the
// rounding of centred coordinates even at UTM magnitudes (|x| ~ 5e6 m gives ~1e-9 m absolute
// noise, i.e. 1e-9 of a 1 m model, 1e-11 of a 100 m one), and far below any real model's
// thickness (a 1e-9 m sheet on a 1 m part). Qhull's own precision tolerance (~1e-15 relative) is
// far below it, so qhull never sees input it would call flat.
constexpr double kFlatnessTolerance = 1e-9;

// A 2D hull vertex closer than this to the chord of its neighbours is dropped as collinear,
// relative to the 2D points' extent (unitless). Rounding of projected coordinates is ~1e-16 of the
// extent; 1e-12 drops points that are on an edge up to rounding and nothing a model could show.
constexpr double kCollinear2d = 1e-12;

// Spread at or below which all points count as one point: a few ulps of the largest coordinate
// magnitude (unitless multiple of |coordinate|), i.e. differences at the level of rounding.
constexpr double kCoincidenceUlps = 4.0 * std::numeric_limits<double>::epsilon();

using V3 = Vec3<double>;

std::size_t farthestFrom(const std::vector<V3>& p, const V3& q) {
  std::size_t best = 0;
  double bestD = -1.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double d = (p[i] - q).squaredNorm();
    if (d > bestD) {
      bestD = d;
      best = i;
    }
  }
  return best;
}

}  // namespace

std::vector<int> convexHull2d(const std::vector<Eigen::Vector2d>& q) {
  const int n = static_cast<int>(q.size());
  if (n == 0) return {};
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return q[a].x() < q[b].x() ||
           (q[a].x() == q[b].x() && (q[a].y() < q[b].y() || (q[a].y() == q[b].y() && a < b)));
  });
  Eigen::Vector2d lo = q[0], hi = q[0];
  for (const auto& p : q) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double tolDist = kCollinear2d * (hi - lo).norm();
  // Drop the middle point a of (o, a, b) unless it is strictly left of o -> b by more than tolDist.
  auto drop = [&](int o, int a, int b) {
    const Eigen::Vector2d oa = q[a] - q[o], ob = q[b] - q[o];
    return oa.x() * ob.y() - oa.y() * ob.x() <= tolDist * ob.norm();
  };
  std::vector<int> h(2 * n);
  int k = 0;
  for (int i = 0; i < n; ++i) {
    while (k >= 2 && drop(h[k - 2], h[k - 1], order[i])) --k;
    h[k++] = order[i];
  }
  for (int i = n - 2, t = k + 1; i >= 0; --i) {
    while (k >= t && drop(h[k - 2], h[k - 1], order[i])) --k;
    h[k++] = order[i];
  }
  h.resize(std::max(1, k - 1));
  if (h.size() == 2 && q[h[0]] == q[h[1]]) h.resize(1);
  return h;
}

namespace {

ConvexHull segmentHull(const std::vector<V3>& points, const std::vector<V3>& c) {
  // The two extreme points along the direction of the longest spread.
  const std::size_t i0 = farthestFrom(c, V3::Zero());
  const std::size_t i1 = farthestFrom(c, c[i0]);
  const V3 d = (c[i1] - c[i0]).normalized();
  std::size_t lo = 0, hi = 0;
  double tlo = std::numeric_limits<double>::infinity(), thi = -tlo;
  for (std::size_t i = 0; i < c.size(); ++i) {
    const double t = d.dot(c[i]);
    if (t < tlo) {
      tlo = t;
      lo = i;
    }
    if (t > thi) {
      thi = t;
      hi = i;
    }
  }
  ConvexHull h;
  h.dimension = 1;
  h.vertices = {points[lo], points[hi]};
  return h;
}

ConvexHull planarHull(const std::vector<V3>& points, const std::vector<V3>& c, const V3& e1In,
                      const V3& e2In) {
  // Orthonormal basis of the plane, then the 2D hull of the projections.
  const V3 e1 = e1In.normalized();
  const V3 e2 = (e2In - e1.dot(e2In) * e1).normalized();
  std::vector<Eigen::Vector2d> q(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) q[i] = {e1.dot(c[i]), e2.dot(c[i])};
  const std::vector<int> ring = convexHull2d(q);
  ConvexHull h;
  if (ring.size() < 3) return segmentHull(points, c);  // cannot happen past the flatness test
  h.dimension = 2;
  for (int i : ring) h.vertices.push_back(points[i]);
  const int m = static_cast<int>(ring.size());
  // Fan from vertex 0, both sides (counter-clockwise about e1 x e2, then clockwise).
  for (int i = 1; i + 1 < m; ++i) h.triangles.push_back({0, i, i + 1});
  for (int i = 1; i + 1 < m; ++i) h.triangles.push_back({0, i + 1, i});
  return h;
}

// qhull (reentrant C API, libqhull_r) on the centred points, triangulated ("Qt"). Returns
// false, with `h` untouched, when qhull reports an error (its messages go to /dev/null).
bool solidHull(const std::vector<V3>& points, const std::vector<V3>& c, ConvexHull& h) {
  std::vector<coordT> coords(3 * c.size());
  for (std::size_t i = 0; i < c.size(); ++i) {
    coords[3 * i] = c[i].x();
    coords[3 * i + 1] = c[i].y();
    coords[3 * i + 2] = c[i].z();
  }
  qhT qhData;
  qhT* qh = &qhData;
  std::FILE* sink = std::fopen("/dev/null", "w");
  qh_zero(qh, sink);
  char command[] = "qhull Qt";
  const int exitcode =
      qh_new_qhull(qh, 3, static_cast<int>(c.size()), coords.data(), False, command, nullptr, sink);
  bool ok = exitcode == 0;
  if (ok) {
    ConvexHull out;
    out.dimension = 3;
    std::vector<int> index(c.size(), -1);  // input point id -> hull vertex index
    auto vertexIndex = [&](int pointId) {
      if (index[pointId] < 0) {
        index[pointId] = static_cast<int>(out.vertices.size());
        out.vertices.push_back(points[pointId]);
      }
      return index[pointId];
    };
    facetT* facet;
    vertexT *vertex, **vertexp;
    FORALLfacets {
      std::array<int, 3> ids{};
      int k = 0;
      FOREACHvertex_(facet->vertices) {
        if (k < 3) ids[k] = qh_pointid(qh, vertex->point);
        ++k;
      }
      if (k != 3) {  // "Qt" gives triangles only
        ok = false;
        break;
      }
      // Orient outward: compare the triangle's normal with qhull's facet normal.
      const V3 normal(facet->normal[0], facet->normal[1], facet->normal[2]);
      const V3 tn = (c[ids[1]] - c[ids[0]]).cross(c[ids[2]] - c[ids[0]]);
      if (tn.dot(normal) < 0.0) std::swap(ids[1], ids[2]);
      out.triangles.push_back({vertexIndex(ids[0]), vertexIndex(ids[1]), vertexIndex(ids[2])});
    }
    if (ok) h = std::move(out);
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  if (sink) std::fclose(sink);
  return ok;
}

}  // namespace

ConvexHull convexHull(const std::vector<Vec3<double>>& points) {
  ConvexHull h;
  if (points.empty()) return h;

  // Centre on the centroid (at map coordinates the differences keep their digits).
  V3 centroid = V3::Zero();
  double maxAbs = 0.0;
  for (const V3& p : points) {
    centroid += p;
    maxAbs = std::max(maxAbs, p.cwiseAbs().maxCoeff());
  }
  centroid /= static_cast<double>(points.size());
  std::vector<V3> c(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) c[i] = points[i] - centroid;

  const std::size_t i0 = farthestFrom(c, V3::Zero());
  const std::size_t i1 = farthestFrom(c, c[i0]);
  const V3 d01 = c[i1] - c[i0];
  const double L = d01.norm();
  if (!(L > kCoincidenceUlps * maxAbs) || !std::isfinite(L)) {
    h.dimension = 0;
    h.vertices = {points[i0]};
    return h;
  }
  const V3 u = d01 / L;
  // Farthest from the line p0 p1.
  std::size_t i2 = i0;
  double d2 = -1.0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    const V3 r = c[i] - c[i0];
    const double d = (r - u.dot(r) * u).squaredNorm();
    if (d > d2) {
      d2 = d;
      i2 = i;
    }
  }
  if (std::sqrt(d2) <= kFlatnessTolerance * L) return segmentHull(points, c);
  const V3 nrm = u.cross(c[i2] - c[i0]).normalized();
  double d3 = 0.0;
  for (const V3& p : c) d3 = std::max(d3, std::abs(nrm.dot(p - c[i0])));
  if (d3 <= kFlatnessTolerance * L) return planarHull(points, c, u, c[i2] - c[i0]);

  if (solidHull(points, c, h)) return h;
  // Past the flatness test qhull should not fail; if its own precision checks still object, fall
  // back to the planar hull in the plane found above.
  return planarHull(points, c, u, c[i2] - c[i0]);
}

}  // namespace nestwalk
