// BoxTree's accessors and inspection (the build is in box_tree_build.cpp, the query in
// box_tree_query.cpp).
#include "nestwalk/hierarchy/box_tree_layout.h"

#include <stdexcept>

namespace nestwalk {

std::size_t BoxTree::size() const { return impl_ ? impl_->units : 0; }
std::size_t BoxTree::nodeCount() const { return impl_ ? impl_->nodes.size() : 0; }
int BoxTree::depth() const { return impl_ && impl_->units > 0 ? impl_->depth : 0; }
std::string BoxTree::describe() const { return impl_ ? impl_->description : "empty"; }

std::vector<BoxTree::NodeInfo> BoxTree::nodes() const { return impl_ ? impl_->nodes : std::vector<NodeInfo>{}; }

std::uint32_t BoxTree::unitParent(std::size_t unit) const {
  if (!impl_ || unit >= impl_->units) throw std::out_of_range("BoxTree::unitParent: no unit " + std::to_string(unit));
  return impl_->unitParent[unit];
}

Aabb<double> BoxTree::bounds() const { return impl_ && !impl_->nodes.empty() ? impl_->nodes[0].box : Aabb<double>{}; }

}  // namespace nestwalk
