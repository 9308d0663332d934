// BoxTree (engine/hierarchy/box_tree.h) against brute force: every query's hits must be exactly
// the units whose double boxes overlap the query box (closed), for every automatic rule and for
// template trees, at the origin and at UTM magnitudes; plus the structure (node boxes are the exact
// unions of their units, at most delta children, template nodes one per group prefix).
#include "nestwalk/hierarchy/box_tree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace nestwalk {
namespace {

using Box = Aabb<double>;
using Hits = std::vector<std::uint32_t>;

const Eigen::Vector3d kUtm(5.5e5, 4.65e6, 0.0);  // a UTM-like map position (zone easting, northing)

Hits bruteForce(const std::vector<Box>& boxes, const Box& q) {
  Hits h;
  for (std::uint32_t i = 0; i < boxes.size(); ++i) {
    const Box& b = boxes[i];
    if ((b.min.array() <= q.max.array()).all() && (q.min.array() <= b.max.array()).all()) h.push_back(i);
  }
  return h;
}

Hits sorted(Hits h) {
  std::sort(h.begin(), h.end());
  return h;
}

/// Random boxes in a cube of side `extent` at `offset`: sizes log-uniform 0.05 .. 12 m, every 10th
/// box flat, a line or a point (zero extents).
std::vector<Box> randomBoxes(std::size_t n, double extent, const Eigen::Vector3d& offset, std::uint32_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Box> boxes;
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Vector3d lo = offset + extent * Eigen::Vector3d(u(rng), u(rng), u(rng));
    Eigen::Vector3d size;
    for (int k = 0; k < 3; ++k) size[k] = 0.05 * std::pow(240.0, u(rng));
    if (i % 10 == 0) size[int(i / 10) % 3] = 0;
    if (i % 30 == 0) size.setZero();
    boxes.push_back({lo, lo + size});
  }
  return boxes;
}

/// Query boxes like the walker's: 0.5 x 0.5 x 1.8 m swept up to 1 m, and some larger ones.
std::vector<Box> randomQueries(std::size_t n, double extent, const Eigen::Vector3d& offset, std::uint32_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Box> qs;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d lo = offset + extent * Eigen::Vector3d(u(rng), u(rng), u(rng));
    Eigen::Vector3d size(0.5 + u(rng), 0.5 + u(rng), 1.8 + u(rng));
    if (i % 7 == 0) size *= 10;
    if (i % 11 == 0) size.setZero();  // a point query
    qs.push_back({lo, lo + size});
  }
  return qs;
}

/// Checks every query against brute force (same hits; the same order when asked twice) and the
/// counters' consistency. Returns the total hits.
std::size_t expectMatchesBruteForce(const BoxTree& tree, const std::vector<Box>& boxes, const std::vector<Box>& queries) {
  std::size_t total = 0;
  Hits out, again;
  for (std::size_t qi = 0; qi < queries.size(); ++qi) {
    out.clear();
    again.clear();
    BroadPhaseCounters c;
    tree.query(queries[qi], out, &c);
    tree.query(queries[qi], again);
    EXPECT_EQ(out, again) << tree.describe() << " query " << qi << ": order not fixed";
    const Hits expected = bruteForce(boxes, queries[qi]);
    EXPECT_EQ(sorted(out), expected) << tree.describe() << " query " << qi;
    EXPECT_EQ(c.leafHits, out.size());
    EXPECT_GE(c.leafTests, c.leafHits);
    EXPECT_EQ(std::set<std::uint32_t>(out.begin(), out.end()).size(), out.size()) << "duplicates";
    total += out.size();
  }
  return total;
}

