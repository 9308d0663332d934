// Fitting an oriented bounding box to a model's points.
//  - Covariance: Gottschalk, Lin & Manocha, "OBBTree" (SIGGRAPH 1996), section 3: the axes are the
//    eigenvectors of the area-weighted covariance of the convex hull's triangles (Eigen's
//    symmetric solver); extents by projecting the hull's vertices.
//  - a tighter fitter (see ObbFitter) so that a scene can choose tightness against fitting time.
// Every fitter returns a box that contains every input point (to rounding: 1e-9 relative to the
// points' extent, plus a few ulps of the coordinates' magnitude -- far from the origin the points
// themselves carry no more than that), with orthonormal right-handed axes, and defined results for
// degenerate input: coplanar points (a zero half extent along the plane normal), collinear points
// (two zero half extents, the first axis along the line), a single point (all zero), repeated
// eigenvalues (cube, cylinder: any orthonormal basis of the repeated eigenspace, deterministically
// chosen).
// Conventions of the result: axes ordered by decreasing half extent (the flat axes of degenerate
// input last: the plane normal is axis 2, a line is axis 0); equal extents ordered by the world
// axis each is closest to (an axis-aligned cube gets the identity); the largest component of axes
// 0 and 1 is positive and axis 2 = axis 0 x axis 1. Same input, same box, bit for bit.
// Points far from the origin (map coordinates) are handled: fitting works relative to the
// points' AABB centre.
// Thread safety: a pure function, safe from several threads at once (hulls through qhull's
// reentrant interface).
#pragma once

#include "nestwalk/geometry/obb_fitter.h"
#include "nestwalk/geometry/volumes.h"

#include <string>
#include <vector>

namespace nestwalk {

/// The fitted box of `points` (throws std::invalid_argument when `points` is empty or holds a
/// non-finite coordinate).
Obb<double> fitObb(const std::vector<Vec3<double>>& points, ObbFitter fitter);

}  // namespace nestwalk
