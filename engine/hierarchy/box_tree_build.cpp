#include "nestwalk/hierarchy/box_tree_build.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>

namespace nestwalk::hierarchy_detail {

namespace {

constexpr std::size_t kMaxUnits = 0x7fffffffu;  // unit lanes are stored as ~leaf in an int32

/// A thing to place in the tree (a unit, or for templates a subgroup), with float copies of its
/// box and centroid relative to the origin (split heuristics only).
struct Item {
  float c[3];
  float lo[3], hi[3];
  std::uint32_t ref;    // unit index, or group index when isGroup
  std::uint32_t isGroup;
};

struct Rule {
  int degree = 4;
  SplitAxis axis = SplitAxis::LongestSide;
  SplitPoint point = SplitPoint::Median;
};

/// Splits [b, e) (e - b >= 2) into two non-empty parts by `rule`; returns the first index of the
/// second part.
std::uint32_t splitRange(std::vector<Item>& items, std::uint32_t b, std::uint32_t e, const Rule& rule) {
  Item* first = items.data() + b;
  Item* last = items.data() + e;
  const std::uint32_t n = e - b;
  int axis = 0;
  if (rule.axis == SplitAxis::LongestSide) {
    float lo[3] = {first->lo[0], first->lo[1], first->lo[2]};
    float hi[3] = {first->hi[0], first->hi[1], first->hi[2]};
    for (const Item* it = first + 1; it != last; ++it)
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], it->lo[k]);
        hi[k] = std::max(hi[k], it->hi[k]);
      }
    double best = -1;
    for (int k = 0; k < 3; ++k) {
      const double ext = double(hi[k]) - double(lo[k]);
      if (ext > best) best = ext, axis = k;
    }
  } else {
    // Splatter: variance of the centroids, sums shifted by the first centroid against cancellation.
    double s[3] = {0, 0, 0}, q[3] = {0, 0, 0};
    const float c0[3] = {first->c[0], first->c[1], first->c[2]};
    for (const Item* it = first; it != last; ++it)
      for (int k = 0; k < 3; ++k) {
        const double d = double(it->c[k]) - double(c0[k]);
        s[k] += d;
        q[k] += d * d;
      }
    double best = -1;
    for (int k = 0; k < 3; ++k) {
      const double var = q[k] / n - (s[k] / n) * (s[k] / n);
      if (var > best) best = var, axis = k;
    }
  }
  const std::uint32_t half = n / 2;
  auto byAxis = [axis](const Item& a, const Item& b2) { return a.c[axis] < b2.c[axis]; };
  if (rule.point == SplitPoint::Mean) {
    double sum = 0;
    for (const Item* it = first; it != last; ++it) sum += it->c[axis];
    const double mean = sum / n;
    Item* mid = std::partition(first, last, [axis, mean](const Item& it) { return double(it.c[axis]) < mean; });
    if (mid != first && mid != last) return b + std::uint32_t(mid - first);
    // One side empty (all centroids equal along the axis, or rounding): index halves.
  }
  std::nth_element(first, first + half, last, byAxis);
  return b + half;
}

/// The parts of [b, e) for one delta-ary node: log2(degree) rounds of binary splits; ranges of one
/// item are not split further. Returns the number of parts (2..degree) written to `parts`.
int partsOf(std::vector<Item>& items, std::uint32_t b, std::uint32_t e, const Rule& rule,
            std::array<std::pair<std::uint32_t, std::uint32_t>, 8>& parts) {
  int count = 1;
  parts[0] = {b, e};
  for (int width = 1; width < rule.degree; width *= 2) {
    std::array<std::pair<std::uint32_t, std::uint32_t>, 8> next;
    int m = 0;
    for (int i = 0; i < count; ++i) {
      const auto [pb, pe] = parts[std::size_t(i)];
      if (pe - pb >= 2) {
        const std::uint32_t mid = splitRange(items, pb, pe, rule);
        next[std::size_t(m++)] = {pb, mid};
        next[std::size_t(m++)] = {mid, pe};
      } else {
        next[std::size_t(m++)] = {pb, pe};
      }
    }
    parts = next;
    count = m;
  }
  return count;
}

void checkBoxes(std::span<const Aabb<double>> boxes, const char* who) {
  if (boxes.size() > kMaxUnits) throw std::length_error(std::string(who) + ": more than 2^31 - 1 boxes");
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const Aabb<double>& b = boxes[i];
    if (b.min.hasNaN() || b.max.hasNaN() || b.isEmpty())
      throw std::invalid_argument(std::string(who) + ": box " + std::to_string(i) + " is empty or NaN");
  }
}

