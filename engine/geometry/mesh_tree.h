// Exact contact and distance between a box (the viewer's body) and a model's real triangles,
// through a bounding-volume hierarchy over the triangles, built once per model: the reference the
// nested AABB/OBB volumes are measured against, and the exact stage of the walker's mesh methods.
//
// The hierarchy (Klosowski, Held, Mitchell, Sowizral & Zikan, "Efficient collision detection using
// bounding volume hierarchies of k-DOPs", 1998): a binary tree of 18-DOPs over the TriangleMesh
// (model frame), built top-down: each node's volume is the slabs of its triangles' vertices on the
// 3 coordinate axes and the 6 diagonals (1,1,0), (1,-1,0), (1,0,1), (1,0,-1), (0,1,1), (0,1,-1);
// the node is split by the "splatter" rule: the coordinate axis along which the triangles'
// centroids have the largest variance, at their mean. A node with at most leafSize triangles is a
// leaf; a split that leaves one side empty (all centroids on one side of the mean, e.g. equal
// centroids) falls back to the median (the sorted centroids cut in two halves), as does every
// split below depth kMaxMeanSplitDepth, so the depth stays below kMaxMeanSplitDepth +
// log2(triangles) + 1 whatever the mesh.
// A node is tested against the box on the 9 directions (the box's own 18-DOP) and on the box's 3
// face axes, along which the node's extent is bounded through three of its slabs (each axis
// written over the coordinate axes, the node's AABB, or over a diagonal and two axes, whichever
// is tighter: a body turned about z uses a horizontal diagonal): a body box turned against the
// model's axes has a loose 18-DOP, and its own axes take that looseness away (the shared data's
// excavator, 11,144 triangles, walked into from 12 sides: the costliest sweep went from 489 node
// and 481 triangle tests, 50 us, to 169 and 40, 15 us, with the AABB alone).
// Why not OBB nodes (Gottschalk, Lin & Manocha, "OBBTree", 1996), which the engine had beside the
// k-DOPs until 2026-11: on body boxes swept into the shared dump truck (23,346 triangles) and
// excavator, the OBB tree's sweeps cost 3.4x to 3.6x this tree's (mean) and its distances 4.7x to
// 5.5x, because an OBB-OBB test (15 axes, a rotation product per node) costs several k-DOP tests;
// and it took 20x as long to build (a convex hull per node: 0.7 s against 36 ms for the truck).
// Layout: nodes in one std::vector in depth-first order (a node's first child is the next node,
// its second child by index), the triangles' corners copied in leaf order into one vector; no
// per-node allocation, no allocation in the queries.
// Build cost (Release, one core): 36 ms for the 23,346-triangle dump truck.
//
// Queries (the box in the model frame; an instance's box is brought there by the inverse of the
// instance's transform, which keeps the numbers at model magnitudes):
//  - overlaps(box): exact contact truth: does any triangle touch the closed box
//    (triangleBoxOverlap, triangle_box.h: never misses a contact, exact for an axis-aligned box).
//    The bounding-volume tests are conservative (node volumes padded outward for rounding, the
//    SAT's slack of sat.h), so the hierarchy never changes the verdict of the brute-force loop.
//  - distance(box): min over triangles of triangleBoxDistance, 0 when they overlap; depth-first
//    branch and bound, nearer child first, pruned by lower bounds on the box-to-volume distance
//    (the largest gap over the 9 directions, each divided by its length, and the box's 3 axes),
//    each lowered by a rounding slack so that pruning never drops the minimum. The result is the
//    brute-force minimum (same triangles, same function, so the same double).
//  - sweep(box, d, tStart): the first t in [tStart, 1] at which the box moved by t d touches a
//    triangle (sweepBoxTriangle, triangle_sweep.h: exact intervals in t, never late); best first:
//    nodes are opened in the order the moving box enters them (a min-heap on the entry time, the
//    box's slabs moving across the node's), and the search ends when the next node is entered
//    after the best contact found, so the work grows with the triangles the box reaches before
//    its contact, not with those inside the model's box. Nodes are tested with the box grown by
//    the triangle test's slack (sweepBoxTriangleSlack), so a node is never entered later than a
//    triangle it holds. Besides its 18-DOP, each node has a slab along its triangles' mean normal
//    (NormalSlab: no thicker than rounding on a flat patch, where the fixed directions are loose by
//    up to a third of the patch). Ties: contacts within kSweepTieSlacks slacks of each other along
//    the motion (meshSweepTieDistance, 33 nm at 20 m from the origin) are one: the search keeps
//    the first it finds and opens nothing entered later than that less the tie; the answer is
//    that contact less the tie (so never late: no later than bruteForceSweep's t, earlier by at
//    most the tie), with the normal of the triangle found. Why: a body pressed on a dense flat
//    face reaches every triangle under it at the same time up to rounding (10,206 on a wall of
//    1 cm squares, 74 on the drill rig's mast); deciding which of them is first to the last bit
//    tested them all, and now tests a handful (the wall: 3 triangles, 51 nodes).
//  - freeUntil(box, d): a time before which the box touches nothing (never late), from the same
//    search stopped at the first contact it finds: the least of that contact and the entry of the
//    earliest node left unopened. What CoherentSweep's look-ahead needs, at a fraction of a sweep.
//  - counters (the cost model T = Nv Cv + Np Cp of Gottschalk et al. and Klosowski et al.):
//    nodeTests = bounding-volume tests (Nv), triangleTests = triangle tests (Np).
// Bad input: a triangle index out of range or a non-finite coordinate throws std::invalid_argument
// naming the triangle; leafSize < 1 throws too. An empty mesh is legal: nothing overlaps, the
// distance is +infinity.
//
// Units: those of the mesh's coordinates (MeshWorld builds the trees in each model file's own frame
// and units and scales at its boundary); distances come back in the same unit; t is a fraction
// of d.
// Ownership: a tree copies the triangles it needs; it keeps no reference to the TriangleMesh.
// Thread safety: a built tree is immutable; its const queries keep no scratch (fixed stacks on the
// call stack) and may run from several threads at once. The optional `counters` and `nearest` are
// the caller's: one per thread.
#pragma once

