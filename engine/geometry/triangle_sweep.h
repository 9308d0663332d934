// A box translating by d (t from 0 to 1) against a triangle at rest: the interval of t over which
// the closed box and the closed triangle overlap, found in one pass over the separating axes
// instead of by repeated distance queries. The exact stage of the walker's mesh methods
// (mesh_tree.h's sweep, walker/mesh_world.h) is built on it.
//
// Why 13 axes are exact: the box overlaps the triangle at t iff the offset of the triangle from
// the box's centre lies in the Minkowski sum triangle + (-box) at t. That sum is a convex polytope
// whose facet normals are among the box's 3 face normals, the triangle's normal and the 9 cross
// products of box axes with triangle edges (the same 13 axes as the static test of triangle_box.h,
// Akenine-Moeller 2001). The offset moves on a line (it changes by -t d), so the set of t is the
// intersection of the 13 slabs, each an interval (slab_clip.h). Axes that are not facet normals
// only add true separations, so the result is the exact interval, not a sampling.
//
// Degenerate triangles (repeated or collinear corners) are legal: a zero axis gives the slab
// |0| <= slack, which always holds, and the remaining axes are those of a segment or a point.
//
// Rounding: the triangle is taken into the box's frame (kFrameRounding, triangle_box.h) and each
// slab carries sat.h's kRoundingSlack times the magnitudes in play, so at any t inside the
// interval the static test of triangle_box.h (up to its own bound) agrees: a contact is never
// missed; one may be reported up to about 1e-12 of the magnitudes early.
// Thread safety: pure functions.
#pragma once

#include "nestwalk/geometry/swept.h"
#include "nestwalk/geometry/triangle_box.h"

namespace nestwalk {

/// The box moving by d against the triangle at rest. Clipping stops once the interval misses
/// [windowStart, windowEnd] (then the result is empty or lies outside that window); `normal` is
/// the unit normal of the slab that entered last, pointing from the triangle toward the box.
SweepResult sweepBoxTriangle(const Obb<double>& box, const Vec3<double>& d, const Triangle& triangle,
                             double windowStart = 0.0, double windowEnd = 1.0);

/// Metres: how far beyond a triangle its slabs' slack may reach (the sweep can report the box
/// touching a triangle while it is still this far away), for every triangle whose corners lie
/// within `reach` (max norm) of the origin. A bounding volume grown by this never enters later
/// than the triangles it holds (mesh_tree.h's sweep prunes with it).
double sweepBoxTriangleSlack(const Obb<double>& box, const Vec3<double>& d, double reach);

}  // namespace nestwalk