struct Group {
  std::string path;
  std::int32_t parent = -1;
  std::vector<std::uint32_t> units;                        // direct units
  std::vector<std::pair<bool, std::uint32_t>> children;    // (isGroup, index), first appearance
  Aabb<double> box;
};

class Builder {
 public:
  Builder(TreeData& t, std::span<const Aabb<double>> boxes) : t_(t), boxes_(boxes) {
    Aabb<double> all;
    for (const Aabb<double>& b : boxes) all.extend(b);
    for (int k = 0; k < 3; ++k) {
      const double o = 0.5 * (all.min[k] + all.max[k]);
      t_.origin[k] = std::isfinite(o) ? o : 0.0;
    }
    t_.units = boxes.size();
    t_.unitParent.assign(boxes.size(), 0);
    t_.leaves.reserve(boxes.size());
  }

  Item unitItem(std::uint32_t i) const { return makeItem(boxes_[i], i, false); }
  Item groupItem(std::uint32_t g, const Aabb<double>& box) const { return makeItem(box, g, true); }

  /// Builds the tree over items [0, n) (auto) or from the groups (template, `groups` non-null).
  void run(const Rule& rule, std::vector<Group>* groups, std::size_t wideLimit) {
    groups_ = groups;
    wideLimit_ = wideLimit;
    // A delta-ary tree over n units has about n / (delta - 1) inner nodes; reserve for delta = 4.
    const std::size_t nodes = items_.size() / 3 + (groups ? groups->size() : 0) + 1;
    t_.nodes.reserve(nodes);
    t_.nodeFirstBlock.reserve(nodes);
    parentSlot_.reserve(nodes);
    t_.blocks.reserve(nodes * std::size_t(rule.degree == 8 ? 2 : 1));
    Work root;
    root.rule = rule;
    if (groups) {
      root.group = 0;
    } else {
      root.begin = 0;
      root.end = std::uint32_t(items_.size());
    }
    stack_.push_back(root);
    while (!stack_.empty()) {
      const Work w = stack_.back();
      stack_.pop_back();
      process(w);
    }
    finish();
  }

  std::vector<Item> items_;

 private:
  struct Work {
    std::uint32_t begin = 0, end = 0;  // item range (group < 0)
    std::int32_t group = -1;           // template group to lay out
    std::int32_t parentNode = -1;
    std::uint32_t parentBlock = 0, parentLane = 0;
    std::uint32_t level = 0;
    bool helper = false;
    Rule rule;
  };

  Item makeItem(const Aabb<double>& box, std::uint32_t ref, bool isGroup) const {
    Item it;
    for (int k = 0; k < 3; ++k) {
      const double lo = box.min[k] - t_.origin[k], hi = box.max[k] - t_.origin[k];
      it.lo[k] = roundDown(lo);
      it.hi[k] = roundUp(hi);
      const double c = 0.5 * (lo + hi);
      it.c[k] = std::isnan(c) ? 0.0f : static_cast<float>(c);
    }
    it.ref = ref;
    it.isGroup = isGroup ? 1u : 0u;
    return it;
  }