#include "nestwalk/geometry/triangle_box.h"
#include "nestwalk/geometry/triangle_mesh.h"
#include "nestwalk/geometry/volumes.h"

#include <array>
#include <cstdint>
#include <vector>

namespace nestwalk {

/// The first contact of a box translating by d (t in [tStart, 1]) with the triangles.
struct MeshSweepHit {
  bool contact = false;
  double t = 1.0;                              // the earliest t in [tStart, 1] the box touches a triangle
  Vec3<double> normal = Vec3<double>::Zero();  // at t, from the triangle toward the box (zero when
                                               // already touching at tStart)
};

/// The reference loops the trees must agree with: every triangle tested.
bool bruteForceOverlaps(const TriangleMesh& mesh, const Obb<double>& box);
double bruteForceDistance(const TriangleMesh& mesh, const Obb<double>& box);
MeshSweepHit bruteForceSweep(const TriangleMesh& mesh, const Obb<double>& box, const Vec3<double>& d,
                             double tStart = 0.0);

/// Work done by one query (Nv and Np of the cost model); queries add to them.
struct MeshQueryCounters {
  std::uint64_t nodeTests = 0;      // bounding-volume tests
  std::uint64_t triangleTests = 0;  // triangle-box tests (overlap or distance)
};

/// An 18-DOP: for each of kKdopDirections (unnormalised), the interval of the projections.
struct Kdop18 {
  static constexpr int kDirections = 9;
  std::array<double, kDirections> min;
  std::array<double, kDirections> max;
};
/// The 9 directions: x, y, z, then (1,1,0), (1,-1,0), (1,0,1), (1,0,-1), (0,1,1), (0,1,-1).
extern const std::array<Vec3<double>, Kdop18::kDirections> kKdopDirections;

/// Contacts of a sweep closer together than this many of the triangle test's rounding slacks
/// (sweepBoxTriangleSlack) along the motion count as one: the sweep keeps the first it finds and
/// opens nothing that could only beat it by less. 64 slacks are 33 nm at 20 m from a model's
/// origin, far below any stop distance; they are wide enough that a node on a flat patch, whose
/// normal slab is tight to the slack, is passed over once the patch has given its contact, for
/// motions more than 1.6 degrees off the patch's plane (its entry moves back by at most
/// sqrt(3) slacks over the sine of that angle).
inline constexpr double kSweepTieSlacks = 64;
/// ... but no more than this fraction of the box's smallest half extent (0.25 um on the body box),
/// where the slack is large (a mesh in map coordinates: 64 slacks are 3 cm at 7,000 km from its
/// origin), and never less than kSweepTieMinSlacks slacks (a flat patch's nodes are then passed
/// over for motions more than 60 degrees off its plane).
inline constexpr double kSweepTieBoxFraction = 1e-6;
inline constexpr double kSweepTieMinSlacks = 2;
/// Along the motion, in the mesh's units: kSweepTieSlacks of sweepBoxTriangleSlack, within the
/// bounds above.
double meshSweepTieDistance(const Obb<double>& box, const Vec3<double>& d, double reach);

/// Mean splits stop at this depth (median splits below it); see the header comment.
inline constexpr int kMaxMeanSplitDepth = 48;
inline constexpr int kDefaultLeafSize = 4;

/// A node's slab along its triangles' mean normal (area-weighted, unit; the x axis when the
/// normals cancel): of no thickness on a flat patch, where the k-DOP's fixed directions are loose
/// by up to a third of the patch's size. The sweep clips it with the others.
struct NormalSlab {
  Vec3<double> normal = Vec3<double>::UnitX();
  double min = 0, max = 0;  // the extent of normal . p over the node's corners, padded for rounding
};

template <class Volume>
struct MeshTreeNode {
  Volume volume;
  NormalSlab facing;
  std::uint32_t firstTriangle = 0;  // the node's triangles are [first, first + count) of triangles()
  std::uint32_t triangleCount = 0;
  std::uint32_t secondChild = 0;    // 0 for a leaf (the root is never a child); first child = this + 1
  bool isLeaf() const { return secondChild == 0; }
};

/// A binary bounding-volume tree over a mesh's triangles; Volume is Kdop18 (KdopTree). See the
/// header comment for the construction rules and the queries.
template <class Volume>
class MeshTree {
 public:
  explicit MeshTree(const TriangleMesh& mesh, int leafSize = kDefaultLeafSize);

