// Building a BoxTree (see box_tree.h): automatic top-down delta-ary trees and template trees.
//
// Automatic trees follow the ABVHCD of the fACT framework ("Bounding volume hierarchies for
// collision detection", section 3: "parent volume is split in delta parts ... if the number of
// primitives is equal or less than delta, leaf nodes for primitives are constructed") with the
// splitting rules of Klosowski et al. 1998 (longest side or splatter = largest centroid variance;
// cut at the mean or the median). A delta-ary node is made of log2(delta) rounds of binary splits
// of its units; a part with one unit becomes a leaf lane, a larger part a child node. Each binary
// split is one pass for the statistics it needs plus std::nth_element (median) or std::partition
// (mean) over a range of 40-byte items, so a level of the tree costs O(n) and the build O(n log n)
// for median splits (mean splits on very skewed data can be deeper, never worse than O(n^2/delta),
// and always terminate: an empty side makes the split fall back to index halves).
//
// Split decisions use float copies of the boxes relative to the tree's origin (a heuristic: the
// tree's correctness does not depend on where it splits). The stored node boxes are computed
// afterwards, bottom up, as the exact union of the children's outward-rounded float boxes, and
// the per-node double boxes (NodeInfo::box) as the exact union of the double unit boxes.
// The build is iterative (explicit work stack), so deep trees cannot overflow the call stack.
//
// Internal to the hierarchy module: BoxTree::buildAuto and BoxTree::buildTemplate (box_tree.h)
// call these; their bad-input rules are box_tree.h's.
// Thread safety: each call reads its arguments and fills only the `tree` it is given.
#pragma once

#include "nestwalk/hierarchy/box_tree_layout.h"

#include <span>
#include <string>

namespace nestwalk::hierarchy_detail {

/// Fills an empty `tree` with the automatic delta-ary tree over `boxes`.
void buildAutoTree(TreeData& tree, std::span<const Aabb<double>> boxes, const AutoTreeOptions& options);

/// Fills an empty `tree` with the template tree of `groupPaths` (one per box).
void buildTemplateTree(TreeData& tree, std::span<const Aabb<double>> boxes, std::span<const std::string> groupPaths,
                       const TemplateTreeOptions& options);

}  // namespace nestwalk::hierarchy_detail
