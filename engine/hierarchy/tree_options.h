// How an automatic broad-phase hierarchy is built (box_tree.h): the branching factor and the
// splitting rule. Its own small header so that a scene file can name the choice without the tree.
// Thread safety: plain values and pure functions.
#pragma once

#include <cstdint>

namespace nestwalk {

enum class SplitAxis : std::uint8_t { LongestSide, Splatter };
enum class SplitPoint : std::uint8_t { Mean, Median };

const char* splitAxisName(SplitAxis a);    // "longest", "splatter"
const char* splitPointName(SplitPoint p);  // "mean", "median"

struct AutoTreeOptions {
  int degree = 8;  // delta: 2, 4 or 8 children per inner node (8: fewest node tests per query, see
                   // `nestwalk bench walker`)
  SplitAxis axis = SplitAxis::LongestSide;
  SplitPoint point = SplitPoint::Median;
};

}  // namespace nestwalk