  std::uint32_t newNode(const Work& w, int lanes) {
    const std::uint32_t node = std::uint32_t(t_.nodes.size());
    const std::uint32_t first = std::uint32_t(t_.blocks.size());
    const std::uint32_t span = std::uint32_t((lanes + kTreeLanes - 1) / kTreeLanes);
    Block empty;
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < kTreeLanes; ++l) {
        empty.lo[k][l] = std::numeric_limits<float>::infinity();
        empty.hi[k][l] = -std::numeric_limits<float>::infinity();
      }
    for (int l = 0; l < kTreeLanes; ++l) {
      empty.child[l] = kEmptyLane;
      empty.span[l] = 0;
    }
    t_.blocks.insert(t_.blocks.end(), span, empty);
    if (w.parentNode >= 0) {
      Block& pb = t_.blocks[w.parentBlock];
      pb.child[w.parentLane] = std::int32_t(first);
      pb.span[w.parentLane] = span;
    } else {
      t_.rootSpan = span;
    }
    BoxTree::NodeInfo info;
    info.parent = w.parentNode;
    info.level = w.level;
    info.helper = w.helper;
    if (w.group >= 0) info.group = (*groups_)[std::size_t(w.group)].path;
    t_.nodes.push_back(std::move(info));
    t_.nodeFirstBlock.push_back(first);
    parentSlot_.push_back({w.parentBlock, w.parentLane});
    t_.depth = std::max(t_.depth, int(w.level) + 1);
    return node;
  }

  /// Lane `lane` of `node` gets `item`: a leaf for a unit, a pending child node for a group.
  void emitItem(std::uint32_t node, int lane, const Item& item, std::vector<Work>& children) {
    const std::uint32_t block = t_.nodeFirstBlock[node] + std::uint32_t(lane / kTreeLanes);
    const int l = lane % kTreeLanes;
    if (item.isGroup) {
      Work w;
      w.group = std::int32_t(item.ref);
      pendingChild(node, block, l, w, children);
      return;
    }
    Block& b = t_.blocks[block];
    const std::uint32_t slot = std::uint32_t(t_.leaves.size());
    const Aabb<double>& box = boxes_[item.ref];
    Leaf leaf;
    for (int k = 0; k < 3; ++k) {
      leaf.lo[k] = box.min[k];
      leaf.hi[k] = box.max[k];
      b.lo[k][l] = item.lo[k];
      b.hi[k][l] = item.hi[k];
    }
    leaf.unit = item.ref;
    t_.leaves.push_back(leaf);
    b.child[l] = ~std::int32_t(slot);
    b.span[l] = 0;
    t_.unitParent[item.ref] = node;
    t_.nodes[node].childUnits++;
    t_.nodes[node].box.extend(box);
  }

  void pendingChild(std::uint32_t node, std::uint32_t block, int lane, Work w, std::vector<Work>& children) {
    w.parentNode = std::int32_t(node);
    w.parentBlock = block;
    w.parentLane = std::uint32_t(lane);
    w.level = t_.nodes[node].level + 1;
    t_.nodes[node].childNodes++;
    children.push_back(w);
  }

  /// Lays out [b, e) under a new node by `rule` (auto trees, and wide groups' helper subtrees).
  void layoutRange(const Work& w, std::uint32_t b, std::uint32_t e, std::vector<Work>& children) {
    const std::uint32_t n = e - b;
    if (n <= std::uint32_t(w.rule.degree)) {
      const std::uint32_t node = newNode(w, int(n));
      for (std::uint32_t i = 0; i < n; ++i) emitItem(node, int(i), items_[b + i], children);
      return;
    }
    std::array<std::pair<std::uint32_t, std::uint32_t>, 8> parts;
    const int count = partsOf(items_, b, e, w.rule, parts);
    const std::uint32_t node = newNode(w, count);
    for (int i = 0; i < count; ++i) {
      const auto [pb, pe] = parts[std::size_t(i)];
      if (pe - pb == 1) {
        emitItem(node, i, items_[pb], children);
      } else {
        Work c;
        c.begin = pb;
        c.end = pe;
        c.rule = w.rule;
        c.helper = w.helper || w.group >= 0;  // below a template group: helper nodes
        pendingChild(node, t_.nodeFirstBlock[node] + std::uint32_t(i / kTreeLanes), i % kTreeLanes, c, children);
      }
    }
  }

  void process(const Work& w) {
    std::vector<Work>& children = children_;
    children.clear();
    if (w.group < 0) {
      layoutRange(w, w.begin, w.end, children);
    } else {
      const Group& g = (*groups_)[std::size_t(w.group)];
      const std::uint32_t b = std::uint32_t(items_.size());
      for (const auto& [isGroup, idx] : g.children)
        items_.push_back(isGroup ? groupItem(idx, (*groups_)[idx].box) : unitItem(idx));
      const std::uint32_t e = std::uint32_t(items_.size());
      if (wideLimit_ > 0 && e - b > wideLimit_) {
        Work h = w;
        h.rule = Rule{4, SplitAxis::LongestSide, SplitPoint::Median};
        layoutRange(h, b, e, children);
      } else {
        const std::uint32_t node = newNode(w, int(e - b));
        for (std::uint32_t i = b; i < e; ++i) emitItem(node, int(i - b), items_[i], children);
      }
    }
    // Depth first: the first child is processed next.
    for (auto it = children.rbegin(); it != children.rend(); ++it) stack_.push_back(*it);
  }

  /// Bottom up (children come after their parents): each node's float box into its parent's
  /// lane, each node's double box into its parent's.
  void finish() {
    for (std::size_t node = t_.nodes.size(); node-- > 1;) {
      const std::uint32_t first = t_.nodeFirstBlock[node];
      const std::uint32_t end = node + 1 < t_.nodes.size() ? t_.nodeFirstBlock[node + 1] : std::uint32_t(t_.blocks.size());
      float lo[3], hi[3];
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::numeric_limits<float>::infinity();
        hi[k] = -std::numeric_limits<float>::infinity();
      }
      for (std::uint32_t bi = first; bi < end; ++bi)
        for (int k = 0; k < 3; ++k)
          for (int l = 0; l < kTreeLanes; ++l) {
            lo[k] = std::min(lo[k], t_.blocks[bi].lo[k][l]);
            hi[k] = std::max(hi[k], t_.blocks[bi].hi[k][l]);
          }
      const auto [pb, pl] = parentSlot_[node];
      for (int k = 0; k < 3; ++k) {
        t_.blocks[pb].lo[k][pl] = lo[k];
        t_.blocks[pb].hi[k][pl] = hi[k];
      }
      const std::int32_t parent = t_.nodes[node].parent;
      t_.nodes[std::size_t(parent)].box.extend(t_.nodes[node].box);
    }
  }

  TreeData& t_;
  std::span<const Aabb<double>> boxes_;
  std::vector<Group>* groups_ = nullptr;
  std::size_t wideLimit_ = 0;
  std::vector<Work> stack_, children_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> parentSlot_;
};

}  // namespace

