// Bounding-volume trees over a model's triangles (OBB tree, 18-DOP tree): top-down construction,
// overlap and distance queries against a box. See mesh_tree.h for the rules and guarantees.
#include "nestwalk/geometry/mesh_tree.h"

#include "nestwalk/geometry/obb_fit.h"
#include "nestwalk/geometry/sat.h"
#include "nestwalk/geometry/slab_clip.h"
#include "nestwalk/geometry/triangle_sweep.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

namespace nestwalk {

const std::array<Vec3<double>, Kdop18::kDirections> kKdopDirections = {
    Vec3<double>(1, 0, 0), Vec3<double>(0, 1, 0),  Vec3<double>(0, 0, 1),
    Vec3<double>(1, 1, 0), Vec3<double>(1, -1, 0), Vec3<double>(1, 0, 1),
    Vec3<double>(1, 0, -1), Vec3<double>(0, 1, 1), Vec3<double>(0, 1, -1)};

namespace {

using V3 = Vec3<double>;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Outward padding of a node's volume, relative to the magnitudes it is computed from (OBB: centre
// |c|_1 plus half extents |h|_1; k-DOP slab: the slab's bound). It covers the rounding of the
// projections that measured the vertices (a difference and a three-term dot product, <= 4u
// relative, u = 2^-53; a k-DOP diagonal is one addition, <= u): 8 epsilon = 16u, a 4x margin.
constexpr double kNodeVolumePadding = 8 * std::numeric_limits<double>::epsilon();

// Distance lower bounds are multiplied by (1 - this) before pruning. It covers what the gaps'
// own slack (kRoundingSlack, sat.h) does not: unit axes off unit length by kAxesTolerance (1e-13),
// edge axes whose length is measured from R (error ~1e-13 absolute, so ~1e-10 relative at the
// shortest edge axis used, kMinEdgeAxisLength) and the division by sqrt(2) on k-DOP diagonals.
constexpr double kLowerBoundShrink = 1e-9;
// Edge axes A_i x B_j shorter than this (sine of the angle between the edges) are left out of the
// lower bound: a bound may use any subset of the separating axes.
constexpr double kMinEdgeAxisLength = 1e-3;

// Depth-first traversal stacks: a node is popped and at most its two children pushed, so a stack
// holds at most depth + 1 entries; the depth is below kMaxMeanSplitDepth + 32 + 1 (median splits
// halve the count, and counts are 32-bit).
constexpr int kStackCapacity = 128;
static_assert(kMaxMeanSplitDepth + 32 + 2 <= kStackCapacity);

// ---- What differs between the two trees: the volume, its split direction, its tests. ----

template <class Volume>
struct VolumeRules;

template <>
struct VolumeRules<Obb<double>> {
  using Query = Obb<double>;
  static Query prepare(const Obb<double>& box) { return box; }

  // Gottschalk's covariance box (the project's fitter), grown to hold every point despite rounding.
  static Obb<double> fit(const std::vector<V3>& points) {
    Obb<double> b = fitObb(points, ObbFitter::Covariance);
    V3 reach = b.halfExtents;
    for (const V3& p : points) reach = reach.cwiseMax((b.axes.transpose() * (p - b.center)).cwiseAbs());
    b.halfExtents = reach + V3::Constant(kNodeVolumePadding * (b.center.cwiseAbs().sum() + reach.sum()));
    return b;
  }
  // The box's longest axis.
  static V3 splitDirection(const Obb<double>& b, const std::vector<V3>&) {
    int longest;
    b.halfExtents.maxCoeff(&longest);
    return b.axes.col(longest);
  }
  static bool overlaps(const Obb<double>& node, const Query& box) { return satObbObb(node, box).overlap; }

  // The swept query: the box and its motion; a node's interval of contact in t.
  struct SweepQuery {
    Obb<double> box;
    V3 d;
  };
  static SweepQuery prepareSweep(const Obb<double>& box, const V3& d) { return {box, d}; }
  static SweepResult sweepInterval(const Obb<double>& node, const SweepQuery& q) { return sweepObbObb(q.box, q.d, node); }

