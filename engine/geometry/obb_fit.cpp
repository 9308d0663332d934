// Oriented bounding box fitting.
//
// Common steps (both fitters):
//  1. Shift the points by the centre of their AABB, so that models at map coordinates (UTM,
//     1e6..1e7 m) are fitted with the digits of a model at the origin; shift back at the end.
//  2. Convex hull (convex_hull.h): its dimension picks the degenerate paths.
//       dim 0: identity axes, all half extents 0.
//       dim 1: first axis along the segment, the other two a deterministic perpendicular basis
//              (built from the world axis least aligned with the segment), two half extents 0.
//       dim 2: the fitter works on the polygon (its fan triangles have area); the third axis is the
//              plane normal and its half extent is 0.
//       dim 3: the fitter works on the hull.
//  3. Finish: Gram-Schmidt, order the non-flat axes by decreasing extent, signs chosen so that the
//     largest component of axes 0 and 1 is positive, axis 2 = axis 0 x axis 1 (right-handed), and
//     extents measured by projecting ALL input points on the final axes (centre = mid of min and
//     max), so every input point is inside to rounding whatever the hull did. Flat axes (dim < 3)
//     get half extent exactly 0; the points lie within the hull's flatness tolerance of the box.
//
// Covariance (Gottschalk, Lin & Manocha 1996, section 3). Area-weighted covariance of the hull's
// triangles: with A_i, m_i the area and centroid of triangle (p, q, r), A = sum A_i and
// mu = sum A_i m_i / A,  C = sum_i A_i / (12 A) (9 m_i m_i^T + p p^T + q q^T + r r^T) - mu mu^T,
// the exact second moment of a uniform density on the triangles (computed with the points
// relative to mu, so no large terms cancel). Axes: eigenvectors of C (Eigen's
// SelfAdjointEigenSolver). Repeated eigenvalues (relative gap <= kRepeatedEigenvalue: a cube, a
// regular prism, a disc) leave the basis of the repeated eigenspace free; it is chosen
// deterministically as the tightest one: for a 2D eigenspace the minimum-area rectangle of the
// projection on it (rotating calipers); for a 3D one (isotropic: a cube, a regular polyhedron) the
// best of the world axes and the hull's face normals each completed by rotating calipers.
// Cost: hull O(n log n) + O(F) + a 3x3 eigensolve (+ one step (b) of HullSearch for a repeated
// pair, or the scan (a)+(b) of HullSearch when isotropic).
//
// HullSearch (the tighter fitter). Candidate boxes, then local refinement:
//  a. Candidate "first axes" n: every distinct hull face normal (faces with a noisy normal, area
//     below kMinFaceAreaRel * L^2, skipped; normals deduplicated on a 1e-6 grid, sign-folded),
//     the three covariance axes and the three world axes.
//  b. For each n, the box with n as an axis that has the least volume: project the hull vertices
//     on the plane perpendicular to n, take their 2D hull, and find its minimum-area enclosing
//     rectangle by rotating calipers (Freeman & Shapira 1975 / Toussaint 1983: one side of the
//     optimal rectangle is flush with a hull edge). Volume = rectangle area x extent along n.
//     This is exact for any box that has a face flush with a hull face.
//  c. The kRefineCandidates best candidates are refined by coordinate descent on the rotation:
//     (i) for each box axis in turn, keep it fixed and replace the other two by the exact
//     optimum about it (step b with that axis), until no step shrinks the volume; (ii) small
//     rotations about the 10 diagonal directions of the box frame (both signs; rotations about
//     the box axes themselves are covered exactly by (i)), angle halved from 0.1 rad down to
//     1e-6 rad, any improvement accepted and followed by (i).
//  The result is never larger than the covariance box (its axes are candidates, and (b) only
//  improves on a box with that axis). On the four shared models its volume equals that of CGAL's
//  optimal oriented bounding box to 1e-6, and on random clouds it is within 0.05% of it, often
//  below (tests/geometry_cgal/obb_fit_cgal_test.cpp prints the table).
//  Cost. Hull O(n log n). Step (b) on a solid hull does not touch every vertex: the 2D hull is
//  taken of the silhouette vertices only (those on edges between a face turned towards n and one
//  turned away, found in O(F) from the faces' orientations; ~sqrt(m) of the m hull vertices for
//  a smooth shape), and extents come from hill climbing on the vertex graph (see BoxSearch); a
//  candidate whose lower bound (extent along n x projected area of the hull, O(F)) cannot beat
//  the kept ones is dropped before that. So (a)+(b) cost O(F) each, and at most
//  kMaxFaceCandidates (1000) face normals are tried: O(min(F, 1000) x F) in all. (c) is a few
//  hundred volume evaluations (six hill climbs each) and a few dozen steps (b) per candidate.
//  Measured (Release, one core of the build machine): shared models (64..290 hull vertices)
//  2..7 ms including the hull; 1500 hull vertices ~30 ms; 3000 hull vertices (~6000 faces)
//  ~120 ms; 5000 (~10000 faces) ~100-200 ms. The covariance fitter: 1..25 ms on the same inputs.
#include "nestwalk/geometry/obb_fit.h"