/// Node boxes are the exact unions of the units below them; unit parents and child counts agree.
void expectExactNodeBoxes(const BoxTree& tree, const std::vector<Box>& boxes) {
  const std::vector<BoxTree::NodeInfo> nodes = tree.nodes();
  ASSERT_EQ(nodes.size(), tree.nodeCount());
  std::vector<Box> expected(nodes.size());
  std::vector<std::uint32_t> units(nodes.size(), 0), childNodes(nodes.size(), 0);
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    std::int64_t n = tree.unitParent(i);
    ++units[std::size_t(n)];
    for (; n >= 0; n = nodes[std::size_t(n)].parent) expected[std::size_t(n)].extend(boxes[i]);
  }
  for (std::size_t n = 1; n < nodes.size(); ++n) {
    ASSERT_LT(nodes[n].parent, std::int32_t(n)) << "parents come first (depth first order)";
    ++childNodes[std::size_t(nodes[n].parent)];
    EXPECT_EQ(nodes[n].level, nodes[std::size_t(nodes[n].parent)].level + 1);
  }
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    EXPECT_EQ(nodes[n].box.min, expected[n].min) << "node " << n;
    EXPECT_EQ(nodes[n].box.max, expected[n].max) << "node " << n;
    EXPECT_EQ(nodes[n].childUnits, units[n]);
    EXPECT_EQ(nodes[n].childNodes, childNodes[n]);
  }
  if (!boxes.empty()) {
    EXPECT_EQ(tree.bounds().min, expected[0].min);
    EXPECT_EQ(tree.bounds().max, expected[0].max);
  }
}

struct Rule {
  int degree;
  SplitAxis axis;
  SplitPoint point;
};
std::vector<Rule> allRules() {
  std::vector<Rule> r;
  for (int d : {2, 4, 8})
    for (SplitAxis a : {SplitAxis::LongestSide, SplitAxis::Splatter})
      for (SplitPoint p : {SplitPoint::Mean, SplitPoint::Median}) r.push_back({d, a, p});
  return r;
}
BoxTree build(const std::vector<Box>& boxes, const Rule& r) {
  return BoxTree::buildAuto(boxes, AutoTreeOptions{r.degree, r.axis, r.point});
}

void expectAutoStructure(const BoxTree& tree, const Rule& r, std::size_t n) {
  for (const BoxTree::NodeInfo& node : tree.nodes()) {
    EXPECT_LE(node.childNodes + node.childUnits, std::uint32_t(r.degree)) << tree.describe();
    if (n >= 2) {
      EXPECT_GE(node.childNodes + node.childUnits, 2u) << tree.describe();
    }
  }
}

class AutoRules : public ::testing::TestWithParam<bool> {};  // false: origin, true: UTM

TEST_P(AutoRules, RandomSetsMatchBruteForce) {
  const Eigen::Vector3d offset = GetParam() ? kUtm : Eigen::Vector3d::Zero();
  const std::vector<Box> boxes = randomBoxes(3000, 80.0, offset, 7);
  const std::vector<Box> queries = randomQueries(400, 80.0, offset, 8);
  std::size_t reference = 0;
  for (const Rule& r : allRules()) {
    const BoxTree tree = build(boxes, r);
    EXPECT_EQ(tree.size(), boxes.size());
    const std::size_t hits = expectMatchesBruteForce(tree, boxes, queries);
    if (reference == 0) reference = hits;
    EXPECT_EQ(hits, reference);
    expectExactNodeBoxes(tree, boxes);
    expectAutoStructure(tree, r, boxes.size());
    // Median splits are balanced: depth about log_delta(n / delta) + 1.
    if (r.point == SplitPoint::Median) {
      EXPECT_LE(tree.depth(), int(std::ceil(std::log(double(boxes.size())) / std::log(double(r.degree)))) + 1)
          << tree.describe();
    }
  }
  EXPECT_GT(reference, 100u) << "the query set should hit something";
}

INSTANTIATE_TEST_SUITE_P(OriginAndUtm, AutoRules, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& i) { return i.param ? "Utm" : "Origin"; });