  // The largest gap over the 15 separating axes of two boxes (sat.h's formulas, A = node, B = box),
  // each divided by its axis' length: the distance between the boxes is at least that.
  static double lowerBound(const Obb<double>& A, const Query& B) {
    const V3 d = B.center - A.center;
    const V3 t = A.axes.transpose() * d;
    const Mat3<double> R = A.axes.transpose() * B.axes;
    const Mat3<double> absR = R.cwiseAbs();
    const V3& a = A.halfExtents;
    const V3& b = B.halfExtents;
    const double slack = kRoundingSlack<double> * (d.cwiseAbs().sum() + a.sum() + b.sum());
    double gap = 0;
    for (int i = 0; i < 3; ++i) gap = std::max(gap, std::abs(t[i]) - a[i] - absR.row(i).dot(b));
    for (int j = 0; j < 3; ++j) gap = std::max(gap, std::abs(t.dot(R.col(j))) - absR.col(j).dot(a) - b[j]);
    gap -= slack;
    for (int i = 0; i < 3; ++i) {
      const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
      for (int j = 0; j < 3; ++j) {
        const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
        const double length = std::hypot(R(i1, j), R(i2, j));
        if (length < kMinEdgeAxisLength) continue;
        const double ra = a[i1] * absR(i2, j) + a[i2] * absR(i1, j);
        const double rb = b[j1] * absR(i, j2) + b[j2] * absR(i, j1);
        gap = std::max(gap, (std::abs(t[i2] * R(i1, j) - t[i1] * R(i2, j)) - ra - rb - slack) / length);
      }
    }
    return std::max(0.0, gap) * (1 - kLowerBoundShrink);
  }
};

template <>
struct VolumeRules<Kdop18> {
  using Query = Kdop18;  // the box's own 18-DOP

  static Query prepare(const Obb<double>& box) {
    Kdop18 q;
    const double magnitude = box.center.cwiseAbs().sum() + box.halfExtents.sum();
    for (int k = 0; k < Kdop18::kDirections; ++k) {
      const V3& dir = kKdopDirections[k];
      const double mid = dir.dot(box.center);
      const double radius = (box.axes.transpose() * dir).cwiseAbs().dot(box.halfExtents);
      // Rounding of mid and radius (a few u of 2 x magnitude) and the axes' tolerance: sat.h's slack.
      const double slack = kRoundingSlack<double> * 2 * magnitude;
      q.min[k] = mid - radius - slack;
      q.max[k] = mid + radius + slack;
    }
    return q;
  }

  static Kdop18 fit(const std::vector<V3>& points) {
    Kdop18 v;
    v.min.fill(kInfinity);
    v.max.fill(-kInfinity);
    for (const V3& p : points)
      for (int k = 0; k < Kdop18::kDirections; ++k) {
        const double s = kKdopDirections[k].dot(p);
        v.min[k] = std::min(v.min[k], s);
        v.max[k] = std::max(v.max[k], s);
      }
    for (int k = 0; k < Kdop18::kDirections; ++k) {
      v.min[k] -= kNodeVolumePadding * std::abs(v.min[k]);
      v.max[k] += kNodeVolumePadding * std::abs(v.max[k]);
    }
    return v;
  }
  // Splatter: the coordinate axis with the largest variance of the centroids.
  static V3 splitDirection(const Kdop18&, const std::vector<V3>& centroids) {
    V3 mean = V3::Zero();
    for (const V3& c : centroids) mean += c;
    mean /= double(centroids.size());
    V3 variance = V3::Zero();
    for (const V3& c : centroids) variance += (c - mean).cwiseAbs2();
    int axis;
    variance.maxCoeff(&axis);
    return V3::Unit(axis);
  }
  // The swept query: the box's 18-DOP at t = 0 and its motion along each direction.
  struct SweepQuery {
    Kdop18 box;
    std::array<double, Kdop18::kDirections> motion;
  };
  static SweepQuery prepareSweep(const Obb<double>& box, const V3& d) {
    SweepQuery q{prepare(box), {}};
    for (int k = 0; k < Kdop18::kDirections; ++k) q.motion[k] = kKdopDirections[k].dot(d);
    return q;
  }
  // Per direction, the box's slab moving across the node's: |p0 - t v| <= r. The motion's
  // rounding is covered by the slack prepare() already put on the box's slabs, widened by |v|.
  static SweepResult sweepInterval(const Kdop18& node, const SweepQuery& q) {
    SlabClip clip;
    bool alive = true;
    for (int k = 0; k < Kdop18::kDirections && alive; ++k) {
      const double p0 = 0.5 * (node.min[k] + node.max[k]) - 0.5 * (q.box.min[k] + q.box.max[k]);
      const double r = 0.5 * (node.max[k] - node.min[k]) + 0.5 * (q.box.max[k] - q.box.min[k]) +
                       kRoundingSlack<double> * std::abs(q.motion[k]);
      alive = clip.clip(p0, q.motion[k], r, std::int8_t(k), k);
    }
    SweepResult out;
    out.enter = clip.enter;
    out.exit = clip.exit;
    return out;
  }