#include "nestwalk/geometry/convex_hull.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <set>
#include <stdexcept>

namespace nestwalk {

namespace {

using V3 = Vec3<double>;
using M3 = Mat3<double>;
using V2 = Eigen::Vector2d;

// Eigenvalues closer than this, relative to the largest one (unitless), count as repeated: the
// eigenvectors of their space are then determined only by rounding (their error grows like
// eps / gap), so the basis is chosen by the tie-break instead. 1e-9 is ~1e7 ulps: far above the
// rounding of an exactly symmetric input, far below any real anisotropy.
constexpr double kRepeatedEigenvalue = 1e-9;

// Hull faces with area below this times L^2 (L: the hull's AABB diagonal; unitless) have normals
// dominated by rounding and are not used as candidate directions.
constexpr double kMinFaceAreaRel = 1e-12;

// Grid on which candidate face normals (unit vectors) are deduplicated: normals closer than
// ~1e-6 rad give boxes within ~1e-6 relative volume of each other, and refinement closes the gap.
constexpr double kNormalGrid = 1e6;

// Relative volume decrease a refinement step must reach to be accepted (prevents cycling on
// rounding-level changes).
constexpr double kImprovement = 1e-12;

// At most this many face normals (of the largest faces) are candidates. Hulls of real models have
// a few hundred faces and all of theirs are used; a smooth, finely tessellated hull (thousands of
// faces) has its normals spread densely over the sphere, where 1000 of them still sample every
// direction to within a few degrees and refinement (step c) does the rest.
constexpr std::size_t kMaxFaceCandidates = 1000;

// Extents within this relative difference count as equal when ordering the axes (unitless; a
// cube's extents measured along slightly rotated axes differ by rounding, ~1e-15).
constexpr double kEqualExtent = 1e-12;

// A hull face whose normal component along a candidate direction is below this fraction of its
// area vector's length (unitless) counts as edge-on to it: the sign of so small a dot product is
// rounding (~1e-16 relative), so the face's edges are kept as silhouette candidates rather than
// trusted to one side.
constexpr double kEdgeOnRelative = 1e-12;

// How many of the best candidates are refined, and the refinement's angle schedule (radians).
constexpr int kRefineCandidates = 6;
constexpr double kRefineAngleStart = 0.1;
constexpr double kRefineAngleEnd = 1e-6;

struct Extents {
  V3 lo = V3::Constant(std::numeric_limits<double>::infinity());
  V3 hi = V3::Constant(-std::numeric_limits<double>::infinity());
  double volume() const { return (hi - lo).prod(); }
};

Extents extentsIn(const M3& axes, const std::vector<V3>& pts) {
  Extents e;
  const M3 at = axes.transpose();
  for (const V3& p : pts) {
    const V3 l = at * p;
    e.lo = e.lo.cwiseMin(l);
    e.hi = e.hi.cwiseMax(l);
  }
  return e;
}

// A unit vector perpendicular to unit n: the world axis least aligned with n, made perpendicular.
V3 perpendicularTo(const V3& n) {
  int k = 0;
  n.cwiseAbs().minCoeff(&k);
  V3 e = V3::Zero();
  e[k] = 1.0;
  return (e - n.dot(e) * n).normalized();
}

// Gram-Schmidt on the columns; the third is the cross product of the first two (right-handed).
M3 rightHanded(const M3& a) {
  M3 r;
  r.col(0) = a.col(0).normalized();
  r.col(1) = (a.col(1) - r.col(0).dot(a.col(1)) * r.col(0)).normalized();
  r.col(2) = r.col(0).cross(r.col(1));
  return r;
}

// Minimum-area enclosing rectangle of the 2D points q by rotating calipers over their hull.
// Returns the unit direction of one side; *area gets the area (0 for collinear / single points).
V2 minAreaRectangle(const std::vector<V2>& q, double* area) {
  const std::vector<int> ring = convexHull2d(q);
  const int h = static_cast<int>(ring.size());
  if (h < 3) {
    *area = 0.0;
    if (h == 2) return (q[ring[1]] - q[ring[0]]).normalized();
    return V2(1.0, 0.0);
  }
  auto P = [&](int i) -> const V2& { return q[ring[((i % h) + h) % h]]; };
  // Edge 0 (the ring is counter-clockwise: the polygon lies left of each edge).
  V2 e = (P(1) - P(0)).normalized();
  V2 nl(-e.y(), e.x());
  int a = 0, b = 0, c = 0;  // max along e, min along e, max along the left normal
  for (int j = 1; j < h; ++j) {
    if (e.dot(P(j)) > e.dot(P(a))) a = j;
    if (e.dot(P(j)) < e.dot(P(b))) b = j;
    if (nl.dot(P(j)) > nl.dot(P(c))) c = j;
  }
  double best = std::numeric_limits<double>::infinity();
  V2 bestDir(1.0, 0.0);
  for (int i = 0; i < h; ++i) {
    const V2 d = P(i + 1) - P(i);
    const double len = d.norm();
    if (!(len > 0.0)) continue;
    e = d / len;
    nl = V2(-e.y(), e.x());
    // Each extreme moves counter-clockwise as the edge direction does (the support function of a
    // convex polygon along a rotating direction); advance while the next vertex is better.
    for (int s = 0; s < h && e.dot(P(a + 1)) > e.dot(P(a)); ++s) ++a;
    for (int s = 0; s < h && e.dot(P(b + 1)) < e.dot(P(b)); ++s) ++b;
    for (int s = 0; s < h && nl.dot(P(c + 1)) > nl.dot(P(c)); ++s) ++c;
    const double ar = e.dot(P(a) - P(b)) * nl.dot(P(c) - P(i));
    if (ar < best) {
      best = ar;
      bestDir = e;
    }
  }
  *area = std::max(0.0, best);
  return bestDir;
}

struct Candidate {
  M3 axes = M3::Identity();
  double volume = std::numeric_limits<double>::infinity();
};

// Answers the two questions the searches ask of a hull: "the least-volume box that has unit n as
// an axis" and "the volume of the box with these axes". On a solid hull (dimension 3) they are
// answered through its faces and edges, without touching every vertex: the vertices whose
// projection along n can be on the 2D hull are those on silhouette edges (edges between a face
// facing +n and one facing -n), and the extreme vertex along a direction is found by hill
// climbing on the vertex graph (a local maximum of a linear function on a convex polytope is
// global). Otherwise (a polygon) over the vertices.
class BoxSearch {
 public:
  BoxSearch(const ConvexHull& hull, double diag) : v_(hull.vertices) {
    solid_ = hull.dimension == 3;
    if (!solid_) return;
    const double minCross = 2.0 * kMinFaceAreaRel * diag * diag;  // |cross| = 2 * area
    const int nf = static_cast<int>(hull.triangles.size());
    faceA_.resize(nf);
    faceOk_.resize(nf);
    std::vector<std::array<int, 3>> halfEdges;  // (key low, key high, face), sorted below
    halfEdges.reserve(3 * nf);
    for (int f = 0; f < nf; ++f) {
      const auto& t = hull.triangles[f];
      faceA_[f] = (v_[t[1]] - v_[t[0]]).cross(v_[t[2]] - v_[t[0]]);
      faceOk_[f] = faceA_[f].norm() > minCross;
      for (int k = 0; k < 3; ++k) {
        const int a = t[k], b = t[(k + 1) % 3];
        halfEdges.push_back({std::min(a, b), std::max(a, b), f});
      }
    }
    std::sort(halfEdges.begin(), halfEdges.end());
    std::vector<std::vector<int>> adj(v_.size());
    for (std::size_t i = 0; i < halfEdges.size();) {
      std::size_t j = i + 1;
      while (j < halfEdges.size() && halfEdges[j][0] == halfEdges[i][0] && halfEdges[j][1] == halfEdges[i][1])
        ++j;
      Edge e{halfEdges[i][0], halfEdges[i][1], halfEdges[i][2], j - i == 2 ? halfEdges[i + 1][2] : -1};
      edges_.push_back(e);
      adj[e.a].push_back(e.b);
      adj[e.b].push_back(e.a);
      i = j;
    }
    adjStart_.push_back(0);
    for (const auto& l : adj) {
      adj_.insert(adj_.end(), l.begin(), l.end());
      adjStart_.push_back(static_cast<int>(adj_.size()));
    }
    stamp_.assign(v_.size(), 0);
    sign_.resize(nf);
    // Distinct face normals, largest faces first (good boxes early make the pruning effective).
    std::vector<int> order(nf);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](int x, int y) { return faceA_[x].squaredNorm() > faceA_[y].squaredNorm(); });
    std::set<std::array<long long, 3>> seen;
    for (int f : order) {
      if (!faceOk_[f]) continue;
      V3 n = faceA_[f].normalized();
      int k = 0;
      n.cwiseAbs().maxCoeff(&k);
      if (n[k] < 0.0) n = -n;  // n and -n give the same box
      const std::array<long long, 3> key = {std::llround(n.x() * kNormalGrid),
                                            std::llround(n.y() * kNormalGrid),
                                            std::llround(n.z() * kNormalGrid)};
      if (seen.insert(key).second) normals_.push_back(n);
      if (normals_.size() >= kMaxFaceCandidates) break;
    }
  }