TEST(BoxTree, CountersSensible) {
  const std::vector<Box> boxes = randomBoxes(5000, 500.0, Eigen::Vector3d::Zero(), 3);
  const BoxTree tree = BoxTree::buildAuto(boxes);
  BroadPhaseCounters c;
  Hits out;
  for (const Box& q : randomQueries(200, 500.0, Eigen::Vector3d::Zero(), 4)) tree.query(q, out, &c);
  EXPECT_GT(c.nodeTests, 0u);
  EXPECT_GE(c.leafTests, c.leafHits);
  EXPECT_EQ(c.leafHits, out.size());
  // A hierarchy tests far fewer boxes than brute force (200 x 5000).
  EXPECT_LT(c.nodeTests + c.leafTests, 200u * 5000u / 10u);
  c.clear();
  EXPECT_EQ(c.nodeTests + c.leafTests + c.leafHits, 0u);
}

/// Unit cubes on a grid sharing faces exactly: a query equal to one cube touches its 26
/// neighbours (closed boxes), one nudged by an ulp inward touches only itself.
TEST(BoxTree, SharedFacesTouch) {
  for (const Eigen::Vector3d& offset : {Eigen::Vector3d(0, 0, 0), kUtm}) {
    const double step = 0.1;  // not a float: the grid lines are rounded doubles at UTM
    std::vector<double> grid;
    for (int i = 0; i <= 6; ++i) grid.push_back(offset.x() + i * step);
    std::vector<double> gy, gz;
    for (int i = 0; i <= 6; ++i) gy.push_back(offset.y() + i * step), gz.push_back(offset.z() + i * step);
    std::vector<Box> boxes;
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j)
        for (int k = 0; k < 6; ++k)
          boxes.push_back({{grid[i], gy[j], gz[k]}, {grid[i + 1], gy[j + 1], gz[k + 1]}});
    for (const Rule& r : allRules()) {
      const BoxTree tree = build(boxes, r);
      const Box& centre = boxes[std::size_t((2 * 6 + 2) * 6 + 2)];
      Hits out;
      tree.query(centre, out);
      EXPECT_EQ(out.size(), 27u) << tree.describe();
      Box inner = centre;
      for (int a = 0; a < 3; ++a) {
        inner.min[a] = std::nextafter(inner.min[a], 1e300);
        inner.max[a] = std::nextafter(inner.max[a], -1e300);
      }
      out.clear();
      tree.query(inner, out);
      EXPECT_EQ(out, Hits{std::uint32_t((2 * 6 + 2) * 6 + 2)}) << tree.describe();
      // A point query at a shared corner touches the 8 cubes around it.
      const Eigen::Vector3d corner(grid[3], gy[3], gz[3]);
      out.clear();
      tree.query({corner, corner}, out);
      EXPECT_EQ(out.size(), 8u) << tree.describe();
      expectMatchesBruteForce(tree, boxes, {centre, inner, Box{corner, corner}});
    }
  }
}

/// Tiny query boxes at UTM magnitudes: float spacing there is 0.0625 m (x) and 0.5 m (y) in
/// absolute terms, but the tree keeps offsets from its origin and decides in double, so queries
/// exactly touching a box are found and those one double ulp away are not.
TEST(BoxTree, TinyQueriesAtUtm) {
  std::vector<Box> boxes = randomBoxes(2000, 50.0, kUtm, 11);
  // Spread far apart too, so the origin offsets are large (kilometres).
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d lo = kUtm + Eigen::Vector3d(-5000.0 + 50.0 * i, 4000.0 - 37.0 * i, 0.3 * i);
    boxes.push_back({lo, lo + Eigen::Vector3d(0.05, 0.05, 3.0)});
  }
  std::vector<Box> queries;
  const double tiny = 1e-6;  // metres
  for (std::size_t i = 0; i < boxes.size(); i += 3) {
    const Box& b = boxes[i];
    const Eigen::Vector3d onMax = b.max, onMin = b.min;
    queries.push_back({onMax, onMax});                                             // the max corner
    queries.push_back({onMin - Eigen::Vector3d::Constant(tiny), onMin});           // ends on the min corner
    Eigen::Vector3d past = b.max;
    past.x() = std::nextafter(past.x(), 1e300);
    queries.push_back({past, past + Eigen::Vector3d::Constant(tiny)});             // one ulp beyond in x
    Eigen::Vector3d before = b.min;
    before.y() = std::nextafter(before.y(), -1e300);
    queries.push_back({before - Eigen::Vector3d::Constant(tiny), before});         // one ulp before in y
  }
  for (const Rule& r : allRules()) {
    const BoxTree tree = build(boxes, r);
    expectMatchesBruteForce(tree, boxes, queries);
  }
  // The corner queries hit their own box at least.
  const BoxTree tree = BoxTree::buildAuto(boxes);
  Hits out;
  tree.query({boxes[0].max, boxes[0].max}, out);
  EXPECT_NE(std::find(out.begin(), out.end(), 0u), out.end());
}