  static bool overlaps(const Kdop18& node, const Query& box) {
    for (int k = 0; k < Kdop18::kDirections; ++k)
      if (node.min[k] > box.max[k] || box.min[k] > node.max[k]) return false;
    return true;
  }
  static double lowerBound(const Kdop18& node, const Query& box) {
    double gap = 0;
    for (int k = 0; k < Kdop18::kDirections; ++k) {
      const double slabGap = std::max(node.min[k] - box.max[k], box.min[k] - node.max[k]);
      gap = std::max(gap, k < 3 ? slabGap : slabGap / std::sqrt(2.0));
    }
    return gap * (1 - kLowerBoundShrink);
  }
};

// ---- Construction. ----

template <class Volume>
class TreeBuilder {
 public:
  TreeBuilder(const TriangleMesh& mesh, int leafSize, std::vector<MeshTreeNode<Volume>>& nodes)
      : mesh_(mesh), leafSize_(std::uint32_t(leafSize)), nodes_(nodes), order_(mesh.triangles.size()) {
    std::iota(order_.begin(), order_.end(), 0u);
    centroids_.reserve(mesh.triangles.size());
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      const Triangle t = mesh.triangle(i);
      centroids_.push_back((t[0] + t[1] + t[2]) / 3.0);
    }
  }

  // Builds the subtree of order_[first, first + count) at `level`; returns its depth.
  int build(std::uint32_t first, std::uint32_t count, int level) {
    const std::size_t index = nodes_.size();
    nodes_.emplace_back();
    gatherNode(first, count);
    nodes_[index].volume = VolumeRules<Volume>::fit(points_);
    nodes_[index].firstTriangle = first;
    nodes_[index].triangleCount = count;
    if (count <= leafSize_) return 0;
    const std::uint32_t leftCount =
        split(first, count, VolumeRules<Volume>::splitDirection(nodes_[index].volume, nodeCentroids_), level);
    const int leftDepth = build(first, leftCount, level + 1);
    nodes_[index].secondChild = std::uint32_t(nodes_.size());
    const int rightDepth = build(first + leftCount, count - leftCount, level + 1);
    return 1 + std::max(leftDepth, rightDepth);
  }

  const std::vector<std::uint32_t>& order() const { return order_; }

 private:
  // points_: the distinct vertices of the node's triangles; nodeCentroids_: their centroids.
  void gatherNode(std::uint32_t first, std::uint32_t count) {
    vertexIds_.clear();
    nodeCentroids_.clear();
    for (std::uint32_t i = first; i < first + count; ++i) {
      const auto& tri = mesh_.triangles[order_[i]];
      vertexIds_.insert(vertexIds_.end(), tri.begin(), tri.end());
      nodeCentroids_.push_back(centroids_[order_[i]]);
    }
    std::sort(vertexIds_.begin(), vertexIds_.end());
    vertexIds_.erase(std::unique(vertexIds_.begin(), vertexIds_.end()), vertexIds_.end());
    points_.clear();
    for (std::uint32_t v : vertexIds_) points_.push_back(mesh_.vertices[v]);
  }

  // Reorders order_[first, first + count) into two non-empty sides; returns the left count.
  // Mean split along `direction`, or the median when the mean leaves a side empty or the
  // node is at kMaxMeanSplitDepth or deeper.
  std::uint32_t split(std::uint32_t first, std::uint32_t count, const V3& direction, int level) {
    auto projection = [&](std::uint32_t t) { return direction.dot(centroids_[t]); };
    const auto begin = order_.begin() + first, end = begin + count;
    if (level < kMaxMeanSplitDepth) {
      double mean = 0;
      for (auto it = begin; it != end; ++it) mean += projection(*it);
      mean /= double(count);
      const auto middle = std::partition(begin, end, [&](std::uint32_t t) { return projection(t) < mean; });
      if (middle != begin && middle != end) return std::uint32_t(middle - begin);
    }
    const auto middle = begin + count / 2;
    std::nth_element(begin, middle, end, [&](std::uint32_t s, std::uint32_t t) { return projection(s) < projection(t); });
    return count / 2;
  }

