// BoxTree (box_tree.h): the public class over the build (box_tree_build.h) and the query
// (box_tree_query.h), with the accessors and inspection.
#include "nestwalk/hierarchy/box_tree.h"

#include "nestwalk/hierarchy/box_tree_build.h"
#include "nestwalk/hierarchy/box_tree_query.h"

#include <stdexcept>

namespace nestwalk {

BoxTree BoxTree::buildAuto(std::span<const Aabb<double>> boxes, const AutoTreeOptions& options) {
  auto impl = std::make_shared<Impl>();
  hierarchy_detail::buildAutoTree(*impl, boxes, options);
  BoxTree t;
  t.impl_ = std::move(impl);
  return t;
}

BoxTree BoxTree::buildTemplate(std::span<const Aabb<double>> boxes, std::span<const std::string> groupPaths,
                               const TemplateTreeOptions& options) {
  auto impl = std::make_shared<Impl>();
  hierarchy_detail::buildTemplateTree(*impl, boxes, groupPaths, options);
  BoxTree t;
  t.impl_ = std::move(impl);
  return t;
}

void BoxTree::query(const Aabb<double>& box, std::vector<std::uint32_t>& out, BroadPhaseCounters* counters) const {
  if (impl_) hierarchy_detail::queryTree(*impl_, box, out, counters);
}

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
