// The bounding-volume tree over a model's triangles (18-DOP tree): top-down construction, overlap,
// distance and swept queries against a box. See mesh_tree.h for the rules and guarantees.
#include "nestwalk/geometry/mesh_tree.h"

#include "nestwalk/geometry/sat.h"
#include "nestwalk/geometry/triangle_sweep.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

namespace nestwalk {

const std::array<Vec3<double>, Kdop18::kDirections> kKdopDirections = {
    Vec3<double>(1, 0, 0), Vec3<double>(0, 1, 0),  Vec3<double>(0, 0, 1),
    Vec3<double>(1, 1, 0), Vec3<double>(1, -1, 0), Vec3<double>(1, 0, 1),
    Vec3<double>(1, 0, -1), Vec3<double>(0, 1, 1), Vec3<double>(0, 1, -1)};

namespace {

using V3 = Vec3<double>;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Outward padding of a node's slabs, relative to the slab's bound. It covers the rounding of the
// projections that measured the vertices (a k-DOP diagonal is one addition, <= u relative,
// u = 2^-53): 8 epsilon = 16u, a 16x margin.
constexpr double kNodeVolumePadding = 8 * std::numeric_limits<double>::epsilon();

// Distance lower bounds are multiplied by (1 - this) before pruning. It covers what the gaps'
// own slack (kRoundingSlack, sat.h) does not: the box's axes off unit length by kAxesTolerance
// (1e-13) and the division by sqrt(2) on the k-DOP's diagonals.
constexpr double kLowerBoundShrink = 1e-9;

// Depth-first traversal stacks: a node is popped and at most its two children pushed, so a stack
// holds at most depth + 1 entries; the depth is below kMaxMeanSplitDepth + 32 + 1 (median splits
// halve the count, and counts are 32-bit).
constexpr int kStackCapacity = 128;
static_assert(kMaxMeanSplitDepth + 32 + 2 <= kStackCapacity);

// ---- The volume: its fit, its split direction, its tests against a box. ----

template <class Volume>
struct VolumeRules;

// A node's swept slabs (slab_clip.h's SlabClip without the contact bookkeeping a node does not
// need): the running interval of t over which |p0 - t v| <= r on every slab so far, with the
// times found as products with inverse = 1 / v. False once the interval misses [0, 1].
struct NodeClip {
  double enter = -std::numeric_limits<double>::infinity(), exit = std::numeric_limits<double>::infinity();
  bool clip(double p0, double v, double inverse, double r) {
    if (v == 0) {  // no motion along L: the slab holds for all t or for none
      if (std::abs(p0) > r) {
        enter = std::numeric_limits<double>::infinity();
        exit = -std::numeric_limits<double>::infinity();
        return false;
      }
      return true;
    }
    double lo = (p0 - r) * inverse, hi = (p0 + r) * inverse;
    if (v < 0) std::swap(lo, hi);
    if (lo > enter) enter = lo;  // NaN compares false: the slab holds, as in SlabClip
    if (hi < exit) exit = hi;
    return enter <= exit && enter <= 1.0 && exit >= 0.0;
  }
};

template <>
struct VolumeRules<Kdop18> {
  // The box's own 18-DOP, and its face axes: the node's AABB (the k-DOP's first three slabs, which
  // hold the whole k-DOP) is also compared with the box along the box's axes. A box turned against
  // the model's axes has a loose 18-DOP; these three axes take most of the looseness away.
  // A box axis u written as c0 e[slab0] + c1 e[slab1] + c2 e[slab2] over three of the k-DOP's
  // directions, so that a node's extent along u is bounded by its slabs on those three:
  // max u.p <= sum of c_m times slab m's max (its min where c_m < 0). Any such sum bounds it; the
  // tightest, for a node about as wide every way, has the least sum |c_m| |e_m|: the coordinate
  // axes (the node's AABB) for u near one of them, a diagonal and two axes for u turned about an
  // axis (a walker's upright body turned 0.1 rad off x: 1.04 against the AABB's 1.10).
  struct AxisDecomposition {
    std::array<int, 3> slab{0, 1, 2};
    V3 coefficient = V3::Zero();
  };
  static AxisDecomposition decompose(const V3& u) {
    AxisDecomposition best;
    best.coefficient = u;
    double bestCost = u.cwiseAbs().sum();
    // The plane of coordinates (i, j), its diagonals e_i + e_j (plus) and e_i - e_j (minus), and
    // the third axis k.
    struct Plane {
      int i, j, k, plus, minus;
    };
    for (const Plane& p : {Plane{0, 1, 2, 3, 4}, Plane{0, 2, 1, 5, 6}, Plane{1, 2, 0, 7, 8}}) {
      const double ai = u[p.i], aj = u[p.j], ak = u[p.k];
      const double s = (ai >= 0) == (aj >= 0) ? 1.0 : -1.0;  // the diagonal e_i + s e_j
      AxisDecomposition d;
      d.slab[1] = s > 0 ? p.plus : p.minus;
      d.slab[2] = p.k;
      d.coefficient[2] = ak;
      if (std::abs(ai) >= std::abs(aj)) {  // u_ij = (ai - s aj) e_i + s aj (e_i + s e_j)
        d.slab[0] = p.i;
        d.coefficient[0] = ai - s * aj;
        d.coefficient[1] = s * aj;
      } else {  // u_ij = (aj - s ai) e_j + ai (e_i + s e_j)
        d.slab[0] = p.j;
        d.coefficient[0] = aj - s * ai;
        d.coefficient[1] = ai;
      }
      const double cost = std::abs(d.coefficient[0]) + std::sqrt(2.0) * std::abs(d.coefficient[1]) + std::abs(ak);
      if (cost < bestCost) {
        bestCost = cost;
        best = d;
      }
    }
    return best;
  }

