// Random box pairs for the batch tests (obb_batch_test, box_pairs_batch_test): uniform rotations,
// pairs placed a chosen gap apart along one of their 15 SAT axes, parallel and identity axes, boxes
// turned about the vertical, flat boxes and huge aspect ratios, around any origin (local frames
// and UTM-like magnitudes).
#pragma once

#include "nestwalk/geometry/volumes.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <utility>

namespace nestwalk::boxgen {

using Pair = std::pair<Obb<double>, Obb<double>>;

class Gen {
 public:
  explicit Gen(std::uint64_t seed) : rng_(seed) {}

  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  double logUniform(double lo, double hi) { return std::exp(uniform(std::log(lo), std::log(hi))); }
  bool chance(double p) { return uniform(0, 1) < p; }
  int index(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng_); }
  Vec3<double> inCube(double half) { return {uniform(-half, half), uniform(-half, half), uniform(-half, half)}; }
  Vec3<double> unitVector() {
    std::normal_distribution<double> n;
    Vec3<double> v(n(rng_), n(rng_), n(rng_));
    return v.normalized();
  }

  /// A uniformly random rotation (normalized quaternion of four normal samples).
  Mat3<double> rotation() {
    std::normal_distribution<double> n;
    Eigen::Quaterniond q(n(rng_), n(rng_), n(rng_), n(rng_));
    return q.normalized().toRotationMatrix();
  }
  /// A rotation by a small angle in [lo, hi] radians about a random axis.
  Mat3<double> smallRotation(double lo, double hi) {
    return Eigen::AngleAxisd(logUniform(lo, hi), unitVector()).toRotationMatrix();
  }
  /// A signed permutation matrix (exact; keeps the box, or swaps its axes).
  Mat3<double> signedPermutation() {
    std::array<int, 3> p = {0, 1, 2};
    std::shuffle(p.begin(), p.end(), rng_);
    Mat3<double> m = Mat3<double>::Zero();
    for (int k = 0; k < 3; ++k) m(p[k], k) = chance(0.5) ? 1.0 : -1.0;
    return m;
  }
  /// Half extents in [0.01, 10] m (log-uniform), each zero with probability pZero.
  Vec3<double> halfExtents(double pZero = 0.1) {
    Vec3<double> e;
    for (int k = 0; k < 3; ++k) e[k] = chance(pZero) ? 0.0 : logUniform(0.01, 10.0);
    return e;
  }

 private:
  std::mt19937_64 rng_;
};

// Radius of a box's projection on unit direction L.
inline double radiusAlong(const Obb<double>& b, const Vec3<double>& l) {
  return (b.axes.transpose() * l).cwiseAbs().dot(b.halfExtents);
}

/// Places B so that its projection on L is `gap` away from A's (negative: overlapping by -gap).
inline void placeAlong(const Obb<double>& a, Obb<double>& b, const Vec3<double>& l, double gap) {
  b.center = a.center + l * (radiusAlong(a, l) + radiusAlong(b, l) + gap);
}

/// One of the 15 SAT axes of the pair, normalized (a random direction when the chosen edge
/// axis is degenerate).
inline Vec3<double> satAxis(Gen& g, const Obb<double>& a, const Obb<double>& b) {
  const int k = g.index(15);
  if (k < 3) return a.axes.col(k);
  if (k < 6) return b.axes.col(k - 3);
  const Vec3<double> c = a.axes.col((k - 6) / 3).cross(b.axes.col((k - 6) % 3));
  return c.norm() > 1e-3 ? Vec3<double>(c.normalized()) : g.unitVector();
}

inline double signedGap(Gen& g) { return (g.chance(0.5) ? 1.0 : -1.0) * g.logUniform(1e-7, 1e-3); }

// The categories of pairs, each around `origin` (A's centre lies within 1 km of it).
inline Pair randomPair(Gen& g, const Vec3<double>& origin) {
  // Centres at a random distance up to 0.45 x the sum of the half diagonals: about half overlap.
  Obb<double> a{origin + g.inCube(1000), g.rotation(), g.halfExtents()};
  Obb<double> b{Vec3<double>::Zero(), g.rotation(), g.halfExtents()};
  b.center = a.center + g.unitVector() * g.uniform(0, 0.45) * (a.halfExtents.norm() + b.halfExtents.norm());
  return {a, b};
}

