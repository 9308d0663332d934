// Convex hull of a point set (through qhull), with its dimension, for OBB fitting.
// Thread safety: pure functions, safe from several threads at once (qhull's reentrant interface,
// libqhull_r, with its own state per call).
#pragma once

#include "nestwalk/geometry/volumes.h"

#include <array>
#include <vector>

namespace nestwalk {

struct ConvexHull {
  /// 3: a solid hull; 2: all points coplanar (the hull is a polygon, triangulated as a fan, both
  /// sides); 1: collinear (a segment: vertices are its two ends); 0: one distinct point; -1: empty.
  int dimension = -1;
  std::vector<Vec3<double>> vertices;            // the hull's vertices (a subset of the input)
  std::vector<std::array<int, 3>> triangles;     // outward-facing for dimension 3
};

/// The convex hull of `points`. Degenerate inputs (coplanar, collinear, repeated points) are
/// detected with a tolerance relative to the points' extent and get the lower-dimensional hull.
/// Deterministic: the same points in the same order give the same hull, bit for bit. Hull vertices
/// keep the input's coordinates exactly.
ConvexHull convexHull(const std::vector<Vec3<double>>& points);

/// The convex hull of 2D points (Andrew's monotone chain): indices into `points` in
/// counter-clockwise order, collinear points dropped (a point within 1e-12 of the points' extent of
/// the chord of its neighbours counts as collinear). Empty input gives an empty list, one
/// distinct point a single index, collinear points the two ends.
std::vector<int> convexHull2d(const std::vector<Eigen::Vector2d>& points);

}  // namespace nestwalk