  bool solid() const { return solid_; }
  const std::vector<V3>& faceNormals() const { return normals_; }

  double volume(const M3& axes) {
    if (!solid_) return extentsIn(axes, v_).volume();
    double vol = 1.0;
    for (int k = 0; k < 3; ++k) vol *= width(axes.col(k), k);
    return vol;
  }

  // The least box about unit n; returns volume = inf (axes unset) when a lower bound (height x
  // projected area) shows it cannot be below `bound`.
  Candidate bestAbout(const V3& nIn, double bound = std::numeric_limits<double>::infinity()) {
    const V3 n = nIn.normalized();
    const V3 u = perpendicularTo(n);
    const V3 w = n.cross(u);
    const std::vector<V3>* pts = &v_;
    if (solid_) {
      const double height = width(n, 2);
      // Projected area of the hull on the plane perpendicular to n: 1/4 sum |n . cross_f|.
      double proj = 0.0;
      for (std::size_t f = 0; f < faceA_.size(); ++f) {
        const double s = n.dot(faceA_[f]);
        proj += std::abs(s);
        sign_[f] = !faceOk_[f] || std::abs(s) <= kEdgeOnRelative * faceA_[f].norm() ? 0 : (s > 0.0 ? 1 : -1);
      }
      if (height * 0.25 * proj >= bound) return {};
      // Vertices of silhouette edges (sign change, or a face that is edge-on or degenerate).
      ++stampGen_;
      sil_.clear();
      for (const Edge& e : edges_) {
        const int s0 = sign_[e.f0], s1 = e.f1 < 0 ? 0 : sign_[e.f1];
        if (s0 == s1 && s0 != 0) continue;
        for (int x : {e.a, e.b}) {
          if (stamp_[x] != stampGen_) {
            stamp_[x] = stampGen_;
            sil_.push_back(v_[x]);
          }
        }
      }
      pts = &sil_;
    }
    q_.resize(pts->size());
    for (std::size_t i = 0; i < pts->size(); ++i) q_[i] = V2(u.dot((*pts)[i]), w.dot((*pts)[i]));
    double area = 0.0;
    const V2 d = minAreaRectangle(q_, &area);
    Candidate c;
    c.axes.col(0) = (d.x() * u + d.y() * w).normalized();
    c.axes.col(2) = n;
    c.axes.col(1) = n.cross(c.axes.col(0));
    c.volume = volume(c.axes);
    return c;
  }