TEST(BoxTree, ZeroSizeIdenticalAndEqualCentroids) {
  for (const Eigen::Vector3d& offset : {Eigen::Vector3d(0, 0, 0), kUtm}) {
    // Points and lines only.
    std::vector<Box> points;
    for (int i = 0; i < 300; ++i) {
      const Eigen::Vector3d p = offset + Eigen::Vector3d(i % 7, (i / 7) % 5, i % 3);
      Eigen::Vector3d q = p;
      if (i % 4 == 0) q.z() += 2.0;  // a vertical line (pole)
      points.push_back({p, q});
    }
    // 200 identical boxes.
    std::vector<Box> same(200, Box{offset, offset + Eigen::Vector3d(1, 2, 3)});
    // Nested boxes with one centroid (all centroids equal).
    std::vector<Box> nested;
    for (int i = 0; i < 500; ++i) {
      const Eigen::Vector3d h = Eigen::Vector3d(0.01 * (i + 1), 0.02 * (i % 13 + 1), 0.5);
      nested.push_back({offset - h, offset + h});
    }
    for (const std::vector<Box>* set : {&points, &same, &nested}) {
      std::vector<Box> queries = randomQueries(100, 10.0, offset - Eigen::Vector3d::Constant(2.0), 5);
      queries.push_back({offset, offset});
      queries.push_back({offset + Eigen::Vector3d(1, 2, 3), offset + Eigen::Vector3d(1, 2, 3)});
      for (const Rule& r : allRules()) {
        const BoxTree tree = build(*set, r);
        expectMatchesBruteForce(tree, *set, queries);
        expectExactNodeBoxes(tree, *set);
        expectAutoStructure(tree, r, set->size());
        // Index halves keep even degenerate sets balanced.
        EXPECT_LE(tree.depth(), int(std::ceil(std::log(double(set->size())) / std::log(double(r.degree)))) + 1)
            << tree.describe();
      }
    }
    Hits out;
    build(same, allRules()[0]).query({offset, offset}, out);
    EXPECT_EQ(out.size(), 200u);
  }
}

/// Centroids growing geometrically: mean splits peel off a few units per level (a deep, lopsided
/// tree); it must still terminate and answer exactly.
TEST(BoxTree, SkewedMeanSplits) {
  std::vector<Box> boxes;
  for (int i = 0; i < 120; ++i) {
    const double x = std::ldexp(1.0, i);
    boxes.push_back({{x, 0, 0}, {x * 1.5, 1, 1}});
  }
  std::vector<Box> queries;
  for (const Box& b : boxes) queries.push_back({b.max, b.max});
  queries.push_back({{0, 0, 0}, {1e300, 1, 1}});
  for (const Rule& r : allRules()) {
    const BoxTree tree = build(boxes, r);
    expectMatchesBruteForce(tree, boxes, queries);
    expectExactNodeBoxes(tree, boxes);
  }
}

