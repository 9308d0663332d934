// The query of a BoxTree (BoxTree::query, box_tree.h): depth-first traversal of the 4-lane blocks with SSE.
//
// Why the float filter loses no hit (the answer equals the double brute force exactly)
// ----------------------------------------------------------------------------------
// Every stored float coordinate is f(x) = roundDown(fl(x - o)) for a min corner and
// roundUp(fl(x - o)) for a max corner, o the tree's origin, fl the double subtraction rounded to
// nearest. fl(. - o) is monotone (non-decreasing) in x, and roundDown(y) <= y <= roundUp(y). The
// query box is converted the same way. If a unit overlaps the query in double on an axis,
//   unit.min <= q.max  =>  roundDown(fl(unit.min - o)) <= fl(unit.min - o) <= fl(q.max - o)
//                          <= roundUp(fl(q.max - o)),
// and likewise for q.min <= unit.max: the float boxes overlap too. An inner node's float box is
// the exact min/max of its children's float boxes, so it contains them and overlaps the query
// whenever one of them does; the traversal therefore reaches every unit that overlaps in double.
// A unit whose float box passes is then decided by the closed double test on its stored double
// box, so false positives of the filter (float rounding near touching, up to one float ulp of the
// offset from o, i.e. ~6e-4 m at 10 km from o) are removed. No tolerance is involved: no named
// slack, nothing to tune. The argument needs no bound on the rounding, so it holds at any
// magnitude (UTM coordinates, coordinates beyond the float range become +-infinity, still
// outward).
//
// Order: within a node, blocks in order and lanes in increasing order; units are reported as their
// block is tested; the first child node hit is visited next, the other hit child nodes wait on a
// LIFO stack. Fixed for a given tree and box.
// Memory: a fixed stack of kStackEntries pending nodes on the call stack; when it is full (only in
// very deep or very wide trees) the node is traversed by a recursive call instead, so nothing is
// allocated and every node is still visited.
// Thread safety: reads `tree` only; safe from several threads at once, each with its own `out` and
// `counters`.
#pragma once

#include "nestwalk/hierarchy/box_tree_layout.h"

#include <cstdint>
#include <vector>

namespace nestwalk::hierarchy_detail {

/// Appends to `out` every unit of `tree` whose box overlaps `box` (closed), in the order above,
/// exactly as the double brute force decides; counts into `counters` when given.
void queryTree(const TreeData& tree, const Aabb<double>& box, std::vector<std::uint32_t>& out,
               BroadPhaseCounters* counters);

}  // namespace nestwalk::hierarchy_detail