  bool overlaps(const Obb<double>& box, MeshQueryCounters* counters = nullptr) const;
  /// `nearest`, when given, receives the triangle at that distance (unchanged when there is none).
  double distance(const Obb<double>& box, MeshQueryCounters* counters = nullptr, Triangle* nearest = nullptr) const;
  /// The box translating by d, from tStart to 1: its first contact (triangle_sweep.h per triangle).
  MeshSweepHit sweep(const Obb<double>& box, const Vec3<double>& d, double tStart = 0.0,
                     MeshQueryCounters* counters = nullptr) const;
  /// A time before which the box moving by d (from t 0) touches no triangle: +infinity when it
  /// touches none over the whole motion, else at most the first contact (never late; it may be
  /// early). The same search as sweep(), stopped at the first contact it finds (CoherentSweep's
  /// look-ahead needs no more).
  double freeUntil(const Obb<double>& box, const Vec3<double>& d, MeshQueryCounters* counters = nullptr) const;

  const std::vector<MeshTreeNode<Volume>>& nodes() const { return nodes_; }
  /// The triangles in leaf order (a leaf's triangles are contiguous).
  const std::vector<Triangle>& triangles() const { return triangles_; }
  int depth() const { return depth_; }  // levels below the root of the deepest leaf
  /// The largest |coordinate| of the triangles' corners: what sweepBoxTriangleSlack needs.
  double reach() const { return reach_; }
  /// Unique to the triangles this tree was built from (a copy keeps it): lets a caller that
  /// remembers answers about a tree (CoherentSweep) tell it from a later tree at the same address.
  std::uint64_t id() const { return id_; }

 private:
  MeshSweepHit search(const Obb<double>& box, const Vec3<double>& d, double tStart, MeshQueryCounters* counters,
                      bool firstFound) const;

  std::vector<MeshTreeNode<Volume>> nodes_;
  std::vector<Triangle> triangles_;
  double reach_ = 0;  // the largest |coordinate| of the triangles' corners (sweep's slack)
  int depth_ = 0;
  std::uint64_t id_ = 0;
};

using KdopTree = MeshTree<Kdop18>;

}  // namespace nestwalk
