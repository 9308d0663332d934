// Small helpers shared by the geometry tests: random rotations and point-set sizes.
#pragma once

#include "nestwalk/geometry/volumes.h"

#include <Eigen/Geometry>

#include <random>
#include <vector>

namespace nestwalk::testshapes {

/// A rotation uniformly distributed over SO(3) (normalised Gaussian quaternion).
inline Mat3<double> randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> g;
  return Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
}

/// The diagonal of the points' AABB: the size tolerances are relative to.
inline double diagonal(const std::vector<Vec3<double>>& pts) {
  Aabb<double> b;
  for (const auto& p : pts) b.extend(p);
  return (b.max - b.min).norm();
}

}  // namespace nestwalk::testshapes