inline Pair nearTouchingPair(Gen& g, const Vec3<double>& origin) {
  Obb<double> a{origin + g.inCube(1000), g.rotation(), g.halfExtents()};
  Obb<double> b{Vec3<double>::Zero(), g.chance(0.2) ? Mat3<double>(a.axes * g.smallRotation(1e-9, 1e-3)) : g.rotation(),
                g.halfExtents()};
  placeAlong(a, b, satAxis(g, a, b), signedGap(g));
  return {a, b};
}

inline Pair parallelPair(Gen& g, const Vec3<double>& origin) {
  Obb<double> a{origin + g.inCube(1000), g.rotation(), g.halfExtents()};
  Obb<double> b{Vec3<double>::Zero(), a.axes * g.signedPermutation(), g.halfExtents()};
  if (g.chance(0.5))
    b.center = a.center + g.inCube(9.0);
  else
    placeAlong(a, b, satAxis(g, a, b), signedGap(g));
  return {a, b};
}

inline Pair identityPair(Gen& g, const Vec3<double>& origin) {
  // Multiples of 1/64 m: exact in float, so touching stays exactly touching.
  auto q = [](double x) { return std::round(x * 64) / 64; };
  Vec3<double> ea = g.halfExtents(), eb = g.halfExtents();
  Obb<double> a{origin + g.inCube(1000).unaryExpr(q), Mat3<double>::Identity(), ea.unaryExpr(q)};
  Obb<double> b{Vec3<double>::Zero(), Mat3<double>::Identity(), eb.unaryExpr(q)};
  const int axis = g.index(3);
  const double gap = g.chance(0.3) ? 0.0 : signedGap(g);
  b.center = a.center + g.inCube(1.0).unaryExpr(q);
  b.center[axis] = a.center[axis] + (g.chance(0.5) ? 1 : -1) * (a.halfExtents[axis] + b.halfExtents[axis] + gap);
  return {a, b};
}


/// Boxes turned about the vertical only (scene equipment): their z axes are exactly parallel, so
/// the edge axes A_z x B_z are exactly degenerate. One box in four is axis aligned. Centres a
/// random distance apart, or near touching along one of the pair's axes.
inline Pair verticalPair(Gen& g, const Vec3<double>& origin, bool nearTouching) {
  auto yaw = [&] {
    return g.chance(0.25) ? Mat3<double>(Mat3<double>::Identity())
                          : Mat3<double>(Eigen::AngleAxisd(g.uniform(0, 6.283185307179586), Vec3<double>::UnitZ())
                                             .toRotationMatrix());
  };
  Obb<double> a{origin + g.inCube(1000), yaw(), g.halfExtents()};
  Obb<double> b{Vec3<double>::Zero(), yaw(), g.halfExtents()};
  if (!nearTouching)
    b.center = a.center + g.unitVector() * g.uniform(0, 0.45) * (a.halfExtents.norm() + b.halfExtents.norm());
  else
    placeAlong(a, b, satAxis(g, a, b), signedGap(g));
  return {a, b};
}

/// One box axis aligned, the other turned anyhow (testBoxPair's stage 2 in both role orders);
/// centres a random distance apart, or near touching.
inline Pair oneAlignedPair(Gen& g, const Vec3<double>& origin, bool nearTouching) {
  Obb<double> a{origin + g.inCube(1000), g.rotation(), g.halfExtents()};
  Obb<double> b{Vec3<double>::Zero(), Mat3<double>::Identity(), g.halfExtents()};
  if (!nearTouching)
    b.center = a.center + g.unitVector() * g.uniform(0, 0.45) * (a.halfExtents.norm() + b.halfExtents.norm());
  else
    placeAlong(a, b, satAxis(g, a, b), signedGap(g));
  if (g.chance(0.5)) std::swap(a, b);
  return {a, b};
}

/// Flat boxes (panels, poles, points: zero half extents) and huge aspect ratios (1e-4 to 1e3 m),
/// near touching.
inline Pair degeneratePair(Gen& g, const Vec3<double>& origin) {
  auto extents = [&] {
    Vec3<double> e;
    for (int k = 0; k < 3; ++k) e[k] = g.chance(0.35) ? 0.0 : g.logUniform(1e-4, 1e3);
    return e;
  };
  Obb<double> a{origin + g.inCube(1000), g.chance(0.2) ? Mat3<double>(Mat3<double>::Identity()) : g.rotation(), extents()};
  Obb<double> b{Vec3<double>::Zero(), g.chance(0.2) ? Mat3<double>(Mat3<double>::Identity()) : g.rotation(), extents()};
  placeAlong(a, b, satAxis(g, a, b), g.chance(0.2) ? 0.0 : signedGap(g));
  return {a, b};
}

}  // namespace nestwalk::boxgen
