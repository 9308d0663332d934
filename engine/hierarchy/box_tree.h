// Broad phase: a hierarchy over the collision units' outer AABBs (local frame, metres).
//
// Two ways to build it (as in the fACT framework, "Bounding volume hierarchies for collision
// detection"):
//  - automatically, top-down, with branching factor delta = 2, 4 or 8: a node's boxes are split
//    along one axis chosen by a rule (the longest side of the node's box, or the axis of largest
//    centroid variance, "splatter", Klosowski et al. 1998), at the mean or the median of
//    the centroids; a delta-ary node is made by repeated binary splits (delta = 4: split, then
//    split each half), recursively until a part holds at most delta units, which become the node's
//    leaves. A mean split that leaves one side empty (e.g. all centroids equal) splits the index
//    range in halves instead, so the build always terminates; the median split never needs to.
//  - from a template: the units' group paths ("bench3/station7") form the tree, one node per group,
//    each group's box the union of its members' boxes (the union of exact boxes is exact: nothing
//    grows at merges).
//
// A query with a box (the viewer's swept outer AABB) returns every unit whose AABB overlaps it;
// boxes are closed (touching overlaps). The leaf-level test of a unit's AABB is stage 1 of the
// nested test (AABB-AABB), so it is counted there; the tests of inner nodes are the hierarchy's own
// BV tests (Nv of the broad phase). As in fACT ("the root of S-T can be omitted") the
// root's own box is not tested: a query starts with the root's children.
//
// Exactness: the answer is exactly that of the brute-force closed test in double,
//   a.min <= b.max && b.min <= a.max on x, y and z,
// on the boxes given to the build. The tree stores its boxes as float relative to its own origin
// (the centre of all boxes), rounded outward, and tests them 4 at a time with SSE as a
// conservative filter; a unit that passes is decided by the double test on its stored double box
// (box_tree_query.cpp gives the argument). So UTM-sized coordinates (5.5e5, 4.65e6) lose nothing.
//
// Layout: flat arrays, no pointers; an inner node is one or more consecutive 4-lane blocks, each
// block holding its lanes' float boxes field by field next to their child references (2 cache
// lines); delta = 2 uses 2 lanes of one block, delta = 4 one block, delta = 8 two blocks.
// Nodes are stored depth first, so a subtree's blocks are contiguous.
//
// Bad input: buildAuto/buildTemplate throw std::invalid_argument for an empty or NaN box, a degree
// other than 2, 4, 8, or (template) a path count different from the box count, and
// std::length_error beyond 2^31 - 1 units. A query box must not be NaN (a NaN box finds nothing);
// an inverted box (min > max) is answered by the same closed formula as above.
// A built tree is immutable and may be queried from several threads at once.
// Copies of a BoxTree share its built data (a shared_ptr to const). `out` and `counters` of query()
// are the caller's: one per querying thread.
#pragma once

#include "nestwalk/geometry/volumes.h"
#include "nestwalk/hierarchy/tree_options.h"

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace nestwalk {

/// Template trees: a group with more than `wideGroupChildren` children (units and subgroups) gets
/// its children arranged under helper nodes, built like an automatic 4-ary longest-side/median
/// tree over those children, instead of being tested flat (a flat group of n children costs n/4
/// block tests per visit; 64 = 16 blocks, where a 4-ary subtree starts to be cheaper on walks).
/// Helper nodes are inner nodes (counted by nodeCount() and nodeTests) with `helper` set in
/// nodes(). 0: never split (every group is one flat node, whatever its width).
struct TemplateTreeOptions {
  std::size_t wideGroupChildren = 64;
};

struct BroadPhaseCounters {
  std::uint64_t nodeTests = 0;  // box tests against inner nodes (the hierarchy's Nv)
  std::uint64_t leafTests = 0;  // box tests against units' AABBs (stage 1 AABB-AABB)
  std::uint64_t leafHits = 0;   // units reported
  void clear() { *this = {}; }
};

class BoxTree {
 public:
  BoxTree() = default;

  // Boxes must not be empty or NaN (callers check). Builds in O(n log n).
  static BoxTree buildAuto(std::span<const Aabb<double>> boxes, const AutoTreeOptions& options = {});
  // groupPaths[i]: unit i's group path, '/'-separated ("" = directly under the root).
  // Children of a group: its subgroups and units, in order of first appearance in groupPaths.
  // Empty path components ("a//b", "/a", "a/") are ignored, so "/a/" is the group "a".
  static BoxTree buildTemplate(std::span<const Aabb<double>> boxes, std::span<const std::string> groupPaths,
                               const TemplateTreeOptions& options = {});

  // Appends to `out` the indices of all units whose AABB overlaps `box` (closed), in a fixed order
  // for a given tree and box. Allocates nothing once `out` has capacity.
  void query(const Aabb<double>& box, std::vector<std::uint32_t>& out, BroadPhaseCounters* counters = nullptr) const;

  std::size_t size() const;       // units
  std::size_t nodeCount() const;  // inner nodes, root included (an empty tree has its root: 1)
  int depth() const;              // levels of inner nodes (a single leaf level: 1; empty tree: 0)
  std::string describe() const;   // e.g. "auto delta=4 longest/median" or "template"

  /// Inspection (tests, reports): one entry per inner node, depth first (index 0 is the root).
  struct NodeInfo {
    Aabb<double> box;         // exact union of the double boxes of all units below (empty: none)
    std::int32_t parent = -1;  // index of the parent node, -1 for the root
    std::uint32_t level = 0;  // 0 for the root
    std::uint32_t childNodes = 0, childUnits = 0;
    bool helper = false;      // a template helper node under a wide group (see TemplateTreeOptions)
    std::string group;        // template: the group path ("" for the root and helpers); auto: ""
  };
  std::vector<NodeInfo> nodes() const;
  /// The node whose child unit `unit` is.
  std::uint32_t unitParent(std::size_t unit) const;
  /// The union of all boxes (empty for an empty tree).
  Aabb<double> bounds() const;

 private:
  struct Impl;
  std::shared_ptr<const Impl> impl_;
};

}  // namespace nestwalk
