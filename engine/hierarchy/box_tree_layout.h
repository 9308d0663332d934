// Internal: the flat storage of a BoxTree, shared by the build (box_tree_build.cpp), the query
// (box_tree_query.cpp) and the inspection functions (box_tree.cpp). Not part of the public API.
//
// An inner node is `span` consecutive blocks of kTreeLanes lanes; a lane is a child: an inner node
// (child >= 0: index of its first block, span[lane] its block count), a unit (child < 0: ~index
// into `leaves`), or nothing (kEmptyLane, with an empty float box that no query overlaps).
// Float boxes are relative to `origin` and rounded outward (see box_tree_query.cpp).
// Thread safety: plain data, written only by the build; read-only once the BoxTree holds it.
#pragma once

#include "nestwalk/geometry/volumes.h"
#include "nestwalk/hierarchy/box_tree.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace nestwalk::hierarchy_detail {

inline constexpr int kTreeLanes = 4;  // one SSE register of floats
inline constexpr std::int32_t kEmptyLane = std::numeric_limits<std::int32_t>::max();

struct alignas(64) Block {
  float lo[3][kTreeLanes];  // lo[axis][lane]: min corner, relative to the origin, rounded down
  float hi[3][kTreeLanes];  // max corner, rounded up
  std::int32_t child[kTreeLanes];
  std::uint32_t span[kTreeLanes];
};
static_assert(sizeof(Block) == 128, "a block is two cache lines");

/// A unit's exact box (absolute coordinates, as given) and its index, in depth-first order.
struct Leaf {
  double lo[3], hi[3];
  std::uint32_t unit;
};

struct TreeData {
  std::vector<Block> blocks;  // root first: blocks [0, rootSpan)
  std::uint32_t rootSpan = 0;
  std::vector<Leaf> leaves;
  std::vector<BoxTree::NodeInfo> nodes;       // depth first, parallel to the nodes' first blocks
  std::vector<std::uint32_t> nodeFirstBlock;  // per node
  std::vector<std::uint32_t> unitParent;      // per unit
  double origin[3] = {0, 0, 0};
  std::size_t units = 0;
  int depth = 0;
  std::string description;
};

/// The next float above f (f itself for NaN and +inf); bit arithmetic, no libm call (the query
/// rounds its 6 coordinates with it on every call).
inline float nextUp(float f) {
  if (f != f || f == std::numeric_limits<float>::infinity()) return f;
  if (f == 0.0f) return std::numeric_limits<float>::denorm_min();
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(f);
  return std::bit_cast<float>(f > 0.0f ? bits + 1 : bits - 1);
}
inline float nextDown(float f) { return -nextUp(-f); }

/// The largest float <= x (-inf below the float range); NaN stays NaN.
inline float roundDown(double x) {
  const float f = static_cast<float>(x);
  return static_cast<double>(f) > x ? nextDown(f) : f;
}
/// The smallest float >= x (+inf above the float range); NaN stays NaN.
inline float roundUp(double x) {
  const float f = static_cast<float>(x);
  return static_cast<double>(f) < x ? nextUp(f) : f;
}

}  // namespace nestwalk::hierarchy_detail

namespace nestwalk {
struct BoxTree::Impl : hierarchy_detail::TreeData {};
}  // namespace nestwalk