  struct Query {
    Kdop18 dop;
    Mat3<double> axes;     // columns: the box's axes
    std::array<AxisDecomposition, 3> along;  // each axis over three of the k-DOP's directions
    V3 centreAlong;        // the box's centre along its axes
    V3 halfExtents;
    double slack = 0;      // the box's share of the rounding slack on its axes
  };

  static Query prepare(const Obb<double>& box) {
    Query q;
    const double magnitude = box.center.cwiseAbs().sum() + box.halfExtents.sum();
    for (int k = 0; k < Kdop18::kDirections; ++k) {
      const V3& dir = kKdopDirections[k];
      const double mid = dir.dot(box.center);
      const double radius = (box.axes.transpose() * dir).cwiseAbs().dot(box.halfExtents);
      // Rounding of mid and radius (a few u of 2 x magnitude) and the axes' tolerance: sat.h's slack.
      const double slack = kRoundingSlack<double> * 2 * magnitude;
      q.dop.min[k] = mid - radius - slack;
      q.dop.max[k] = mid + radius + slack;
    }
    q.axes = box.axes;
    for (int j = 0; j < 3; ++j) q.along[std::size_t(j)] = decompose(box.axes.col(j));
    q.centreAlong = box.axes.transpose() * box.center;
    q.halfExtents = box.halfExtents;
    q.slack = kRoundingSlack<double> * 2 * magnitude;
    return q;
  }

