// Nested view-frustum culling (nested_cull.h): the frustum from OSG matrices, the AABB stage over
// flat arrays, the OBB stage for the undecided instances, the cull callbacks, and OSG's own
// bounding-sphere test for comparison.
#include "nestwalk/render/nested_cull.h"

#include "nestwalk/scene/scene.h"

#include <Eigen/Geometry>
#include <osg/NodeCallback>
#include <osg/Polytope>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace nestwalk {
namespace {

/// Roundings a plane distance may carry: the dot product and offset (4), the plane's own
/// normalization (2) and the projected radius of an OBB (6), with margin.
constexpr double kSlackRoundings = 16.0;

double elapsedMicros(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
}

/// Plane k of a combined matrix (Gribb & Hartmann): clip_k = p . column k, inside where
/// -w <= clip_k <= w, i.e. (column 3 + sign * column k) . p >= 0; normalized to a unit normal.
FrustumPlane planeOf(const osg::Matrixd& m, int column, double sign) {
  const Eigen::Vector4d c(m(0, 3) + sign * m(0, column), m(1, 3) + sign * m(1, column),
                          m(2, 3) + sign * m(2, column), m(3, 3) + sign * m(3, column));
  const double length = c.head<3>().norm();
  if (!(length > 0) || !std::isfinite(length))
    throw std::invalid_argument("Frustum::fromMatrices: degenerate view or projection matrix");
  return {c.head<3>() / length, c[3] / length};
}

/// The point on three planes (Cramer's rule through cross products).
Vec3<double> meetingPoint(const FrustumPlane& a, const FrustumPlane& b, const FrustumPlane& c) {
  const Vec3<double> bc = b.normal.cross(c.normal);
  const double det = a.normal.dot(bc);
  return -(a.offset * bc + b.offset * c.normal.cross(a.normal) + c.offset * a.normal.cross(b.normal)) / det;
}

/// The cull callback on instance i's node: traverses only when the nested test kept it.
class InstanceCullCallback : public osg::NodeCallback {
 public:
  InstanceCullCallback() = default;
  InstanceCullCallback(NestedFrustumCuller::Visibility* visibility, std::size_t instance)
      : visibility_(visibility), instance_(instance) {}
  InstanceCullCallback(const InstanceCullCallback& other, const osg::CopyOp& copyop)
      : osg::Object(other, copyop), osg::Callback(other, copyop), osg::NodeCallback(other, copyop),
        visibility_(other.visibility_), instance_(other.instance_) {}
  META_Object(nestwalk, InstanceCullCallback);

  void retarget(NestedFrustumCuller::Visibility* visibility, std::size_t instance) {
    visibility_ = visibility;
    instance_ = instance;
  }
  void operator()(osg::Node* node, osg::NodeVisitor* nv) override {
    if (!visibility_ || instance_ >= visibility_->flags.size() || visibility_->flags[instance_]) traverse(node, nv);
  }

 private:
  osg::ref_ptr<NestedFrustumCuller::Visibility> visibility_;
  std::size_t instance_ = 0;
};

/// Our callback in a node's chain of cull callbacks, or null.
InstanceCullCallback* findInstanceCallback(osg::Node& node) {
  for (osg::Callback* c = node.getCullCallback(); c; c = c->getNestedCallback())
    if (auto* ours = dynamic_cast<InstanceCullCallback*>(c)) return ours;
  return nullptr;
}

}  // namespace

Frustum Frustum::fromMatrices(const osg::Matrixd& viewLocal, const osg::Matrixd& projection) {
  const osg::Matrixd m = viewLocal * projection;  // row vectors: clip = p * viewLocal * projection
  Frustum f;
  f.planes[kLeft] = planeOf(m, 0, +1.0);
  f.planes[kRight] = planeOf(m, 0, -1.0);
  f.planes[kBottom] = planeOf(m, 1, +1.0);
  f.planes[kTop] = planeOf(m, 1, -1.0);
  f.planes[kNear] = planeOf(m, 2, +1.0);
  f.planes[kFar] = planeOf(m, 2, -1.0);
  for (int i = 0; i < 8; ++i)
    f.corners[i] = meetingPoint(f.planes[(i & 1) ? kRight : kLeft], f.planes[(i & 2) ? kTop : kBottom],
                                f.planes[(i & 4) ? kFar : kNear]);
  return f;
}

NestedFrustumCuller::NestedFrustumCuller(const Scene& scene) : visibility_(new Visibility) {
  const std::size_t n = scene.instances.size();
  if (n > std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument("NestedFrustumCuller: more than 2^32 - 1 instances");
  for (int k = 0; k < 3; ++k) {
    boxMin_[k].resize(n);
    boxMax_[k].resize(n);
  }
  inner_.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const NestedVolume<double>& v = scene.instances[i].volume;
    for (int k = 0; k < 3; ++k) {
      boxMin_[k][i] = v.outer.min[k];
      boxMax_[k][i] = v.outer.max[k];
    }
    inner_.push_back(v.inner);
    magnitude_ = std::max({magnitude_, v.outer.min.cwiseAbs().maxCoeff(), v.outer.max.cwiseAbs().maxCoeff(),
                           v.inner.center.cwiseAbs().maxCoeff() + v.inner.halfExtents.sum()});
  }
  kept_.resize(n);
  straddling_.resize(n);
  visibility_->flags.assign(n, 1);
}

NestedFrustumCuller::~NestedFrustumCuller() = default;

bool NestedFrustumCuller::visible(std::size_t instance) const { return visibility_->flags.at(instance) != 0; }