void buildAutoTree(TreeData& tree, std::span<const Aabb<double>> boxes, const AutoTreeOptions& options) {
  if (options.degree != 2 && options.degree != 4 && options.degree != 8)
    throw std::invalid_argument("BoxTree::buildAuto: degree must be 2, 4 or 8, got " + std::to_string(options.degree));
  checkBoxes(boxes, "BoxTree::buildAuto");
  TreeData* impl = &tree;
  Builder b(tree, boxes);
  b.items_.reserve(boxes.size());
  for (std::uint32_t i = 0; i < boxes.size(); ++i) b.items_.push_back(b.unitItem(i));
  b.run(Rule{options.degree, options.axis, options.point}, nullptr, 0);
  impl->description = "auto delta=" + std::to_string(options.degree) + " " + splitAxisName(options.axis) + "/" +
                      splitPointName(options.point);
}

void buildTemplateTree(TreeData& tree, std::span<const Aabb<double>> boxes, std::span<const std::string> groupPaths,
                       const TemplateTreeOptions& options) {
  checkBoxes(boxes, "BoxTree::buildTemplate");
  if (groupPaths.size() != boxes.size())
    throw std::invalid_argument("BoxTree::buildTemplate: " + std::to_string(groupPaths.size()) + " group paths for " +
                                std::to_string(boxes.size()) + " boxes");
  std::vector<Group> groups(1);  // the root, path ""
  std::unordered_map<std::string, std::uint32_t> byPath;  // normalized path -> group
  std::unordered_map<std::string, std::uint32_t> byRaw;   // path as given -> group
  byPath.emplace("", 0);
  for (std::uint32_t i = 0; i < boxes.size(); ++i) {
    const std::string& raw = groupPaths[i];
    std::uint32_t g;
    if (const auto it = byRaw.find(raw); it != byRaw.end()) {
      g = it->second;
    } else {
      g = 0;
      std::string prefix;
      std::size_t pos = 0;
      while (pos <= raw.size()) {
        std::size_t slash = raw.find('/', pos);
        if (slash == std::string::npos) slash = raw.size();
        if (slash > pos) {
          if (!prefix.empty()) prefix += '/';
          prefix.append(raw, pos, slash - pos);
          const auto [it2, added] = byPath.emplace(prefix, std::uint32_t(groups.size()));
          if (added) {
            Group ng;
            ng.path = prefix;
            ng.parent = std::int32_t(g);
            groups.push_back(std::move(ng));
            groups[g].children.push_back({true, it2->second});
          }
          g = it2->second;
        }
        pos = slash + 1;
      }
      byRaw.emplace(raw, g);
    }
    groups[g].children.push_back({false, i});
    groups[g].box.extend(boxes[i]);
  }
  // Group boxes bottom up (a group is created after its parent): exact unions of unit boxes.
  for (std::size_t g = groups.size(); g-- > 1;) groups[std::size_t(groups[g].parent)].box.extend(groups[g].box);

  TreeData* impl = &tree;
  Builder b(tree, boxes);
  b.items_.reserve(boxes.size() + groups.size());
  b.run(Rule{}, &groups, options.wideGroupChildren);
  std::size_t helpers = 0;
  for (const BoxTree::NodeInfo& n : impl->nodes) helpers += n.helper ? 1 : 0;
  impl->description = "template";
  if (helpers > 0)
    impl->description += " (+" + std::to_string(helpers) + " helper nodes under groups wider than " +
                         std::to_string(options.wideGroupChildren) + ")";
}

}  // namespace nestwalk::hierarchy_detail