  const TriangleMesh& mesh_;
  const std::uint32_t leafSize_;
  std::vector<MeshTreeNode<Volume>>& nodes_;
  std::vector<std::uint32_t> order_;  // triangle indices, permuted into leaf order
  std::vector<V3> centroids_;         // by mesh triangle index
  // Scratch for the node being built.
  std::vector<std::uint32_t> vertexIds_;
  std::vector<V3> points_;
  std::vector<V3> nodeCentroids_;
};

void validate(const TriangleMesh& mesh, int leafSize) {
  if (leafSize < 1) throw std::invalid_argument("mesh tree: leafSize must be >= 1, got " + std::to_string(leafSize));
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    for (std::uint32_t v : mesh.triangles[i]) {
      if (v >= mesh.vertices.size())
        throw std::invalid_argument("mesh tree: triangle " + std::to_string(i) + " refers to vertex " + std::to_string(v) +
                                    " of " + std::to_string(mesh.vertices.size()));
      if (!mesh.vertices[v].allFinite())
        throw std::invalid_argument("mesh tree: triangle " + std::to_string(i) + " has a non-finite coordinate");
    }
}

struct StackEntry {
  std::uint32_t node;
  double lowerBound;
};

}  // namespace

bool bruteForceOverlaps(const TriangleMesh& mesh, const Obb<double>& box) {
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    if (triangleBoxOverlap(mesh.triangle(i), box)) return true;
  return false;
}

double bruteForceDistance(const TriangleMesh& mesh, const Obb<double>& box) {
  double best = kInfinity;
  for (std::size_t i = 0; i < mesh.triangles.size() && best > 0; ++i)
    best = std::min(best, triangleBoxDistance(mesh.triangle(i), box));
  return best;
}

MeshSweepHit bruteForceSweep(const TriangleMesh& mesh, const Obb<double>& box, const Vec3<double>& d,
                             double tStart) {
  MeshSweepHit hit;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const SweepResult r = sweepBoxTriangle(box, d, mesh.triangle(i), tStart, 1.0);
    if (!(r.enter <= r.exit && r.enter <= 1.0 && r.exit >= tStart)) continue;
    const double t = std::max(r.enter, tStart);
    if (!hit.contact || t < hit.t) hit = {true, t, r.enter > tStart ? r.normal : Vec3<double>::Zero()};
  }
  return hit;
}

template <class Volume>
MeshTree<Volume>::MeshTree(const TriangleMesh& mesh, int leafSize) {
  validate(mesh, leafSize);
  if (mesh.triangles.empty()) return;
  TreeBuilder<Volume> builder(mesh, leafSize, nodes_);
  depth_ = builder.build(0, std::uint32_t(mesh.triangles.size()), 0);
  triangles_.reserve(mesh.triangles.size());
  for (std::uint32_t t : builder.order()) triangles_.push_back(mesh.triangle(t));
  for (const Triangle& t : triangles_)
    for (const V3& p : t) reach_ = std::max(reach_, p.cwiseAbs().maxCoeff());
}

template <class Volume>
bool MeshTree<Volume>::overlaps(const Obb<double>& box, MeshQueryCounters* counters) const {
  if (nodes_.empty()) return false;
  const auto query = VolumeRules<Volume>::prepare(box);
  std::uint64_t nodeTests = 0, triangleTests = 0;
  std::uint32_t stack[kStackCapacity];
  int top = 0;
  stack[top++] = 0;
  bool contact = false;
  while (top > 0 && !contact) {
    const std::uint32_t index = stack[--top];
    const MeshTreeNode<Volume>& node = nodes_[index];
    ++nodeTests;
    if (!VolumeRules<Volume>::overlaps(node.volume, query)) continue;
    if (node.isLeaf()) {
      for (std::uint32_t i = node.firstTriangle; i < node.firstTriangle + node.triangleCount && !contact; ++i) {
        ++triangleTests;
        contact = triangleBoxOverlap(triangles_[i], box);
      }
    } else {
      stack[top++] = node.secondChild;
      stack[top++] = index + 1;
    }
  }
  if (counters) {
    counters->nodeTests += nodeTests;
    counters->triangleTests += triangleTests;
  }
  return contact;
}

