// Triangle-box overlap (13-axis SAT with exact signs) and distance; see triangle_box.h for the
// method and its guarantees.
#include "nestwalk/geometry/triangle_box.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace nestwalk {
namespace {

using V3 = Vec3<double>;
constexpr double kEpsilon = std::numeric_limits<double>::epsilon();  // 2u, u = 2^-53

// Forward error bounds of the double evaluations below, relative to the sum of the absolute values
// of the terms (the "permanent" M of each value; u = 2^-53 = epsilon / 2; d = x - c, the vertex
// relative to the box centre, carries u of |d|):
//  - Face axis, F = (x - c) - s (s = +-h): u |d| + u |F|, so |error| <= 2u M, M = |d| + h;
//    4u = 2 epsilon keeps a 2x margin.
//  - Edge axis, Q = L_a d_a + L_b d_b -+ (h_a |L_a| + h_b |L_b|), L = +-(edge difference, u):
//    3u on each product's share, a sum (u) on each side and the final subtraction (u):
//    |error| <= 5u M, M = sum |L_m| (|d_m| + h_m); 12u = 6 epsilon keeps a 2.4x margin.
//  - Triangle normal, D = n . d0 -+ sum h_m |n_m|, n = (t1 - t0) x (t2 - t0): n_m carries 4u of
//    N_m = |a_i b_j| + |a_j b_i| (two differences, two products, a subtraction), the products
//    with d0_m (itself u) or h_m one more u, the three-term sums 2u and the subtraction u:
//    |error| <= 9u M, M = sum N_m (|d0_m| + h_m); 20u = 10 epsilon keeps a 2.2x margin.
// The bounds of M itself are rounded too (a few u, inside the margins).
constexpr double kFaceAxisFilter = 2 * kEpsilon;
constexpr double kEdgeAxisFilter = 6 * kEpsilon;
constexpr double kNormalAxisFilter = 10 * kEpsilon;

// ---- Exact signs: error-free transformations and expansion arithmetic (Shewchuk 1997). ----

// a + b = s + e exactly (Knuth's two-sum, no precondition on magnitudes).
inline void twoSum(double a, double b, double& s, double& e) {
  s = a + b;
  const double bVirtual = s - a;
  e = (a - (s - bVirtual)) + (b - bVirtual);
}

// An exact value as a sum of at most three doubles.
struct ExactFactor {
  double part[3];
  int count;
};
// a - b exactly.
inline ExactFactor exactDifference(double a, double b) {
  ExactFactor f{{0, 0, 0}, 2};
  twoSum(a, -b, f.part[0], f.part[1]);
  return f;
}
// x - c - s exactly.
inline ExactFactor exactOffset(double x, double c, double s) {
  ExactFactor f{{0, 0, 0}, 3};
  double partial;
  twoSum(x, -c, partial, f.part[0]);
  twoSum(partial, -s, f.part[1], f.part[2]);
  return f;
}

// Doubles whose exact sum is a polynomial's value; sign() is the exact sign of that sum.
// Capacity: the largest value built here (the normal test) has 3 x 2 products of three factors of
// 2, 2 and 3 parts, each monomial split exactly into 4 doubles: 288 terms.
class ExactSum {
 public:
  void add(const ExactFactor& x) {
    for (int i = 0; i < x.count; ++i) push(x.part[i]);
  }
  // + or - x * y exactly (each monomial an fma-exact product: 2 doubles).
  void addProduct(double sign, const ExactFactor& x, const ExactFactor& y) {
    for (int i = 0; i < x.count; ++i)
      for (int j = 0; j < y.count; ++j) addExactProduct(sign * x.part[i], y.part[j]);
  }
  // + or - x * y * z exactly (each monomial 4 doubles).
  void addProduct(double sign, const ExactFactor& x, const ExactFactor& y, const ExactFactor& z) {
    for (int i = 0; i < x.count; ++i)
      for (int j = 0; j < y.count; ++j) {
        const double xi = sign * x.part[i], yj = y.part[j];
        const double p = xi * yj;
        const double e = std::fma(xi, yj, -p);  // xi yj = p + e exactly
        for (int k = 0; k < z.count; ++k) {
          addExactProduct(p, z.part[k]);
          addExactProduct(e, z.part[k]);
        }
      }
  }
  // The sign of the exact sum: grow a nonoverlapping expansion term by term (Shewchuk's
  // Grow-Expansion with zero elimination); its largest, last component has the sum's sign.
  int sign() const {
    double expansion[kCapacity];
    int length = 0;
    for (int t = 0; t < count_; ++t) {
      double q = terms_[t];
      int kept = 0;
      for (int i = 0; i < length; ++i) {
        double s, e;
        twoSum(q, expansion[i], s, e);
        if (e != 0) expansion[kept++] = e;
        q = s;
      }
      if (q != 0) expansion[kept++] = q;
      length = kept;
    }
    if (length == 0) return 0;
    return expansion[length - 1] > 0 ? 1 : -1;
  }