  // Along the box's 3 axes, the node (its extent bounded through each axis's decomposition over
  // its slabs) and the box: the offsets of the node's middle from the box's centre (p0) and the
  // sums of their radii with the slack (r).
  struct AxisSlabs {
    V3 p0, r;
  };
  static AxisSlabs boxAxisSlabs(const Kdop18& node, const Query& q, double extraSlack = 0) {
    AxisSlabs out;
    for (int j = 0; j < 3; ++j) {
      const AxisDecomposition& a = q.along[std::size_t(j)];
      double middle = 0, radius = 0, magnitude = 0;
      for (int m = 0; m < 3; ++m) {
        const int k = a.slab[std::size_t(m)];
        const double mid = 0.5 * (node.min[k] + node.max[k]), half = 0.5 * (node.max[k] - node.min[k]);
        const double c = a.coefficient[m];
        middle += c * mid;
        radius += std::abs(c) * half;
        magnitude += std::abs(c) * (std::abs(mid) + half);
      }
      out.p0[j] = middle - q.centreAlong[j];
      out.r[j] = radius + q.halfExtents[j] + q.slack + extraSlack + kRoundingSlack<double> * 2 * magnitude;
    }
    return out;
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
  // The swept query: the box at t = 0 and its motion along each of the 9 directions and the
  // box's 3 axes.
  struct SweepQuery {
    Query box;
    std::array<double, Kdop18::kDirections> motion;
    std::array<double, Kdop18::kDirections> inverseMotion;  // 1 / motion (inf where 0)
    V3 motionAlong;      // d along the box's axes
    V3 inverseAlong;     // 1 / motionAlong
    double motionSlack;  // the rounding of motionAlong
  };
  static SweepQuery prepareSweep(const Obb<double>& box, const V3& d) {
    SweepQuery q{prepare(box), {}, {}, box.axes.transpose() * d, V3::Zero(), kRoundingSlack<double> * d.cwiseAbs().sum()};
    for (int k = 0; k < Kdop18::kDirections; ++k) {
      q.motion[k] = kKdopDirections[k].dot(d);
      q.inverseMotion[k] = 1.0 / q.motion[k];
    }
    q.inverseAlong = q.motionAlong.cwiseInverse();
    return q;
  }
  // Per direction, the box's slab moving across the node's: |p0 - t v| <= r. The motion's
  // rounding is covered by the slack prepare() already put on the box's slabs, widened by |v|.
  // The times are products with 1 / v, found once per sweep (a node test made 24 divisions);
  // they differ from the quotients by an ulp or two of t, far inside the slack that grows the
  // box (sweepBoxTriangleSlack: its share of t is that slack over |v|), so a node is still
  // never entered later than its triangles.
  static SweepResult sweepInterval(const Kdop18& node, const SweepQuery& q) {
    NodeClip clip;
    bool alive = true;
    for (int k = 0; k < Kdop18::kDirections && alive; ++k) {
      const double p0 = 0.5 * (node.min[k] + node.max[k]) - 0.5 * (q.box.dop.min[k] + q.box.dop.max[k]);
      const double r = 0.5 * (node.max[k] - node.min[k]) + 0.5 * (q.box.dop.max[k] - q.box.dop.min[k]) +
                       kRoundingSlack<double> * std::abs(q.motion[k]);
      alive = clip.clip(p0, q.motion[k], q.inverseMotion[k], r);
    }
    if (alive) {
      const AxisSlabs slabs = boxAxisSlabs(node, q.box, q.motionSlack);
      for (int j = 0; j < 3 && alive; ++j) alive = clip.clip(slabs.p0[j], q.motionAlong[j], q.inverseAlong[j], slabs.r[j]);
    }
    SweepResult out;
    out.enter = clip.enter;
    out.exit = clip.exit;
    return out;
  }

  static bool overlaps(const Kdop18& node, const Query& box) {
    for (int k = 0; k < Kdop18::kDirections; ++k)
      if (node.min[k] > box.dop.max[k] || box.dop.min[k] > node.max[k]) return false;
    const AxisSlabs slabs = boxAxisSlabs(node, box);
    return (slabs.p0.cwiseAbs().array() <= slabs.r.array()).all();
  }
  static double lowerBound(const Kdop18& node, const Query& box) {
    double gap = 0;
    for (int k = 0; k < Kdop18::kDirections; ++k) {
      const double slabGap = std::max(node.min[k] - box.dop.max[k], box.dop.min[k] - node.max[k]);
      gap = std::max(gap, k < 3 ? slabGap : slabGap / std::sqrt(2.0));
    }
    const AxisSlabs slabs = boxAxisSlabs(node, box);  // unit axes
    gap = std::max(gap, (slabs.p0.cwiseAbs() - slabs.r).maxCoeff());
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
    nodes_[index].facing = fitNormalSlab(first, count);
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

  // The slab along the node's mean normal over points_ (the node's corners), padded outward like
  // the k-DOP's slabs, plus the rounding of the products with a unit normal (<= 3u |n|_1 |p|_inf).
  NormalSlab fitNormalSlab(std::uint32_t first, std::uint32_t count) const {
    V3 sum = V3::Zero();
    for (std::uint32_t i = first; i < first + count; ++i) {
      const Triangle t = mesh_.triangle(order_[i]);
      sum += (t[1] - t[0]).cross(t[2] - t[0]);
    }
    NormalSlab slab;
    const double length = sum.norm();
    if (length > 0 && std::isfinite(length)) slab.normal = sum / length;
    slab.min = kInfinity;
    slab.max = -kInfinity;
    double largest = 0;
    for (const V3& p : points_) {
      const double s = slab.normal.dot(p);
      slab.min = std::min(slab.min, s);
      slab.max = std::max(slab.max, s);
      largest = std::max(largest, p.cwiseAbs().maxCoeff());
    }
    const double pad = kNodeVolumePadding * slab.normal.cwiseAbs().sum() * largest;
    slab.min -= pad;
    slab.max += pad;
    return slab;
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

// The sweep's frontier: a binary min-heap on the entry time, on the call stack (kFrontierCapacity
// entries, 16 bytes each). When it is full the sweep searches the child it could not queue depth
// first instead, so no motion overflows it.
constexpr int kFrontierCapacity = 256;

class SweepFrontier {
 public:
  bool empty() const { return size_ == 0; }
  const StackEntry& top() const { return heap_[0]; }
  bool full() const { return size_ == kFrontierCapacity; }
  void push(const StackEntry& e) {
    int i = size_++;
    while (i > 0) {
      const int parent = (i - 1) / 2;
      if (!(e.lowerBound < heap_[parent].lowerBound)) break;
      heap_[i] = heap_[parent];
      i = parent;
    }
    heap_[i] = e;
  }
  StackEntry pop() {
    const StackEntry top = heap_[0];
    const StackEntry last = heap_[--size_];
    int i = 0;
    for (;;) {
      int child = 2 * i + 1;
      if (child >= size_) break;
      if (child + 1 < size_ && heap_[child + 1].lowerBound < heap_[child].lowerBound) ++child;
      if (!(heap_[child].lowerBound < last.lowerBound)) break;
      heap_[i] = heap_[child];
      i = child;
    }
    heap_[i] = last;
    return top;
  }

 private:
  StackEntry heap_[kFrontierCapacity];
  int size_ = 0;
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
  static std::atomic<std::uint64_t> lastId{0};
  id_ = ++lastId;
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
  return search(box, d, tStart, counters, false);
}

template <class Volume>
double MeshTree<Volume>::freeUntil(const Obb<double>& box, const Vec3<double>& d, MeshQueryCounters* counters) const {
  const MeshSweepHit hit = search(box, d, 0.0, counters, true);
  return hit.contact ? hit.t : kInfinity;
}

template <class Volume>
MeshSweepHit MeshTree<Volume>::search(const Obb<double>& box, const Vec3<double>& d, double tStart,
                                      MeshQueryCounters* counters, bool firstFound) const {
  MeshSweepHit hit;
  if (nodes_.empty()) return hit;
  Obb<double> grown = box;
  const double slack = sweepBoxTriangleSlack(box, d, reach_);
  grown.halfExtents.array() += slack;
  const auto query = VolumeRules<Volume>::prepareSweep(grown, d);
  // The box's centre and radius along a node's normal slab, as for the k-DOP's slabs (prepare()):
  // the rounding of the products and the axes' tolerance are covered by sat.h's slack.
  const double boxMagnitude = grown.center.cwiseAbs().sum() + grown.halfExtents.sum() + d.cwiseAbs().sum();
  const double facingSlack = kRoundingSlack<double> * 2 * boxMagnitude;
  // Contacts closer than this along the motion are one: the search keeps the first it finds.
  const double length = d.norm();
  const double tie = length > 0 && !firstFound ? meshSweepTieDistance(box, d, reach_) / length : 0.0;
  std::uint64_t nodeTests = 1, triangleTests = 0;
  // A node's entry: the time its volume is first touched (no triangle inside is touched earlier).
  auto entry = [&](std::uint32_t index) {
    const MeshTreeNode<Volume>& node = nodes_[index];
    SweepResult r = VolumeRules<Volume>::sweepInterval(node.volume, query);
    if (r.enter <= r.exit && r.enter <= 1.0 && r.exit >= tStart) {
      const NormalSlab& f = node.facing;
      const double mid = 0.5 * (f.min + f.max);
      const double radius = (grown.axes.transpose() * f.normal).cwiseAbs().dot(grown.halfExtents);
      NodeClip clip{r.enter, r.exit};
      const double p0 = mid - f.normal.dot(grown.center), v = f.normal.dot(d);
      clip.clip(p0, v, 1.0 / v, 0.5 * (f.max - f.min) + radius + facingSlack + kRoundingSlack<double> * 2 * std::abs(mid));
      r.enter = clip.enter;
      r.exit = clip.exit;
    }
    const bool meets = r.enter <= r.exit && r.enter <= 1.0 && r.exit >= tStart;
    return StackEntry{index, meets ? std::max(r.enter, tStart) : kInfinity};
  };
  double best = kInfinity;  // the earliest contact found so far
  // A node or triangle entered no earlier than this cannot improve the contact by more than the tie.
  auto beyond = [&](double t) { return t >= best - tie; };
  auto testLeaf = [&](const MeshTreeNode<Volume>& node) {
    for (std::uint32_t i = node.firstTriangle; i < node.firstTriangle + node.triangleCount; ++i) {
      ++triangleTests;
      const double end = std::min(best - tie, 1.0);
      const SweepResult r = sweepBoxTriangle(box, d, triangles_[i], tStart, end);
      if (!(r.enter <= r.exit && r.enter <= end && r.exit >= tStart)) continue;
      const double t = std::max(r.enter, tStart);
      if (beyond(t)) continue;
      best = t;
      hit = {true, t, r.enter > tStart ? r.normal : Vec3<double>::Zero()};
    }
  };
  // Best first: the frontier is a min-heap on the entry time, so nodes are opened in the order
  // the box reaches them and the search ends once the earliest unopened node is entered no
  // earlier than the best contact less the tie (no triangle below it can come earlier by more).
  SweepFrontier frontier;
  if (const StackEntry root = entry(0); root.lowerBound != kInfinity) frontier.push(root);
  while (!frontier.empty()) {
    const StackEntry e = frontier.pop();
    if (beyond(e.lowerBound)) break;  // every node left is entered later still
    const MeshTreeNode<Volume>& node = nodes_[e.node];
    if (node.isLeaf()) {
      testLeaf(node);
      // freeUntil: nothing is touched before the contact found nor before the earliest node
      // still unopened; that is all it needs to know.
      if (firstFound && hit.contact) {
        if (!frontier.empty()) hit.t = std::min(hit.t, frontier.top().lowerBound);
        break;
      }
      continue;
    }
    for (const std::uint32_t child : {e.node + 1, node.secondChild}) {
      const StackEntry c = entry(child);
      ++nodeTests;
      if (c.lowerBound == kInfinity || beyond(c.lowerBound)) continue;  // not entered, or after the best
      if (!frontier.full()) {
        frontier.push(c);
        continue;
      }
      // A full frontier (a motion through thousands of nodes): this child is searched depth
      // first on the spot, with the same pruning; the answer does not depend on the order.
      std::uint32_t stack[kStackCapacity];
      int top = 0;
      stack[top++] = c.node;
      while (top > 0) {
        const std::uint32_t index = stack[--top];
        const MeshTreeNode<Volume>& n = nodes_[index];
        if (n.isLeaf()) {
          testLeaf(n);
          continue;
        }
        for (const std::uint32_t g : {index + 1, n.secondChild}) {
          ++nodeTests;
          const double enter = entry(g).lowerBound;
          if (enter != kInfinity && !beyond(enter)) stack[top++] = g;
        }
      }
    }
  }
  // Never late: a triangle left unopened may touch up to the tie before the one found.
  if (hit.contact && tie > 0) hit.t = std::max(tStart, hit.t - tie);
  if (counters) {
    counters->nodeTests += nodeTests;
    counters->triangleTests += triangleTests;
  }
  return hit;
}

double meshSweepTieDistance(const Obb<double>& box, const Vec3<double>& d, double reach) {
  const double slack = sweepBoxTriangleSlack(box, d, reach);
  return std::max(kSweepTieMinSlacks * slack,
                  std::min(kSweepTieSlacks * slack, kSweepTieBoxFraction * box.halfExtents.minCoeff()));
}

template class MeshTree<Kdop18>;

}  // namespace nestwalk