template <class Volume>
double MeshTree<Volume>::distance(const Obb<double>& box, MeshQueryCounters* counters, Triangle* nearest) const {
  if (nodes_.empty()) return kInfinity;
  const auto query = VolumeRules<Volume>::prepare(box);
  std::uint64_t nodeTests = 1, triangleTests = 0;
  StackEntry stack[kStackCapacity];
  int top = 0;
  stack[top++] = {0, VolumeRules<Volume>::lowerBound(nodes_[0].volume, query)};
  double best = kInfinity;
  while (top > 0 && best > 0) {
    const StackEntry entry = stack[--top];
    if (entry.lowerBound >= best) continue;
    const MeshTreeNode<Volume>& node = nodes_[entry.node];
    if (node.isLeaf()) {
      for (std::uint32_t i = node.firstTriangle; i < node.firstTriangle + node.triangleCount && best > 0; ++i) {
        ++triangleTests;
        const double d = triangleBoxDistance(triangles_[i], box);
        if (d < best) {
          best = d;
          if (nearest) *nearest = triangles_[i];
        }
      }
      continue;
    }
    StackEntry first{entry.node + 1, VolumeRules<Volume>::lowerBound(nodes_[entry.node + 1].volume, query)};
    StackEntry second{node.secondChild, VolumeRules<Volume>::lowerBound(nodes_[node.secondChild].volume, query)};
    nodeTests += 2;
    if (second.lowerBound < first.lowerBound) std::swap(first, second);
    // The nearer child is pushed last, so it is visited first.
    if (second.lowerBound < best) stack[top++] = second;
    if (first.lowerBound < best) stack[top++] = first;
  }
  if (counters) {
    counters->nodeTests += nodeTests;
    counters->triangleTests += triangleTests;
  }
  return best;
}

template <class Volume>
MeshSweepHit MeshTree<Volume>::sweep(const Obb<double>& box, const Vec3<double>& d, double tStart,
                                     MeshQueryCounters* counters) const {
  MeshSweepHit hit;
  if (nodes_.empty()) return hit;
  Obb<double> grown = box;
  grown.halfExtents.array() += sweepBoxTriangleSlack(box, d, reach_);
  const auto query = VolumeRules<Volume>::prepareSweep(grown, d);
  std::uint64_t nodeTests = 1, triangleTests = 0;
  // A node's entry: the time its volume is first touched (no triangle inside is touched earlier).
  auto entry = [&](std::uint32_t index) {
    const SweepResult r = VolumeRules<Volume>::sweepInterval(nodes_[index].volume, query);
    const bool meets = r.enter <= r.exit && r.enter <= 1.0 && r.exit >= tStart;
    return StackEntry{index, meets ? std::max(r.enter, tStart) : kInfinity};
  };
  double best = kInfinity;  // the earliest contact found so far
  StackEntry stack[kStackCapacity];
  int top = 0;
  stack[top++] = entry(0);
  while (top > 0) {
    const StackEntry e = stack[--top];
    if (e.lowerBound == kInfinity || e.lowerBound >= best) continue;
    const MeshTreeNode<Volume>& node = nodes_[e.node];
    if (node.isLeaf()) {
      for (std::uint32_t i = node.firstTriangle; i < node.firstTriangle + node.triangleCount; ++i) {
        ++triangleTests;
        const SweepResult r = sweepBoxTriangle(box, d, triangles_[i], tStart, std::min(best, 1.0));
        if (!(r.enter <= r.exit && r.enter <= 1.0 && r.exit >= tStart)) continue;
        const double t = std::max(r.enter, tStart);
        if (t < best) {
          best = t;
          hit = {true, t, r.enter > tStart ? r.normal : Vec3<double>::Zero()};
        }
      }
      if (best == tStart) break;  // nothing can come earlier
      continue;
    }
    StackEntry first = entry(e.node + 1), second = entry(node.secondChild);
    nodeTests += 2;
    if (second.lowerBound < first.lowerBound) std::swap(first, second);
    // The child entered first is pushed last, so it is visited first.
    if (second.lowerBound < best) stack[top++] = second;
    if (first.lowerBound < best) stack[top++] = first;
  }
  if (counters) {
    counters->nodeTests += nodeTests;
    counters->triangleTests += triangleTests;
  }
  return hit;
}

template class MeshTree<Obb<double>>;
template class MeshTree<Kdop18>;

}  // namespace nestwalk