 private:
  static constexpr int kCapacity = 288;
  void push(double v) {
    if (v != 0) terms_[count_++] = v;
  }
  void addExactProduct(double a, double b) {
    const double p = a * b;
    push(p);
    push(std::fma(a, b, -p));  // zero when p is exact (or a or b is zero)
  }
  double terms_[kCapacity];
  int count_ = 0;
};

inline int signOf(double v) { return (v > 0) - (v < 0); }

// The sign of a value computed in double as `value` with forward error <= `bound`, or, when the
// filter cannot decide, of the exact value `exact()` returns.
template <class Exact>
inline int filteredSign(double value, double bound, Exact&& exact) {
  if (value > bound) return 1;
  if (value < -bound) return -1;
  return exact().sign();
}

// Face axis k: the sign of x - c - s (s = +-h_k).
int faceAxisSign(double x, double c, double s) {
  const double d = x - c;
  return filteredSign(d - s, kFaceAxisFilter * (std::abs(d) + std::abs(s)), [&] {
    ExactSum sum;
    sum.add(exactOffset(x, c, s));
    return sum;
  });
}

// Edge axis L = e_k x f, f = t[j1] - t[j] (only the components a = k+1, b = k+2 are nonzero:
// L_a = -f_b, L_b = f_a). For a vertex x of the triangle and sigma = +1 (-1), the sign of
//   Q = L . (x - c) - sigma r,  r = h_a |L_a| + h_b |L_b|  (the box's radius on L),
// i.e. of sum_m L_m (x_m - c_m - sigma s_m h_m) with s_m = sign(L_m) (exact: a comparison of two
// coordinates). The triangle lies beyond the box on L iff Q(+1) > 0 for all three vertices.
int edgeAxisSign(const Triangle& t, int j, int k, const V3& x, double sigma, const V3& c, const V3& h) {
  const int j1 = (j + 1) % 3, a = (k + 1) % 3, b = (k + 2) % 3;
  const double La = -(t[j1][b] - t[j][b]), Lb = t[j1][a] - t[j][a];
  const double da = x[a] - c[a], db = x[b] - c[b];
  const double value = La * da + Lb * db - sigma * (h[a] * std::abs(La) + h[b] * std::abs(Lb));
  const double permanent = std::abs(La) * (std::abs(da) + h[a]) + std::abs(Lb) * (std::abs(db) + h[b]);
  return filteredSign(value, kEdgeAxisFilter * permanent, [&] {
    ExactSum sum;
    sum.addProduct(1.0, exactDifference(t[j][b], t[j1][b]), exactOffset(x[a], c[a], sigma * signOf(La) * h[a]));
    sum.addProduct(1.0, exactDifference(t[j1][a], t[j][a]), exactOffset(x[b], c[b], sigma * signOf(Lb) * h[b]));
    return sum;
  });
}

// Triangle normal n = (t1 - t0) x (t2 - t0): the sign of D = n . (t0 - c) - sigma sum_m h_m |n_m|,
// i.e. of sum_m n_m (t0_m - c_m - sigma s_m h_m) with s_m = sign(n_m) (exact signs of 2x2 minors).
// The box lies strictly below the triangle's plane iff D(+1) > 0, strictly above iff D(-1) < 0.
int normalAxisSign(const Triangle& t, double sigma, const V3& c, const V3& h) {
  const V3 e1 = t[1] - t[0], e2 = t[2] - t[0];
  const V3 n = e1.cross(e2);
  const V3 d0 = t[0] - c;
  double value = 0, permanent = 0;
  for (int m = 0; m < 3; ++m) {
    const int i = (m + 1) % 3, j = (m + 2) % 3;
    value += n[m] * d0[m] - sigma * h[m] * std::abs(n[m]);
    permanent += (std::abs(e1[i] * e2[j]) + std::abs(e1[j] * e2[i])) * (std::abs(d0[m]) + h[m]);
  }
  return filteredSign(value, kNormalAxisFilter * permanent, [&] {
    ExactFactor d1[3], d2[3];
    for (int m = 0; m < 3; ++m) {
      d1[m] = exactDifference(t[1][m], t[0][m]);
      d2[m] = exactDifference(t[2][m], t[0][m]);
    }
    ExactSum sum;
    for (int m = 0; m < 3; ++m) {
      const int i = (m + 1) % 3, j = (m + 2) % 3;
      ExactSum minor;  // n_m = d1_i d2_j - d1_j d2_i
      minor.addProduct(1.0, d1[i], d2[j]);
      minor.addProduct(-1.0, d1[j], d2[i]);
      const int sm = minor.sign();
      if (sm == 0) continue;
      const ExactFactor w = exactOffset(t[0][m], c[m], sigma * sm * h[m]);
      sum.addProduct(1.0, d1[i], d2[j], w);
      sum.addProduct(-1.0, d1[j], d2[i], w);
    }
    return sum;
  });
}

// ---- Distance helpers, in the box's frame (box [-h, h]). ----

double pointBoxDistanceSquared(const V3& p, const V3& h) {
  return (p.cwiseAbs() - h).cwiseMax(0.0).squaredNorm();
}

// Squared distance between segments p1q1 and p2q2 (Ericson 5.1.9, zero-length segments exact).
double segmentSegmentDistanceSquared(const V3& p1, const V3& q1, const V3& p2, const V3& q2) {
  const V3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0, t = 0;
  if (a == 0 && e == 0) return r.squaredNorm();
  if (a == 0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e == 0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return (p1 + d1 * s - (p2 + d2 * t)).squaredNorm();
}

// Squared distance from p to the triangle's plane when p projects inside the triangle (its face
// region), else +infinity (the triangle's edges then hold the closest point: the caller's
// edge-edge pairs cover it). A degenerate triangle has no face region.
double pointFaceDistanceSquared(const V3& p, const Triangle& t, const V3& normal) {
  const double nn = normal.squaredNorm();
  if (nn == 0) return std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    const V3& u = t[i];
    const V3& v = t[(i + 1) % 3];
    if ((v - u).cross(p - u).dot(normal) < 0) return std::numeric_limits<double>::infinity();
  }
  const double offset = normal.dot(p - t[0]);
  return offset * offset / nn;
}

// The triangle mapped into a rotated box's frame, and the box's half extents grown by the rounding
// of that map (see triangle_box.h): the box is then [-halfExtents, halfExtents].
struct TriangleInBoxFrame {
  Triangle triangle;
  V3 halfExtents;
};
TriangleInBoxFrame toBoxFrame(const Triangle& tri, const Obb<double>& box) {
  TriangleInBoxFrame out;
  V3 growth = V3::Zero();
  for (int i = 0; i < 3; ++i) {
    const V3 d = tri[i] - box.center;
    out.triangle[i] = box.axes.transpose() * d;
    growth = growth.cwiseMax(kFrameRounding * (box.axes.cwiseAbs().transpose() * d.cwiseAbs()));
  }
  out.halfExtents = box.halfExtents;
  for (int k = 0; k < 3; ++k)
    out.halfExtents[k] = std::nextafter(box.halfExtents[k] + growth[k], std::numeric_limits<double>::infinity());
  return out;
}

}  // namespace

