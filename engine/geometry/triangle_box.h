// Exact contact between a triangle and a closed oriented box, and their distance: the primitive
// test (Cp of the cost model) under the mesh trees of mesh_tree.h.
//
// Overlap: the separating-axis test with the 13 candidate axes of a triangle and a box
// (Akenine-Moeller, "Fast 3D triangle-box overlap testing", 2001; Ericson, Real-Time Collision
// Detection 5.2.9): the box's 3 face normals, the triangle's normal and the 9 cross products of
// the box's axes with the triangle's edges, tested in the box's frame. The sets are closed:
// touching (a vertex on a face, an edge along a face, a triangle coplanar with a face) is overlap;
// separation needs a strict gap on some axis.
//
// Exactness. For a box with axes exactly the identity (an axis-aligned box given by its centre c
// and half extents h) every test is the sign of a polynomial of degree <= 3 in the inputs (box
// faces: x - c -+ h, degree 1; edge axes: degree 2; normal: degree 3). Each sign is first taken in
// double with a forward error bound (a floating-point filter, as in Shewchuk's adaptive
// predicates, 1997) and, when the value lies inside its bound, recomputed exactly as a sum of
// error-free products (std::fma) accumulated into a nonoverlapping expansion. So the verdict is
// exact for the doubles as given (c included: nothing is rounded, even at UTM magnitudes): no
// tolerance. Degenerate triangles (collinear, repeated or coincident vertices) need no special
// path: a zero cross product gives the interval [0, 0] against [-r, r], which never separates,
// and the remaining axes (box faces, the segment's edge axes) are exactly the separating axes of a
// segment or a point against a box.
// Assumption: no intermediate product under- or overflows (nonzero coordinates and differences
// between ~1e-90 and ~1e90 in magnitude); model coordinates in metres are far inside that.
//
// Rotated boxes. The triangle is mapped to p' = axes^T (p - center), the frame in which the box is
// [-h, h] (Obb::contains' definition of the box; the map is affine, so the triangle stays a
// triangle). The map's rounding is bounded by kFrameRounding (below) and the box is grown by that
// bound before the exact test: a contact is never missed; a gap smaller than the bound (about
// 2e-15 of the triangle's distance from the box centre: 2e-14 m at 10 m) may be reported as
// touching. Geometry far from the origin should be moved to a local frame first (the
// mesh trees work in the model's frame).
//
// Distance (triangleBoxDistance): the Euclidean distance between the closed sets, 0 when they
// overlap (decided by the exact test above). Otherwise it is the minimum over the feature pairs
// that can hold the closest points of two disjoint convex polytopes: triangle vertices against the
// solid box (clamping), box corners against the triangle's face (when a corner projects inside
// the triangle; otherwise its closest point is on an edge, covered next), and triangle edges
// against box edges (segment-segment, Ericson 5.1.9). The pairs left out (edge-face, face-edge, face-face) can hold a closest
// pair only when parallel, and then a pair listed above holds one too. Computed in double in the
// box's frame: relative error ~1e-15 of the distance plus ~1e-16 of |p - center|.
// Thread safety: pure functions.
#pragma once

#include "nestwalk/geometry/volumes.h"

#include <array>
#include <limits>

namespace nestwalk {

/// A triangle by its three corners (any of them may coincide: degenerate triangles are legal).
using Triangle = std::array<Vec3<double>, 3>;

/// Bound on the rounding of mapping a point into a rotated box's frame, relative to
/// |axes_k| . |p - center| for local coordinate k: the difference p - center (u each) and the
/// three-term dot product (3u) give 4u (u = 2^-53 = epsilon / 2); 4 epsilon = 8u keeps a 2x margin
/// (and covers the rounding of the bound itself).
inline constexpr double kFrameRounding = 4 * std::numeric_limits<double>::epsilon();

/// Exact overlap of the closed triangle with the closed axis-aligned box centre +- halfExtents
/// (half extents >= 0), for any double inputs (see the header comment). No tolerance.
bool triangleOverlapsAxisAlignedBox(const Triangle& tri, const Vec3<double>& center, const Vec3<double>& halfExtents);

/// Closed triangle vs closed OBB, both in the same frame. Exact when the box's axes are exactly
/// the identity; otherwise never misses a contact (see the header comment).
bool triangleBoxOverlap(const Triangle& tri, const Obb<double>& box);

/// Euclidean distance between the closed triangle and the closed box, 0 when they overlap.
double triangleBoxDistance(const Triangle& tri, const Obb<double>& box);

}  // namespace nestwalk