 private:
  struct Edge {
    int a, b, f0, f1;  // f1 = -1 for an edge with one face (should not happen on a closed hull)
  };

  // Extent of the hull along unit d (hill climbing from the last extremes found for slot k).
  double width(const V3& d, int k) {
    hiStart_[k] = climb(d, hiStart_[k]);
    loStart_[k] = climb(-d, loStart_[k]);
    return d.dot(v_[hiStart_[k]] - v_[loStart_[k]]);
  }
  int climb(const V3& d, int x) const {
    double best = d.dot(v_[x]);
    for (bool moved = true; moved;) {
      moved = false;
      for (int i = adjStart_[x]; i < adjStart_[x + 1]; ++i) {
        const double val = d.dot(v_[adj_[i]]);
        if (val > best) {
          best = val;
          x = adj_[i];
          moved = true;
          break;
        }
      }
    }
    return x;
  }

  const std::vector<V3>& v_;
  bool solid_ = false;
  std::vector<V3> faceA_;
  std::vector<char> faceOk_;
  std::vector<Edge> edges_;
  std::vector<int> adjStart_, adj_;
  std::vector<V3> normals_;
  std::vector<int> stamp_;
  int stampGen_ = 0;
  std::vector<signed char> sign_;
  std::vector<V3> sil_;
  std::vector<V2> q_;
  std::array<int, 3> hiStart_ = {0, 0, 0}, loStart_ = {0, 0, 0};
};