TEST(BoxTree, EmptyAndSingle) {
  for (const Rule& r : allRules()) {
    const BoxTree empty = build({}, r);
    EXPECT_EQ(empty.size(), 0u);
    EXPECT_EQ(empty.nodeCount(), 1u);
    EXPECT_EQ(empty.depth(), 0);
    EXPECT_TRUE(empty.bounds().isEmpty());
    Hits out;
    BroadPhaseCounters c;
    empty.query({{-1e9, -1e9, -1e9}, {1e9, 1e9, 1e9}}, out, &c);
    EXPECT_TRUE(out.empty());
    EXPECT_EQ(c.nodeTests + c.leafTests, 0u);

    const std::vector<Box> one{{kUtm, kUtm + Eigen::Vector3d(0.05, 0.05, 4.0)}};
    const BoxTree single = build(one, r);
    EXPECT_EQ(single.nodeCount(), 1u);
    EXPECT_EQ(single.depth(), 1);
    single.query({kUtm + Eigen::Vector3d(0.05, 0.05, 4.0), kUtm + Eigen::Vector3d(1, 1, 5)}, out, &c);
    EXPECT_EQ(out, Hits{0});
    EXPECT_EQ(c.leafTests, 1u);
    out.clear();
    single.query({kUtm + Eigen::Vector3d(0.06, 0.05, 4.0), kUtm + Eigen::Vector3d(1, 1, 5)}, out);
    EXPECT_TRUE(out.empty());
  }
  const BoxTree def;
  Hits out;
  def.query({{0, 0, 0}, {1, 1, 1}}, out);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(def.size(), 0u);
}

TEST(BoxTree, BadInputThrows) {
  const std::vector<Box> ok{{{0, 0, 0}, {1, 1, 1}}};
  EXPECT_THROW(BoxTree::buildAuto(ok, AutoTreeOptions{3}), std::invalid_argument);
  EXPECT_THROW(BoxTree::buildAuto(std::vector<Box>{Box{}}), std::invalid_argument);  // empty box
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(BoxTree::buildAuto(std::vector<Box>{{{nan, 0, 0}, {1, 1, 1}}}), std::invalid_argument);
  EXPECT_THROW(BoxTree::buildTemplate(ok, std::vector<std::string>{}), std::invalid_argument);
  EXPECT_THROW(BoxTree::buildTemplate(ok, std::vector<std::string>{"a"}).unitParent(1), std::out_of_range);
}

/// Distinct non-empty prefixes of the paths ("a/b/c" gives a, a/b, a/b/c), ignoring empty parts.
std::set<std::string> prefixes(const std::vector<std::string>& paths) {
  std::set<std::string> s;
  for (const std::string& p : paths) {
    std::string prefix;
    std::size_t pos = 0;
    while (pos <= p.size()) {
      std::size_t slash = p.find('/', pos);
      if (slash == std::string::npos) slash = p.size();
      if (slash > pos) {
        prefix += (prefix.empty() ? "" : "/") + p.substr(pos, slash - pos);
        s.insert(prefix);
      }
      pos = slash + 1;
    }
  }
  return s;
}