bool triangleOverlapsAxisAlignedBox(const Triangle& t, const V3& c, const V3& h) {
  // Box face axes: the nearest vertex (an exact comparison) beyond the face.
  for (int k = 0; k < 3; ++k) {
    if (faceAxisSign(std::min({t[0][k], t[1][k], t[2][k]}), c[k], h[k]) > 0) return false;
    if (faceAxisSign(std::max({t[0][k], t[1][k], t[2][k]}), c[k], -h[k]) < 0) return false;
  }
  // Triangle normal: the box strictly on one side of the plane.
  if (normalAxisSign(t, 1.0, c, h) > 0 || normalAxisSign(t, -1.0, c, h) < 0) return false;
  // Edge axes e_k x (t[j+1] - t[j]); on each, t[j] and t[j+1] project to the same value, so the
  // edge's start and the opposite vertex decide.
  for (int j = 0; j < 3; ++j) {
    const int j1 = (j + 1) % 3, opposite = (j + 2) % 3;
    for (int k = 0; k < 3; ++k) {
      const int a = (k + 1) % 3, b = (k + 2) % 3;
      if (t[j1][a] == t[j][a] && t[j1][b] == t[j][b]) continue;  // zero axis: cannot separate
      if (edgeAxisSign(t, j, k, t[j], 1.0, c, h) > 0 && edgeAxisSign(t, j, k, t[opposite], 1.0, c, h) > 0) return false;
      if (edgeAxisSign(t, j, k, t[j], -1.0, c, h) < 0 && edgeAxisSign(t, j, k, t[opposite], -1.0, c, h) < 0) return false;
    }
  }
  return true;
}

