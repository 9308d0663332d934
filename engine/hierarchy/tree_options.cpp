#include "nestwalk/hierarchy/tree_options.h"

namespace nestwalk {

const char* splitAxisName(SplitAxis a) { return a == SplitAxis::LongestSide ? "longest" : "splatter"; }
const char* splitPointName(SplitPoint p) { return p == SplitPoint::Mean ? "mean" : "median"; }

}  // namespace nestwalk