TEST(BoxTree, TemplateNestedGroupsAndRootUnits) {
  for (const Eigen::Vector3d& offset : {Eigen::Vector3d(0, 0, 0), kUtm}) {
    const std::vector<Box> boxes = randomBoxes(1200, 300.0, offset, 21);
    std::vector<std::string> paths;
    std::mt19937_64 rng(22);
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      switch (rng() % 5) {
        case 0: paths.push_back(""); break;  // directly under the root
        case 1: paths.push_back("bench" + std::to_string(rng() % 4)); break;
        case 2: paths.push_back("bench" + std::to_string(rng() % 4) + "/station" + std::to_string(rng() % 6)); break;
        case 3:
          paths.push_back("bench" + std::to_string(rng() % 4) + "/station" + std::to_string(rng() % 6) + "/mast" +
                          std::to_string(rng() % 3));
          break;
        default: paths.push_back("/pit/ditch" + std::to_string(rng() % 5) + "/"); break;  // empty parts ignored
      }
    }
    const BoxTree tree = BoxTree::buildTemplate(boxes, paths, TemplateTreeOptions{0});
    EXPECT_EQ(tree.describe(), "template");
    const std::set<std::string> groups = prefixes(paths);
    EXPECT_EQ(tree.nodeCount(), groups.size() + 1);
    EXPECT_EQ(tree.depth(), 4);
    expectExactNodeBoxes(tree, boxes);
    const std::vector<BoxTree::NodeInfo> nodes = tree.nodes();
    std::set<std::string> seen;
    for (std::size_t n = 1; n < nodes.size(); ++n) {
      seen.insert(nodes[n].group);
      EXPECT_FALSE(nodes[n].helper);
      // A group's parent is the group one component shorter.
      const std::string& g = nodes[n].group;
      const std::size_t slash = g.rfind('/');
      EXPECT_EQ(nodes[std::size_t(nodes[n].parent)].group, slash == std::string::npos ? "" : g.substr(0, slash));
    }
    EXPECT_EQ(seen, groups);
    // Unit i sits in the node of its own (normalized) group.
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      std::string norm;
      for (const std::string& p : prefixes({paths[i]})) norm = norm.size() < p.size() ? p : norm;
      EXPECT_EQ(nodes[tree.unitParent(i)].group, norm) << "unit " << i;
    }
    // Children in first-appearance order: the root's first child group is the first path's first group.
    std::size_t firstGrouped = 0;
    while (prefixes({paths[firstGrouped]}).empty()) ++firstGrouped;
    std::string firstTop = paths[firstGrouped].substr(paths[firstGrouped].find_first_not_of('/'));
    firstTop = firstTop.substr(0, firstTop.find('/'));
    EXPECT_EQ(nodes[1].group, firstTop);
    expectMatchesBruteForce(tree, boxes, randomQueries(300, 300.0, offset, 23));

    // With wide-group splitting (the root holds ~240 units here): same answers, helper nodes.
    const BoxTree split = BoxTree::buildTemplate(boxes, paths);
    EXPECT_GT(split.nodeCount(), tree.nodeCount());
    EXPECT_NE(split.describe().find("helper"), std::string::npos);
    expectExactNodeBoxes(split, boxes);
    std::set<std::string> splitGroups;
    for (const BoxTree::NodeInfo& n : split.nodes()) {
      if (!n.helper) splitGroups.insert(n.group);
      EXPECT_LE(n.childNodes + n.childUnits, n.helper ? 4u : 64u);
    }
    splitGroups.erase("");
    EXPECT_EQ(splitGroups, groups);
    expectMatchesBruteForce(split, boxes, randomQueries(300, 300.0, offset, 24));
  }
}

/// A template whose root has 600 single-unit groups, all hit by one query: more pending nodes than
/// the traversal's fixed stack holds (its overflow path).
TEST(BoxTree, TemplateWideFlatRootOverflowsStack) {
  std::vector<Box> boxes;
  std::vector<std::string> paths;
  for (int i = 0; i < 600; ++i) {
    const Eigen::Vector3d lo = kUtm + Eigen::Vector3d(0.5 * i, 0, 0);
    boxes.push_back({lo, lo + Eigen::Vector3d(0.5, 1, 1)});  // neighbours share faces
    paths.push_back("g" + std::to_string(i));
  }
  const BoxTree flat = BoxTree::buildTemplate(boxes, paths, TemplateTreeOptions{0});
  EXPECT_EQ(flat.nodeCount(), 601u);
  EXPECT_EQ(flat.depth(), 2);
  const std::vector<Box> queries{{kUtm, kUtm + Eigen::Vector3d(1000, 1, 1)}, {boxes[7].max, boxes[7].max}};
  expectMatchesBruteForce(flat, boxes, queries);
  Hits out;
  BroadPhaseCounters c;
  flat.query(queries[0], out, &c);
  EXPECT_EQ(out.size(), 600u);
  EXPECT_EQ(c.nodeTests, 600u);
  EXPECT_EQ(c.leafTests, 600u);
  const BoxTree split = BoxTree::buildTemplate(boxes, paths);
  expectMatchesBruteForce(split, boxes, queries);
}

}  // namespace
}  // namespace nestwalk