// Area-weighted covariance of triangles (Gottschalk 1996, section 3). Returns false when the
// triangles have no area.
bool triangleCovariance(const std::vector<V3>& v, const std::vector<std::array<int, 3>>& tris, M3* cov) {
  double total = 0.0;
  V3 mu = V3::Zero();
  for (const auto& t : tris) {
    const double a = 0.5 * (v[t[1]] - v[t[0]]).cross(v[t[2]] - v[t[0]]).norm();
    total += a;
    mu += a * (v[t[0]] + v[t[1]] + v[t[2]]) / 3.0;
  }
  if (!(total > 0.0)) return false;
  mu /= total;
  M3 c = M3::Zero();
  V3 mean = V3::Zero();  // the area-weighted mean relative to mu: zero up to rounding
  for (const auto& t : tris) {
    const V3 p = v[t[0]] - mu, q = v[t[1]] - mu, r = v[t[2]] - mu;
    const double a = 0.5 * (q - p).cross(r - p).norm();
    const V3 m = (p + q + r) / 3.0;
    c += (a / 12.0) * (9.0 * m * m.transpose() + p * p.transpose() + q * q.transpose() + r * r.transpose());
    mean += a * m;
  }
  c /= total;
  mean /= total;
  *cov = c - mean * mean.transpose();
  return true;
}

// Eigenvectors of cov, in order of decreasing eigenvalue, with repeated eigenvalues resolved as
// the file comment says.
M3 covarianceAxes(const M3& cov, BoxSearch& search) {
  Eigen::SelfAdjointEigenSolver<M3> es(cov);
  // Eigen returns increasing eigenvalues; reverse to decreasing.
  const V3 lam(es.eigenvalues()[2], es.eigenvalues()[1], es.eigenvalues()[0]);
  M3 vec;
  vec.col(0) = es.eigenvectors().col(2);
  vec.col(1) = es.eigenvectors().col(1);
  vec.col(2) = es.eigenvectors().col(0);
  const double tol = kRepeatedEigenvalue * std::max(std::abs(lam[0]), std::numeric_limits<double>::min());
  const bool r01 = lam[0] - lam[1] <= tol;
  const bool r12 = lam[1] - lam[2] <= tol;
  if (r01 && r12) {
    // Isotropic: every basis is an eigenbasis; take the tightest of the world axes and the boxes
    // flush with a hull face.
    Candidate best;
    best.axes = M3::Identity();
    best.volume = search.volume(best.axes);
    std::vector<V3> dirs = {V3::UnitX(), V3::UnitY(), V3::UnitZ()};
    dirs.insert(dirs.end(), search.faceNormals().begin(), search.faceNormals().end());
    for (const V3& n : dirs) {
      const Candidate c = search.bestAbout(n, best.volume);
      if (c.volume < best.volume * (1.0 - kImprovement)) best = c;
    }
    return best.axes;
  }
  if (r01) return search.bestAbout(vec.col(2)).axes;  // repeated pair (0, 1) about axis 2
  if (r12) {
    const M3 a = search.bestAbout(vec.col(0)).axes;  // repeated pair (1, 2) about axis 0
    M3 r;
    r << a.col(2), a.col(0), a.col(1);
    return r;
  }
  return vec;
}