std::size_t NestedFrustumCuller::classifyAabbs(const Frustum& frustum) {
  // One plane at a time over the instances still in (compacted in place in kept_): most instances
  // leave at the first side planes, so the later planes see only the few near the view.
  const std::size_t n = size();
  std::uint32_t* const kept = kept_.data();
  std::uint8_t* const straddling = straddling_.data();
  std::size_t alive = n;
  for (int j = 0; j < Frustum::kPlaneCount; ++j) {
    const FrustumPlane& plane = frustum.planes[j];
    const double nx = plane.normal.x(), ny = plane.normal.y(), nz = plane.normal.z(), d = plane.offset;
    const double slack = slack_[j];
    // The p-vertex (the corner furthest along the inward normal) decides "outside"; the n-vertex
    // (the opposite corner) decides "entirely inside".
    const double* const px = (nx >= 0 ? boxMax_[0] : boxMin_[0]).data();
    const double* const py = (ny >= 0 ? boxMax_[1] : boxMin_[1]).data();
    const double* const pz = (nz >= 0 ? boxMax_[2] : boxMin_[2]).data();
    const double* const qx = (nx >= 0 ? boxMin_[0] : boxMax_[0]).data();
    const double* const qy = (ny >= 0 ? boxMin_[1] : boxMax_[1]).data();
    const double* const qz = (nz >= 0 ? boxMin_[2] : boxMax_[2]).data();
    // Instance i's verdict on this plane: the survivors go on, first in kept.
    std::size_t stillIn = 0;
    const auto test = [&](std::uint32_t i, std::uint8_t straddlingBefore) {
      const double pDistance = nx * px[i] + ny * py[i] + nz * pz[i] + d;
      const double nDistance = nx * qx[i] + ny * qy[i] + nz * qz[i] + d;
      straddling[i] = straddlingBefore | std::uint8_t(nDistance < 0);
      kept[stillIn] = i;
      stillIn += !(pDistance < -slack);
    };
    if (j == 0) {
      for (std::size_t i = 0; i < n; ++i) test(std::uint32_t(i), 0);
    } else {
      for (std::size_t k = 0; k < alive; ++k) test(kept[k], straddling[kept[k]]);
    }
    alive = stillIn;
  }
  return alive;
}

bool NestedFrustumCuller::obbOutside(std::size_t instance, const Frustum& frustum) const {
  const Obb<double>& b = inner_[instance];
  for (int j = 0; j < Frustum::kPlaneCount; ++j) {
    const FrustumPlane& plane = frustum.planes[j];
    const double radius = (b.axes.transpose() * plane.normal).cwiseAbs().dot(b.halfExtents);
    if (plane.distance(b.center) + radius < -slack_[j]) return true;
  }
  return false;
}

const CullCounts& NestedFrustumCuller::update(const Frustum& frustum) {
  const auto start = std::chrono::steady_clock::now();
  for (int j = 0; j < Frustum::kPlaneCount; ++j) {
    const FrustumPlane& plane = frustum.planes[j];
    slack_[j] = kSlackRoundings * std::numeric_limits<double>::epsilon() *
                (std::abs(plane.offset) + plane.normal.lpNorm<1>() * magnitude_);
  }
  const std::size_t inFrustum = classifyAabbs(frustum);

  CullCounts c;
  c.instances = size();
  c.aabbOutside = size() - inFrustum;
  std::uint8_t* const flags = visibility_->flags.data();
  std::fill(visibility_->flags.begin(), visibility_->flags.end(), std::uint8_t(0));
  for (std::size_t k = 0; k < inFrustum; ++k) {
    const std::uint32_t i = kept_[k];
    bool keep = true;
    if (!straddling_[i]) {
      ++c.aabbInside;
    } else {
      ++c.obbTested;
      if (obbOutside(i, frustum)) {
        ++c.obbOutside;
        keep = false;
      }
    }
    flags[i] = keep;
    c.visible += keep;
  }
  c.micros = elapsedMicros(start);
  counts_ = c;
  return counts_;
}

void NestedFrustumCuller::install(osg::Group* equipment, bool enabled) {
  if (!equipment) throw std::invalid_argument("NestedFrustumCuller::install: no equipment group");
  if (equipment->getNumChildren() != size())
    throw std::invalid_argument("NestedFrustumCuller::install: the group has " +
                                std::to_string(equipment->getNumChildren()) + " children for " +
                                std::to_string(size()) + " instances");
  for (std::size_t i = 0; i < size(); ++i) {
    osg::Node& child = *equipment->getChild(unsigned(i));
    InstanceCullCallback* ours = findInstanceCallback(child);
    if (enabled) {
      if (ours) ours->retarget(visibility_.get(), i);
      else child.addCullCallback(new InstanceCullCallback(visibility_.get(), i));
      child.setCullingActive(false);
    } else {
      if (ours) child.removeCullCallback(ours);
      child.setCullingActive(true);
    }
  }
}

CullCounts sphereCull(const std::vector<osg::BoundingSphere>& spheres, const Frustum& frustum) {
  const auto start = std::chrono::steady_clock::now();
  osg::Polytope polytope;
  for (const FrustumPlane& p : frustum.planes)
    polytope.add(osg::Plane(p.normal.x(), p.normal.y(), p.normal.z(), p.offset));
  CullCounts c;
  c.instances = spheres.size();
  for (const osg::BoundingSphere& s : spheres) c.visible += !s.valid() || polytope.contains(s);
  c.micros = elapsedMicros(start);
  return c;
}

}  // namespace nestwalk
