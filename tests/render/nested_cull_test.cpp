// Nested frustum culling (engine/render/nested_cull.h) against independent references: frustum
// corners from the inverted view-projection matrix (long double), an exact separating-axis test
// between the frustum (its 8 corners) and a box, point-in-frustum for the geometry itself, OSG's own
// frustum (osg::Polytope::setToUnitFrustum through the matrices), and a real osgUtil cull traversal
// (SceneView, no GL context needed for culling) that shows which instances get traversed.
#include "nestwalk/render/nested_cull.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/render/scene_graph.h"
#include "nestwalk/scene/scene_loader.h"
#include "tests/common/build_paths.h"
#include "tests/scene/scene_test_util.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <nlohmann/json.hpp>
#include <osg/MatrixTransform>
#include <osg/Polytope>
#include <osgUtil/SceneView>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <numbers>
#include <random>
#include <set>

namespace nestwalk {
namespace {

using Real = long double;
using RVec3 = Eigen::Matrix<Real, 3, 1>;
using Json = nlohmann::json;

/// A UTM-like scene origin (zone 51N magnitudes), as loadScene would choose one.
const Eigen::Vector3d kUtmOrigin(551234.5, 4652345.25, 0.0);

osg::Vec3d toOsg(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// ---------------------------------------------------------------------------------------------
// References

/// The frustum from its 8 corners, computed by inverting view * projection in long double and
/// mapping the NDC cube's corners back (corner i: bit 0 x = +1, bit 1 y = +1, bit 2 z = +1 (far)).
struct ReferenceFrustum {
  std::array<RVec3, 8> corners;
  std::array<RVec3, 6> normals;  // inward unit normals of the faces, from cross products of edges
  std::array<Real, 6> offsets;
  std::vector<RVec3> edges;      // edge directions
  Real scale = 0;                // the largest distance between two corners

  Real distance(int face, const RVec3& p) const { return normals[face].dot(p) + offsets[face]; }
};

ReferenceFrustum referenceFrustum(const osg::Matrixd& viewLocal, const osg::Matrixd& projection) {
  const osg::Matrixd m = viewLocal * projection;
  Eigen::Matrix<Real, 4, 4> rowVectorMatrix;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) rowVectorMatrix(i, j) = Real(m(i, j));
  const Eigen::Matrix<Real, 4, 4> inverse = rowVectorMatrix.inverse();
  ReferenceFrustum f;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Matrix<Real, 1, 4> ndc((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1, 1);
    const Eigen::Matrix<Real, 1, 4> h = ndc * inverse;
    f.corners[i] = h.head<3>().transpose() / h[3];
  }
  RVec3 centroid = RVec3::Zero();
  for (const auto& c : f.corners) centroid += c / 8;
  // Faces in Frustum::Side order: left, right, bottom, top, near, far (three corners of each).
  const int faces[6][3] = {{0, 2, 4}, {1, 3, 5}, {0, 1, 4}, {2, 3, 6}, {0, 1, 2}, {4, 5, 6}};
  for (int k = 0; k < 6; ++k) {
    const RVec3& a = f.corners[faces[k][0]];
    RVec3 n = (f.corners[faces[k][1]] - a).cross(f.corners[faces[k][2]] - a).normalized();
    if (n.dot(centroid - a) < 0) n = -n;
    f.normals[k] = n;
    f.offsets[k] = -n.dot(a);
  }
  for (const auto& [a, b] : {std::pair{0, 1}, {0, 2}, {4, 5}, {4, 6}, {0, 4}, {1, 5}, {2, 6}, {3, 7}})
    f.edges.push_back(f.corners[b] - f.corners[a]);
  for (const auto& a : f.corners)
    for (const auto& b : f.corners) f.scale = std::max(f.scale, (a - b).norm());
  return f;
}

/// A box in long double: centre, axes (columns), half extents.
struct ReferenceBox {
  RVec3 center;
  Eigen::Matrix<Real, 3, 3> axes;
  RVec3 half;
};
ReferenceBox referenceBox(const Aabb<double>& b) {
  return {(b.min.cast<Real>() + b.max.cast<Real>()) / 2, Eigen::Matrix<Real, 3, 3>::Identity(),
          (b.max.cast<Real>() - b.min.cast<Real>()) / 2};
}
ReferenceBox referenceBox(const Obb<double>& b) {
  return {b.center.cast<Real>(), b.axes.cast<Real>(), b.halfExtents.cast<Real>()};
}

/// The exact separating-axis test between the convex frustum and a box: the largest gap between
/// their projections over the frustum's face normals, the box's axes and the cross products of
/// their edge directions. > 0: separated by that much; <= 0: they intersect (touching at 0).
Real separation(const ReferenceFrustum& f, const ReferenceBox& box) {
  std::vector<RVec3> axes(f.normals.begin(), f.normals.end());
  for (int k = 0; k < 3; ++k) {
    const RVec3 a = box.axes.col(k);
    axes.push_back(a);
    for (const RVec3& e : f.edges) {
      const RVec3 c = e.cross(a);
      if (c.norm() > Real(1e-12) * e.norm()) axes.push_back(c);
    }
  }
  Real gap = -std::numeric_limits<Real>::infinity();
  for (RVec3 axis : axes) {
    axis.normalize();
    Real lo = std::numeric_limits<Real>::infinity(), hi = -lo;
    for (const RVec3& c : f.corners) {
      lo = std::min(lo, axis.dot(c));
      hi = std::max(hi, axis.dot(c));
    }
    const Real center = axis.dot(box.center);
    const Real radius = (box.axes.transpose() * axis).cwiseAbs().dot(box.half);
    gap = std::max({gap, lo - (center + radius), (center - radius) - hi});
  }
  return gap;
}

/// The smallest signed distance of a point to the faces (> 0: strictly inside).
Real insideDepth(const ReferenceFrustum& f, const RVec3& p) {
  Real d = std::numeric_limits<Real>::infinity();
  for (int k = 0; k < 6; ++k) d = std::min(d, f.distance(k, p));
  return d;
}

/// An AABB-only plane test written out: culled when all 8 corners lie beyond one face by more than tol.
bool aabbCornersBeyondAFace(const ReferenceFrustum& f, const Aabb<double>& b, Real tol) {
  for (int k = 0; k < 6; ++k) {
    bool allOutside = true;
    for (int i = 0; i < 8 && allOutside; ++i) {
      const RVec3 c(Real((i & 1) ? b.max.x() : b.min.x()), Real((i & 2) ? b.max.y() : b.min.y()),
                    Real((i & 4) ? b.max.z() : b.min.z()));
      allOutside = f.distance(k, c) < -tol;
    }
    if (allOutside) return true;
  }
  return false;
}

/// OSG's own cull frustum for the same matrices, as osgUtil's CullStack builds it.
osg::Polytope osgFrustum(const osg::Matrixd& viewLocal, const osg::Matrixd& projection) {
  osg::Polytope p;
  p.setToUnitFrustum(true, true);
  p.transformProvidingInverse(viewLocal * projection);
  return p;
}

// ---------------------------------------------------------------------------------------------
// Random cameras and boxes

double uniform(std::mt19937_64& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }

/// A uniformly random rotation (a normalized 4D Gaussian as a quaternion).
Eigen::Matrix3d randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> gauss;
  return Eigen::Quaterniond(gauss(rng), gauss(rng), gauss(rng), gauss(rng)).normalized().toRotationMatrix();
}

struct Camera {
  Eigen::Vector3d eyeLocal;
  osg::Matrixd viewMap;          // map -> eye
  osg::Matrixd viewLocal;        // local -> eye, as the renderer composes it: translate(origin) * viewMap
  osg::Matrixd viewLocalDirect;  // local -> eye, lookAt at the local eye (the reference's)
  osg::Matrixd projection;
};

/// A camera at a UTM-like eye position: eye within a few hundred metres of the origin, some 200 m
/// up, looking in a random direction; perspective (symmetric or not) or orthographic projection.
Camera randomCamera(std::mt19937_64& rng, double farLo, double farHi) {
  Camera c;
  c.eyeLocal = {uniform(rng, -300, 300), uniform(rng, -300, 300), uniform(rng, 180, 260)};
  const Eigen::Vector3d eyeMap = kUtmOrigin + c.eyeLocal;
  const double heading = uniform(rng, 0, 2 * std::numbers::pi), pitch = uniform(rng, -1.2, 1.2);
  const Eigen::Vector3d dir(std::sin(heading) * std::cos(pitch), std::cos(heading) * std::cos(pitch), std::sin(pitch));
  const osg::Vec3d up(0, 0, 1);
  c.viewMap = osg::Matrixd::lookAt(toOsg(eyeMap), toOsg(eyeMap + dir), up);
  c.viewLocal = osg::Matrixd::translate(toOsg(kUtmOrigin)) * c.viewMap;
  c.viewLocalDirect = osg::Matrixd::lookAt(toOsg(c.eyeLocal), toOsg(c.eyeLocal + dir), up);
  const double nearPlane = uniform(rng, 0.1, 2.0), farPlane = uniform(rng, farLo, farHi);
  const int kind = int(rng() % 4);
  if (kind == 0) {
    const double w = uniform(rng, 0.05, 1.5) * nearPlane, h = uniform(rng, 0.05, 1.5) * nearPlane;
    c.projection = osg::Matrixd::frustum(-w * uniform(rng, 0.2, 1.8), w, -h, h * uniform(rng, 0.2, 1.8), nearPlane, farPlane);
  } else if (kind == 1) {
    const double w = uniform(rng, 5, 200), h = uniform(rng, 5, 200);
    c.projection = osg::Matrixd::ortho(-w, w * uniform(rng, 0.2, 1.5), -h, h, nearPlane, farPlane);
  } else {
    c.projection = osg::Matrixd::perspective(uniform(rng, 15, 100), uniform(rng, 0.5, 2.4), nearPlane, farPlane);
  }
  return c;
}

/// Random geometry near a frustum: a cloud of points, its exact AABB, and an OBB containing it
/// (in the cloud's own frame, or in a random frame, sometimes padded).
struct RandomObject {
  std::vector<Eigen::Vector3d> points;
  NestedVolume<double> volume;
};

RandomObject randomObject(std::mt19937_64& rng, const ReferenceFrustum& f) {
  // The centre: a trilinear blend of the corners, reaching a little beyond the frustum.
  const double s = uniform(rng, -0.25, 1.25), t = uniform(rng, -0.25, 1.25), u = std::pow(uniform(rng, 0, 1), 2.0) * 1.3 - 0.1;
  RVec3 c = RVec3::Zero();
  for (int i = 0; i < 8; ++i)
    c += f.corners[i] * Real(((i & 1) ? s : 1 - s) * ((i & 2) ? t : 1 - t) * ((i & 4) ? u : 1 - u));
  const Eigen::Vector3d center = c.cast<double>();
  const double size = std::exp(uniform(rng, std::log(0.05), std::log(0.15 * double(f.scale))));
  const Eigen::Vector3d extent(size * uniform(rng, 0.02, 1), size * uniform(rng, 0.02, 1), size * uniform(rng, 0.02, 1));
  const Eigen::Matrix3d cloudFrame = randomRotation(rng);
  RandomObject o;
  for (int k = 0; k < 10; ++k) {
    const Eigen::Vector3d q(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    o.points.push_back(center + cloudFrame * q.cwiseProduct(extent));
  }
  for (const auto& p : o.points) o.volume.outer.extend(p);
  const Eigen::Matrix3d obbFrame = (rng() % 3 == 0) ? randomRotation(rng) : cloudFrame;
  Aabb<double> inFrame;
  for (const auto& p : o.points) inFrame.extend(Eigen::Vector3d(obbFrame.transpose() * p));
  const double pad = (rng() % 4 == 0) ? uniform(rng, 0, 0.3) * size : 0.0;
  o.volume.inner = {obbFrame * inFrame.center(), obbFrame, inFrame.halfExtents() + Eigen::Vector3d::Constant(pad + 1e-9 * size)};
  return o;
}

/// A scene holding only instances with these volumes (all the culler reads).
Scene sceneOfVolumes(const std::vector<NestedVolume<double>>& volumes) {
  Scene scene;
  scene.instances.resize(volumes.size());
  for (std::size_t i = 0; i < volumes.size(); ++i) scene.instances[i].volume = volumes[i];
  return scene;
}

void expectCountsAddUp(const CullCounts& c, const NestedFrustumCuller& culler) {
  EXPECT_EQ(c.instances, culler.size());
  EXPECT_EQ(c.aabbOutside + c.aabbInside + c.obbTested, c.instances);
  EXPECT_LE(c.obbOutside, c.obbTested);
  EXPECT_EQ(c.visible, c.instances - c.aabbOutside - c.obbOutside);
  std::uint64_t flagged = 0;
  for (std::size_t i = 0; i < culler.size(); ++i) flagged += culler.visible(i);
  EXPECT_EQ(flagged, c.visible);
}

// ---------------------------------------------------------------------------------------------
// Tests

TEST(NestedCullFrustum, PlanesPassThroughTheCornersOfTheInvertedMatrix) {
  std::mt19937_64 rng(20240611);
  for (int trial = 0; trial < 200; ++trial) {
    const Camera cam = randomCamera(rng, 50, 5000);
    const Frustum f = Frustum::fromMatrices(cam.viewLocal, cam.projection);
    const ReferenceFrustum ref = referenceFrustum(cam.viewLocalDirect, cam.projection);
    const double tol = 1e-9 * double(ref.scale);  // 1e-9 relative to the frustum's size
    for (int i = 0; i < 8; ++i) {
      const int own[3] = {(i & 1) ? Frustum::kRight : Frustum::kLeft, (i & 2) ? Frustum::kTop : Frustum::kBottom,
                          (i & 4) ? Frustum::kFar : Frustum::kNear};
      const Eigen::Vector3d corner = ref.corners[i].cast<double>();
      for (int k = 0; k < Frustum::kPlaneCount; ++k) {
        const double d = f.planes[k].distance(corner);
        if (k == own[0] || k == own[1] || k == own[2])
          EXPECT_LE(std::abs(d), tol) << "trial " << trial << " corner " << i << " plane " << k;
        else
          EXPECT_GE(d, -tol) << "trial " << trial << " corner " << i << " is outside plane " << k;
      }
      EXPECT_LE((f.corners[i] - corner).norm(), tol) << "trial " << trial << " corner " << i;
    }
    for (const auto& p : f.planes) EXPECT_NEAR(p.normal.norm(), 1.0, 1e-14);
    // The eye side: the near plane's normal points away from the eye (forward).
    EXPECT_LT(f.planes[Frustum::kNear].distance(cam.eyeLocal), 0.0) << "trial " << trial;
  }
}

TEST(NestedCullConservative, NeverCullsWhatTheExactTestsKeep) {
  std::mt19937_64 rng(7);
  std::uint64_t objects = 0, culled = 0, exactCullsKept = 0, pointsSeen = 0;
  CullCounts total;
  for (int trial = 0; trial < 60; ++trial) {
    const Camera cam = randomCamera(rng, 30, 600);
    const ReferenceFrustum ref = referenceFrustum(cam.viewLocalDirect, cam.projection);
    const Real tol = Real(1e-9) * ref.scale;
    std::vector<RandomObject> objs;
    std::vector<NestedVolume<double>> volumes;
    for (int k = 0; k < 300; ++k) {
      objs.push_back(randomObject(rng, ref));
      volumes.push_back(objs.back().volume);
    }
    const Scene scene = sceneOfVolumes(volumes);
    NestedFrustumCuller culler(scene);
    const CullCounts& c = culler.update(Frustum::fromMatrices(cam.viewLocal, cam.projection));
    expectCountsAddUp(c, culler);
    total.aabbOutside += c.aabbOutside;
    total.aabbInside += c.aabbInside;
    total.obbTested += c.obbTested;
    total.obbOutside += c.obbOutside;
    for (std::size_t i = 0; i < objs.size(); ++i) {
      const Real gap = std::max(separation(ref, referenceBox(volumes[i].outer)), separation(ref, referenceBox(volumes[i].inner)));
      const bool kept = culler.visible(i);
      ++objects;
      culled += !kept;
      if (!kept) {
        EXPECT_GT(gap, -tol) << "trial " << trial << " object " << i << ": culled although both boxes intersect the frustum";
        for (const auto& p : objs[i].points) {
          const bool inside = insideDepth(ref, p.cast<Real>()) > tol;
          pointsSeen += inside;
          EXPECT_FALSE(inside) << "trial " << trial << " object " << i << ": culled with a point inside the frustum";
        }
      }
      if (aabbCornersBeyondAFace(ref, volumes[i].outer, tol)) {
        EXPECT_FALSE(kept) << "trial " << trial << " object " << i << ": the AABB plane test culls it";
      }
      if (kept && gap > tol) ++exactCullsKept;
    }
  }
  std::printf("[ conservative ] %llu objects, %llu culled (AABB %llu, OBB %llu of %llu tested, %llu AABB-inside); "
              "the exact box-frustum test would also cull %llu that the plane tests keep\n",
              (unsigned long long)objects, (unsigned long long)culled, (unsigned long long)total.aabbOutside,
              (unsigned long long)total.obbOutside, (unsigned long long)total.obbTested,
              (unsigned long long)total.aabbInside, (unsigned long long)exactCullsKept);
  EXPECT_EQ(pointsSeen, 0u);
  // Sanity: every stage did something, and the plane tests miss only a minority of exact culls.
  EXPECT_GT(total.aabbOutside, 0u);
  EXPECT_GT(total.aabbInside, 0u);
  EXPECT_GT(total.obbOutside, 0u);
  EXPECT_LT(exactCullsKept, objects - culled);
}

TEST(NestedCullPole, DiagonalPoleWhoseAabbStraddlesIsCulledByTheObb) {
  // Eye at the local origin looking north (+y), 60 degrees both ways: the right plane is x = y tan 30.
  const osg::Matrixd view = osg::Matrixd::lookAt(osg::Vec3d(0, 0, 0), osg::Vec3d(0, 1, 0), osg::Vec3d(0, 0, 1));
  const osg::Matrixd projection = osg::Matrixd::perspective(60.0, 1.0, 0.5, 100.0);
  const Frustum frustum = Frustum::fromMatrices(view, projection);
  const ReferenceFrustum ref = referenceFrustum(view, projection);

  // A 14 m pole, 10 cm thick, from (8, 5, 0) to (18, 15, 0): both ends right of the right plane,
  // while its AABB's corner (8, 15) is inside it.
  const Eigen::Vector3d u = Eigen::Vector3d(1, 1, 0).normalized(), v = Eigen::Vector3d(-1, 1, 0).normalized();
  Eigen::Matrix3d axes;
  axes << u, v, Eigen::Vector3d::UnitZ();
  const Obb<double> pole{{13, 10, 0}, axes, {std::sqrt(200.0) / 2, 0.05, 0.05}};
  // The same pole in front of the eye, and one behind it.
  const Obb<double> ahead{{0, 30, 0}, axes, pole.halfExtents}, behind{{0, -30, 0}, axes, pole.halfExtents};
  const Scene scene = sceneOfVolumes({NestedVolume<double>::fromObb(pole), NestedVolume<double>::fromObb(ahead),
                                      NestedVolume<double>::fromObb(behind)});
  ASSERT_GT(separation(ref, referenceBox(pole)), 0.5) << "the pole misses the frustum";
  ASSERT_LT(separation(ref, referenceBox(aabbOf(pole))), 0.0) << "its AABB meets the frustum";

  NestedFrustumCuller culler(scene);
  const CullCounts& c = culler.update(frustum);
  expectCountsAddUp(c, culler);
  EXPECT_FALSE(culler.visible(0));
  EXPECT_TRUE(culler.visible(1));
  EXPECT_FALSE(culler.visible(2));
  EXPECT_EQ(c.aabbOutside, 1u);  // behind
  EXPECT_EQ(c.aabbInside, 1u);   // ahead
  EXPECT_EQ(c.obbTested, 1u);    // the pole
  EXPECT_EQ(c.obbOutside, 1u);
  EXPECT_EQ(c.visible, 1u);
}

TEST(NestedCullSphere, CountsWhatOsgPolytopeKeeps) {
  std::mt19937_64 rng(99);
  for (int trial = 0; trial < 40; ++trial) {
    const Camera cam = randomCamera(rng, 30, 800);
    const Frustum f = Frustum::fromMatrices(cam.viewLocal, cam.projection);
    const ReferenceFrustum ref = referenceFrustum(cam.viewLocalDirect, cam.projection);
    osg::Polytope osgOwn = osgFrustum(cam.viewLocal, cam.projection);
    std::vector<osg::BoundingSphere> spheres;
    std::uint64_t expected = 0;
    while (spheres.size() < 400) {
      const RandomObject o = randomObject(rng, ref);
      const Eigen::Vector3d c = o.volume.outer.center();
      const osg::BoundingSphere s(osg::Vec3(float(c.x()), float(c.y()), float(c.z())), float(o.volume.outer.size().norm() / 2));
      // Leave out spheres within a millimetre of touching a plane: OSG's planes and ours differ by
      // rounding there.
      bool borderline = false;
      for (const auto& p : f.planes)
        borderline |= std::abs(std::abs(p.distance({s.center().x(), s.center().y(), s.center().z()})) - s.radius()) < 1e-3;
      if (borderline) continue;
      spheres.push_back(s);
      expected += osgOwn.contains(s);
    }
    spheres.push_back(osg::BoundingSphere());  // invalid: kept, as OSG keeps a node without bounds
    ++expected;
    const CullCounts c = sphereCull(spheres, f);
    EXPECT_EQ(c.instances, spheres.size());
    EXPECT_EQ(c.visible, expected) << "trial " << trial;
    EXPECT_GE(c.micros, 0.0);
  }
}

/// Records which instances (children of the equipment group) a cull traversal reached: a cull
/// callback on the shared model node, reading its parent transform off the node path.
class ReachedInstances : public osg::NodeCallback {
 public:
  explicit ReachedInstances(osg::Group* equipment) : equipment_(equipment) {}
  void operator()(osg::Node* node, osg::NodeVisitor* nv) override {
    const osg::NodePath& path = nv->getNodePath();
    if (path.size() >= 2) reached.insert(equipment_->getChildIndex(path[path.size() - 2]));
    traverse(node, nv);
  }
  std::set<unsigned> reached;

 private:
  osg::Group* equipment_;
};

osg::Group* childGroupNamed(osg::Group& g, const std::string& name) {
  for (unsigned i = 0; i < g.getNumChildren(); ++i)
    if (g.getChild(i)->getName() == name) return g.getChild(i)->asGroup();
  return nullptr;
}

osg::Group* equipmentGroup(osg::Group& root) {
  osg::Group* localToMap = childGroupNamed(root, "local_to_map");
  return localToMap ? childGroupNamed(*localToMap, "equipment") : nullptr;
}

/// One real cull traversal of `root` (osgUtil::SceneView::cull, which needs no GL context), with all
/// six frustum planes and no small-feature culling.
void cullOnce(osg::Node* root, const osg::Matrixd& viewMap, const osg::Matrixd& projection) {
  osg::ref_ptr<osgUtil::SceneView> view = new osgUtil::SceneView;
  view->setDefaults();
  view->setComputeNearFarMode(osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);
  view->setCullingMode(osg::CullSettings::VIEW_FRUSTUM_CULLING);
  view->setViewport(0, 0, 640, 480);
  view->setSceneData(root);
  view->setViewMatrix(viewMap);
  view->setProjectionMatrix(projection);
  view->cull();
}

std::vector<osg::BoundingSphere> childBounds(osg::Group& equipment) {
  std::vector<osg::BoundingSphere> spheres;
  for (unsigned i = 0; i < equipment.getNumChildren(); ++i) spheres.push_back(equipment.getChild(i)->getBound());
  return spheres;
}

class NestedCullInstall : public test::TempFolderTest {};

TEST_F(NestedCullInstall, CulledInstancesAreNotTraversedByARealCullTraversal) {
  // A small real scene at UTM magnitudes: a planar terrain and 36 weather stations on a grid.
  test::PlaneTerrain terrain;
  terrain.west = 550000.0;
  terrain.north = 4650065.0;
  test::writePlaneTiff(dir() / "terrain.tif", terrain);
  Json equipment = Json::array();
  for (int a = 0; a < 6; ++a)
    for (int b = 0; b < 6; ++b)
      equipment.push_back({{"model", test::weatherStation()},
                           {"position", {terrain.sampleX(4.5 + 11 * a), terrain.sampleY(4.5 + 11 * b)}},
                           {"heading", 17 * (a * 6 + b)}});
  test::writeText(dir() / "scene.json", Json{{"terrain", "terrain.tif"}, {"equipment", equipment}}.dump());
  const Scene scene = loadScene((dir() / "scene.json").string());
  ASSERT_EQ(scene.instances.size(), 36u);
  SceneGraphOptions graphOptions;
  graphOptions.terrain = false;
  SceneGraphParts parts;
  const osg::ref_ptr<osg::Group> root = buildSceneGraph(scene, graphOptions, &parts);
  osg::Group* equipmentNode = equipmentGroup(*root);
  ASSERT_NE(equipmentNode, nullptr);

  // Observe the shared model node: what reaches it is what the instance nodes let through (and,
  // while its own OSG test is on, what that test keeps of it).
  osg::Node* model = parts.modelNodes[0].get();
  osg::ref_ptr<ReachedInstances> reached = new ReachedInstances(equipmentNode);
  model->addCullCallback(reached);
  const auto reachedBy = [&](const osg::Matrixd& viewMap, const osg::Matrixd& projection) {
    reached->reached.clear();
    cullOnce(root, viewMap, projection);
    return reached->reached;
  };

  NestedFrustumCuller culler(scene);
  culler.install(equipmentNode);
  culler.install(equipmentNode);  // twice: still one callback
  int callbacks = 0;
  for (osg::Callback* c = equipmentNode->getChild(0)->getCullCallback(); c; c = c->getNestedCallback()) ++callbacks;
  EXPECT_EQ(callbacks, 1);
  EXPECT_FALSE(equipmentNode->getChild(0)->getCullingActive());

  // Eyes 2 m above the ground, looking around from the middle and across from two edges, 10 degrees
  // down; a narrow view so that many stations stand near its side planes.
  const struct {
    double column, row, headingDeg;
  } views[] = {{33, 33, 10}, {33, 33, 55}, {33, 33, 100}, {33, 33, 145}, {33, 33, 190},
               {33, 33, 235}, {33, 33, 280}, {33, 33, 325}, {2, 62, 45}, {62, 30, 250}};
  const osg::Matrixd projection = osg::Matrixd::perspective(30.0, 4.0 / 3.0, 0.5, 60.0);
  std::size_t keptByNested = 0, keptBySpheres = 0, onlyBySpheres = 0;
  for (const auto& v : views) {
    const double x = terrain.sampleX(v.column), y = terrain.sampleY(v.row);
    const Eigen::Vector3d eye(x, y, terrain.height(x, y) + 2);
    const double heading = v.headingDeg * std::numbers::pi / 180, pitch = -10 * std::numbers::pi / 180;
    const Eigen::Vector3d dir(std::sin(heading) * std::cos(pitch), std::cos(heading) * std::cos(pitch), std::sin(pitch));
    const osg::Matrixd viewMap = osg::Matrixd::lookAt(toOsg(eye), toOsg(eye + dir), osg::Vec3d(0, 0, 1));
    const Frustum frustum = Frustum::fromMatrices(osg::Matrixd::translate(toOsg(scene.origin)) * viewMap, projection);
    const CullCounts counts = culler.update(frustum);
    expectCountsAddUp(counts, culler);
    std::set<unsigned> kept;
    for (unsigned i = 0; i < culler.size(); ++i)
      if (culler.visible(i)) kept.insert(i);

    // The model's own OSG test off: the traversal reaches exactly the instances the culler keeps.
    model->setCullingActive(false);
    EXPECT_EQ(reachedBy(viewMap, projection), kept) << "heading " << v.headingDeg;
    // On (as drawn): OSG's test below the instance can only leave out more.
    model->setCullingActive(true);
    const std::set<unsigned> drawn = reachedBy(viewMap, projection);
    EXPECT_TRUE(std::includes(kept.begin(), kept.end(), drawn.begin(), drawn.end()));

    // OSG's own culling back on the instances: the traversal reaches what the bounding spheres keep.
    culler.install(equipmentNode, false);
    EXPECT_EQ(equipmentNode->getChild(0)->getCullCallback(), nullptr);
    EXPECT_TRUE(equipmentNode->getChild(0)->getCullingActive());
    const std::set<unsigned> bySpheres = reachedBy(viewMap, projection);
    EXPECT_EQ(bySpheres.size(), sphereCull(childBounds(*equipmentNode), frustum).visible);
    culler.install(equipmentNode);

    keptByNested += kept.size();
    keptBySpheres += bySpheres.size();
    for (unsigned i : bySpheres) onlyBySpheres += !kept.count(i);
  }
  std::printf("[ install ] %zu views of %zu stations: the traversal reached %zu by the nested test, %zu by OSG's "
              "spheres (%zu only by the spheres)\n",
              std::size(views), culler.size(), keptByNested, keptBySpheres, onlyBySpheres);
  // The two tests differ on these views, so the traversal really follows the nested test.
  EXPECT_GT(onlyBySpheres, 0u);
  EXPECT_GT(keptByNested, 0u);
  EXPECT_THROW(culler.install(nullptr), std::invalid_argument);
  osg::ref_ptr<osg::Group> tooSmall = new osg::Group;
  EXPECT_THROW(culler.install(tooSmall), std::invalid_argument);
}

TEST(NestedCullBundled, KeepsNoMoreThanOsgSpheresAtGroundLevel) {
  const std::filesystem::path scenePath = std::filesystem::path(nestwalk::test::build::bundledSceneDir()) / "scene.json";
  if (!std::filesystem::exists(scenePath))
    GTEST_SKIP() << "the bundled scene is absent (" << scenePath << "); build the bundled_scene target";
  const Scene scene = loadScene(scenePath.string());
  SceneGraphOptions graphOptions;
  graphOptions.terrain = false;
  const osg::ref_ptr<osg::Group> root = buildSceneGraph(scene, graphOptions);
  osg::Group* equipment = equipmentGroup(*root);
  ASSERT_NE(equipment, nullptr);
  const std::vector<osg::BoundingSphere> spheres = childBounds(*equipment);
  NestedFrustumCuller culler(scene);

  const osg::Matrixd projection = osg::Matrixd::perspective(60.0, 16.0 / 9.0, 0.3, 2000.0);
  std::vector<double> nestedMicros, sphereMicros;
  int views = 0;
  for (int k = 0; k < 6; ++k) {
    // An eye 1.7 m above the ground, 12 m south-west of an instance, looking four ways.
    const Eigen::Vector3d at = scene.instances[k * scene.instances.size() / 6].toLocal.translation;
    const Eigen::Vector3d map = scene.toMap(at + Eigen::Vector3d(-12, -12, 0));
    const auto ground = scene.terrain->groundHeight(map.x(), map.y());
    if (!ground) continue;
    const Eigen::Vector3d eye = scene.toLocal({map.x(), map.y(), *ground + 1.7});
    for (int h = 0; h < 4; ++h) {
      const double heading = (45 + 90 * h) * std::numbers::pi / 180;
      const Eigen::Vector3d dir(std::sin(heading), std::cos(heading), -0.05);
      const Frustum f = Frustum::fromMatrices(osg::Matrixd::lookAt(toOsg(eye), toOsg(eye + dir), osg::Vec3d(0, 0, 1)), projection);
      const CullCounts nested = culler.update(f);
      const CullCounts sphere = sphereCull(spheres, f);
      expectCountsAddUp(nested, culler);
      EXPECT_LE(nested.visible, sphere.visible) << "view " << k << "/" << h;
      std::printf("[ bundled ] view %d/%d: nested keeps %llu (AABB culled %llu, inside %llu, OBB culled %llu of %llu), "
                  "OSG spheres keep %llu of %llu\n",
                  k, h, (unsigned long long)nested.visible, (unsigned long long)nested.aabbOutside,
                  (unsigned long long)nested.aabbInside, (unsigned long long)nested.obbOutside,
                  (unsigned long long)nested.obbTested, (unsigned long long)sphere.visible,
                  (unsigned long long)sphere.instances);
      for (int r = 0; r < 50; ++r) {
        nestedMicros.push_back(culler.update(f).micros);
        sphereMicros.push_back(sphereCull(spheres, f).micros);
      }
      ++views;
    }
  }
  ASSERT_GT(views, 0) << "no instance with ground 12 m south-west of it";
  const auto minAndMedian = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return std::pair{v.front(), v[v.size() / 2]};
  };
  const auto [nestedMin, nestedMedian] = minAndMedian(nestedMicros);
  const auto [sphereMin, sphereMedian] = minAndMedian(sphereMicros);
  std::printf("[ bundled ] %zu instances, %d views x 50: update() min %.2f us, median %.2f us; sphereCull min %.2f us, "
              "median %.2f us\n",
              culler.size(), views, nestedMin, nestedMedian, sphereMin, sphereMedian);
}

}  // namespace
}  // namespace nestwalk