// Local refinement of a candidate (see the file comment, step c).
Candidate refine(Candidate c, BoxSearch& search) {
  auto axisSteps = [&](Candidate& cur) {
    for (int iter = 0; iter < 100; ++iter) {
      bool improved = false;
      for (int k = 0; k < 3; ++k) {
        const Candidate t = search.bestAbout(cur.axes.col(k), cur.volume);
        if (t.volume < cur.volume * (1.0 - kImprovement)) {
          cur = t;
          improved = true;
        }
      }
      if (!improved) break;
    }
  };
  axisSteps(c);
  static const std::array<V3, 10> kDirs = [] {
    std::array<V3, 10> d = {V3(1, 1, 0),  V3(1, -1, 0), V3(1, 0, 1),  V3(1, 0, -1), V3(0, 1, 1),
                            V3(0, 1, -1), V3(1, 1, 1),  V3(1, 1, -1), V3(1, -1, 1), V3(-1, 1, 1)};
    for (V3& x : d) x.normalize();
    return d;
  }();
  for (double angle = kRefineAngleStart; angle >= kRefineAngleEnd; angle *= 0.5) {
    for (int pass = 0; pass < 20; ++pass) {
      bool improved = false;
      for (const V3& dLocal : kDirs) {
        for (double sign : {1.0, -1.0}) {
          const M3 r = rightHanded(c.axes * Eigen::AngleAxisd(sign * angle, dLocal).toRotationMatrix());
          const double vol = search.volume(r);
          if (vol < c.volume * (1.0 - kImprovement)) {
            c.axes = r;
            c.volume = vol;
            axisSteps(c);
            improved = true;
          }
        }
      }
      if (!improved) break;
    }
  }
  return c;
}

M3 hullSearchAxes(const ConvexHull& hull, BoxSearch& search) {
  if (hull.dimension == 2) {
    // The plane normal (area vector of the fan, signs aligned to its largest triangle), then the
    // exact minimum-area rectangle in the plane.
    const std::vector<V3>& pts = hull.vertices;
    V3 biggest = V3::Zero();
    for (const auto& t : hull.triangles) {
      const V3 c = (pts[t[1]] - pts[t[0]]).cross(pts[t[2]] - pts[t[0]]);
      if (c.squaredNorm() > biggest.squaredNorm()) biggest = c;
    }
    V3 n = V3::Zero();
    for (const auto& t : hull.triangles) {
      const V3 c = (pts[t[1]] - pts[t[0]]).cross(pts[t[2]] - pts[t[0]]);
      n += c.dot(biggest) >= 0.0 ? c : V3(-c);
    }
    return search.bestAbout(n.normalized()).axes;
  }
  // Candidates: face normals (largest faces first), covariance axes, world axes.
  std::vector<V3> dirs = search.faceNormals();
  M3 cov;
  if (triangleCovariance(hull.vertices, hull.triangles, &cov)) {
    const M3 ca = covarianceAxes(cov, search);
    for (int k = 0; k < 3; ++k) dirs.push_back(ca.col(k));
  }
  for (int k = 0; k < 3; ++k) dirs.push_back(V3::Unit(k));
  // Keep the kRefineCandidates best (a candidate whose lower bound reaches the worst kept one
  // cannot enter the list and is pruned).
  std::vector<Candidate> kept;  // sorted by volume, at most kRefineCandidates
  for (const V3& n : dirs) {
    const double bound = static_cast<int>(kept.size()) < kRefineCandidates
                             ? std::numeric_limits<double>::infinity()
                             : kept.back().volume;
    const Candidate c = search.bestAbout(n, bound);
    if (!(c.volume < bound)) continue;
    auto at = std::upper_bound(kept.begin(), kept.end(), c.volume,
                               [](double vol, const Candidate& x) { return vol < x.volume; });
    kept.insert(at, c);
    if (static_cast<int>(kept.size()) > kRefineCandidates) kept.pop_back();
  }
  if (kept.empty()) return M3::Identity();  // only with non-finite volumes, which fitObb rules out
  Candidate best = kept.front();
  for (const Candidate& k : kept) {
    const Candidate r = refine(k, search);
    if (r.volume < best.volume * (1.0 - kImprovement)) best = r;
  }
  return best.axes;
}