bool triangleBoxOverlap(const Triangle& tri, const Obb<double>& box) {
  if (box.isAxisAligned()) return triangleOverlapsAxisAlignedBox(tri, box.center, box.halfExtents);
  const TriangleInBoxFrame local = toBoxFrame(tri, box);
  return triangleOverlapsAxisAlignedBox(local.triangle, V3::Zero(), local.halfExtents);
}

double triangleBoxDistance(const Triangle& tri, const Obb<double>& box) {
  if (triangleBoxOverlap(tri, box)) return 0.0;
  Triangle t;  // in the box's frame, where the box is [-h, h]
  for (int i = 0; i < 3; ++i) t[i] = box.axes.transpose() * (tri[i] - box.center);
  const V3& h = box.halfExtents;
  double best = std::numeric_limits<double>::infinity();
  // Triangle vertices against the solid box.
  for (const V3& p : t) best = std::min(best, pointBoxDistanceSquared(p, h));
  // Box corners against the triangle's face.
  const V3 normal = (t[1] - t[0]).cross(t[2] - t[0]);
  for (int c = 0; c < 8; ++c) {
    const V3 corner((c & 1) ? h[0] : -h[0], (c & 2) ? h[1] : -h[1], (c & 4) ? h[2] : -h[2]);
    best = std::min(best, pointFaceDistanceSquared(corner, t, normal));
  }
  // Triangle edges against box edges: along axis k, at the four sign pairs of the other two.
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    for (int s = 0; s < 4; ++s) {
      V3 from, to;
      from[k] = -h[k];
      to[k] = h[k];
      from[a] = to[a] = (s & 1) ? h[a] : -h[a];
      from[b] = to[b] = (s & 2) ? h[b] : -h[b];
      for (int j = 0; j < 3; ++j)
        best = std::min(best, segmentSegmentDistanceSquared(t[j], t[(j + 1) % 3], from, to));
    }
  }
  return std::sqrt(best);
}

}  // namespace nestwalk
