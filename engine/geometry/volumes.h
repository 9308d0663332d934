// Bounding volumes of the nested method (Ma et al., nested.h): the outer axis-aligned box
// (Aabb) and the inner oriented box (Obb), in float or double, on Eigen.
//
// Frames: a volume lives in whatever frame its numbers are in. The engine keeps geometry in a
// local frame near the origin (map coordinates minus a scene origin: a double map coordinate
// at UTM magnitude, 1e7 m, keeps only ~1 m in a float, a local one ~0.1 mm at 1 km); float
// volumes are only meaningful there.
// Thread safety: plain value types and pure functions.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <limits>

namespace nestwalk {

template <class T> using Vec3 = Eigen::Matrix<T, 3, 1>;
template <class T> using Mat3 = Eigen::Matrix<T, 3, 3>;

/// Closed axis-aligned box [min, max]. An empty box has min > max on every axis; a box with
/// min == max on some axis is flat (a panel), a line (a pole) or a point, and is not empty.
template <class T>
struct Aabb {
  Vec3<T> min = Vec3<T>::Constant(std::numeric_limits<T>::infinity());
  Vec3<T> max = Vec3<T>::Constant(-std::numeric_limits<T>::infinity());

  static Aabb fromCenterHalfExtents(const Vec3<T>& c, const Vec3<T>& h) { return {c - h, c + h}; }

  bool isEmpty() const { return (min.array() > max.array()).any(); }
  Vec3<T> center() const { return T(0.5) * (min + max); }
  Vec3<T> halfExtents() const { return T(0.5) * (max - min); }
  Vec3<T> size() const { return max - min; }
  T volume() const { return isEmpty() ? T(0) : size().prod(); }

  void extend(const Vec3<T>& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  void extend(const Aabb& b) {
    min = min.cwiseMin(b.min);
    max = max.cwiseMax(b.max);
  }
  /// Closed containment, with an absolute tolerance `tol` (same unit as the coordinates).
  bool contains(const Vec3<T>& p, T tol = T(0)) const {
    return ((p.array() >= min.array() - tol) && (p.array() <= max.array() + tol)).all();
  }
  template <class U> Aabb<U> cast() const { return {min.template cast<U>(), max.template cast<U>()}; }
};

/// Closed oriented box: the points center + axes * x with |x_k| <= halfExtents_k.
/// Contract: the columns of `axes` (u, v, w) are orthonormal and right-handed to within
/// kAxesTolerance<T> (see orthonormalized()); half extents are >= 0. A zero half extent is a
/// legal flat panel, pole or point.
template <class T>
struct Obb {
  Vec3<T> center = Vec3<T>::Zero();
  Mat3<T> axes = Mat3<T>::Identity();
  Vec3<T> halfExtents = Vec3<T>::Zero();

  static Obb fromAabb(const Aabb<T>& b) { return {b.center(), Mat3<T>::Identity(), b.halfExtents()}; }

  T volume() const { return T(8) * halfExtents.prod(); }
  /// Corner i (bit k of i chooses the sign along axis k).
  Vec3<T> corner(int i) const {
    Vec3<T> s((i & 1) ? T(1) : T(-1), (i & 2) ? T(1) : T(-1), (i & 4) ? T(1) : T(-1));
    return center + axes * s.cwiseProduct(halfExtents);
  }
  /// Closed containment with an absolute tolerance `tol` along each axis.
  bool contains(const Vec3<T>& p, T tol = T(0)) const {
    const Vec3<T> local = axes.transpose() * (p - center);
    return (local.cwiseAbs().array() <= halfExtents.array() + tol).all();
  }
  /// True when the axes are exactly the identity: the box is an AABB.
  bool isAxisAligned() const { return axes == Mat3<T>::Identity(); }
  template <class U> Obb<U> cast() const {
    return {center.template cast<U>(), axes.template cast<U>(), halfExtents.template cast<U>()};
  }
};

/// How far from orthonormal the axes of an Obb may be for the overlap tests' guarantees
/// (largest entry of axes^T axes - I). Double: ten times what a few chained rotations leave;
/// float: what rounding a double rotation to float leaves (3 half-ulps of 1.0).
template <class T> inline constexpr T kAxesTolerance = T(1e-13);
template <> inline constexpr float kAxesTolerance<float> = 2e-7f;

/// Largest |axes^T axes - I| entry, the orthonormality error the contract above bounds.
template <class T>
T axesError(const Mat3<T>& axes) {
  return (axes.transpose() * axes - Mat3<T>::Identity()).cwiseAbs().maxCoeff();
}

/// The nearest right-handed rotation to `m` (polar decomposition through the SVD, computed in
/// double for either type), for axes read from text or accumulated through many products.
template <class T>
Mat3<T> orthonormalized(const Mat3<T>& m);

/// Outward rounding of derived boxes, relative to the magnitudes involved: 8 unit roundoffs cover
/// the three-term sum |axes| * e (3u), the sum c +- h (u) and the padding itself (u), with margin.
template <class T> inline constexpr T kOutwardRounding = T(4) * std::numeric_limits<T>::epsilon();

/// The AABB of an OBB: half extents |axes| * e (Ericson, RTCD 4.2.6), rounded outward by
/// kOutwardRounding so that it contains the OBB despite rounding (it is exact to 1e-15 relative).
template <class T>
Aabb<T> aabbOf(const Obb<T>& b) {
  const Vec3<T> h = b.axes.cwiseAbs() * b.halfExtents;
  const Vec3<T> pad = kOutwardRounding<T> * (b.center.cwiseAbs() + h);
  return {b.center - h - pad, b.center + h + pad};
}

/// Rigid motion with uniform scale: p -> scale * rotation * p + translation. Under it an OBB stays
/// an exact OBB (axes rotate, half extents scale); scale must be > 0.
template <class T>
struct Similarity {
  Mat3<T> rotation = Mat3<T>::Identity();
  T scale = T(1);
  Vec3<T> translation = Vec3<T>::Zero();

  Vec3<T> apply(const Vec3<T>& p) const { return scale * (rotation * p) + translation; }
  /// (this * other)(p) = this(other(p)).
  Similarity operator*(const Similarity& o) const {
    return {rotation * o.rotation, scale * o.scale, apply(o.translation)};
  }
  Similarity inverse() const {
    const Mat3<T> rt = rotation.transpose();
    return {rt, T(1) / scale, -(rt * translation) / scale};
  }
  Obb<T> apply(const Obb<T>& b) const { return {apply(b.center), rotation * b.axes, scale * b.halfExtents}; }
  /// The AABB of a transformed AABB (treated as the OBB it becomes; see aabbOf).
  Aabb<T> apply(const Aabb<T>& b) const { return aabbOf(apply(Obb<T>::fromAabb(b))); }
};

}  // namespace nestwalk