// Step 3 of the file comment: canonical axes and the extents of all points.
Obb<double> finish(const M3& raw, int flat, const std::vector<V3>& s, const V3& origin) {
  M3 a = rightHanded(raw);
  const Extents e0 = extentsIn(a, s);
  const V3 size = e0.hi - e0.lo;
  // Order the non-flat axes by decreasing extent; extents equal to kEqualExtent (a cube, a square
  // section) are ordered by the world axis each is closest to, so an axis-aligned cube keeps the
  // world axes. Three elements: a bubble sort with this (non-transitive near ties) rule is
  // well-defined where std::sort's requirements would not be.
  std::array<int, 3> perm = {0, 1, 2};
  const int free = 3 - flat;
  auto dominant = [&](int k) {
    int i = 0;
    a.col(k).cwiseAbs().maxCoeff(&i);
    return i;
  };
  auto before = [&](int x, int y) {  // true when axis x must come before axis y
    if (std::abs(size[x] - size[y]) <= kEqualExtent * std::max(size[x], size[y]))
      return dominant(x) < dominant(y);
    return size[x] > size[y];
  };
  for (int pass = 0; pass < 2; ++pass) {
    for (int i = 0; i + 1 < free; ++i) {
      if (before(perm[i + 1], perm[i])) std::swap(perm[i], perm[i + 1]);
    }
  }
  M3 b;
  for (int k = 0; k < 3; ++k) b.col(k) = a.col(perm[k]);
  for (int k = 0; k < 2; ++k) {
    int i = 0;
    b.col(k).cwiseAbs().maxCoeff(&i);
    if (b(i, k) < 0.0) b.col(k) = -b.col(k);
  }
  b = rightHanded(b);
  const Extents e = extentsIn(b, s);
  const V3 mid = 0.5 * (e.lo + e.hi);
  V3 half = 0.5 * (e.hi - e.lo);
  for (int k = free; k < 3; ++k) half[k] = 0.0;
  Obb<double> box;
  box.axes = b;
  box.center = origin + b * mid;
  box.halfExtents = half;
  return box;
}

}  // namespace

const char* fitterName(ObbFitter f) {
  switch (f) {
    case ObbFitter::Covariance:
      return "covariance";
    case ObbFitter::HullSearch:
      return "hull-search";
  }
  return "unknown";
}

std::optional<ObbFitter> parseFitter(const std::string& name) {
  if (name == "covariance") return ObbFitter::Covariance;
  if (name == "hull-search") return ObbFitter::HullSearch;
  return std::nullopt;
}

Obb<double> fitObb(const std::vector<Vec3<double>>& points, ObbFitter fitter) {
  if (points.empty()) throw std::invalid_argument("fitObb: no points");
  Aabb<double> box;
  for (const V3& p : points) {
    if (!p.allFinite()) throw std::invalid_argument("fitObb: a point has a non-finite coordinate");
    box.extend(p);
  }
  const V3 origin = box.center();
  std::vector<V3> s(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) s[i] = points[i] - origin;
  const double diag = (box.max - box.min).norm();

  const ConvexHull hull = convexHull(s);
  switch (hull.dimension) {
    case 0:
      return finish(M3::Identity(), 3, s, origin);
    case 1: {
      const V3 d = (hull.vertices[1] - hull.vertices[0]).normalized();
      M3 a;
      a.col(0) = d;
      a.col(1) = perpendicularTo(d);
      a.col(2) = d.cross(a.col(1));
      return finish(a, 2, s, origin);
    }
    default:
      break;
  }
  const int flat = hull.dimension == 2 ? 1 : 0;
  M3 axes;
  BoxSearch search(hull, diag);
  if (fitter == ObbFitter::HullSearch) {
    axes = hullSearchAxes(hull, search);
  } else {
    M3 cov;
    if (!triangleCovariance(hull.vertices, hull.triangles, &cov)) {
      // Cannot happen for dimension 2 or 3 (their triangles have area); the vertices' covariance.
      V3 m = V3::Zero();
      for (const V3& p : hull.vertices) m += p;
      m /= static_cast<double>(hull.vertices.size());
      cov.setZero();
      for (const V3& p : hull.vertices) cov += (p - m) * (p - m).transpose();
    }
    axes = covarianceAxes(cov, search);
  }
  if (flat) {
    // Put the plane normal (the axis of least extent) last.
    const Extents e = extentsIn(rightHanded(axes), hull.vertices);
    int k = 0;
    (e.hi - e.lo).minCoeff(&k);
    if (k != 2) {
      M3 r = axes;
      r.col(2) = axes.col(k);
      r.col(k) = axes.col(2);
      axes = r;
    }
  }
  return finish(axes, flat, s, origin);
}

}  // namespace nestwalk
