// The mesh tree (mesh_tree.h: the 18-DOP tree over a model's triangles) against the
// brute-force loops over every triangle (whose primitive, triangle_box.h, is checked against CGAL
// and FCL in its own tests), on meshes that stress them: an icosphere, a thin pole, coplanar and
// degenerate triangles, a single triangle, an empty mesh, a mesh with exponentially spaced parts,
// and a sphere at UTM magnitudes (the trees work in whatever frame the mesh is in).
//
// Queries: thousands of random boxes (random rotations or exactly axis-aligned; half extents from
// 1 mm to half the mesh, some zero) around each mesh, and boxes with a corner exactly on a mesh
// vertex (touching contact, where a bounding-volume test that is not conservative would prune a
// real contact). Asserted: overlaps() equals the brute-force verdict, every time; distance() equals
// the brute-force minimum (to 1e-12 relative: the same triangles and function, so normally bit for
// bit); the node volumes hold their triangles; the counters stay far below brute force (far boxes
// under 10% of the triangle count, as are near boxes on average). Timings are printed.
// The bundled equipment models (the bundled scene's models/, or the folder the environment
// variable NESTWALK_BUNDLED_SCENE names; skipped when absent) are read through collectModelGeometry (scene/node_geometry.h) and
// walked into by body-sized boxes: the tree equals brute force, every mesh contact is an inner-OBB
// contact, and the OBB's false contacts (OBB touched, triangles not) are printed with how far
// from the real surface they stop the viewer: the error the exact reference measures.
#include "nestwalk/geometry/mesh_tree.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/geometry/obb_fit.h"
#include "nestwalk/geometry/sat.h"
#include "nestwalk/scene/node_geometry.h"
#include "tests/geometry/test_meshes.h"
#include "tests/geometry/test_shapes.h"
#include "tests/common/test_data.h"

#include <gtest/gtest.h>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/MatrixTransform>
#include <osgDB/ReadFile>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace nestwalk {
namespace {

using V3 = Vec3<double>;
using namespace testmeshes;

// ---- Structure. ----

template <class Volume>
bool volumeHolds(const Volume& v, const V3& p);
template <>
bool volumeHolds(const Kdop18& v, const V3& p) {
  for (int k = 0; k < Kdop18::kDirections; ++k) {
    const double s = kKdopDirections[k].dot(p);
    if (s < v.min[k] || s > v.max[k]) return false;
  }
  return true;
}

template <class Tree>
void checkStructure(const Tree& tree, const TriangleMesh& mesh, int leafSize) {
  const auto& nodes = tree.nodes();
  ASSERT_EQ(tree.triangles().size(), mesh.triangles.size());
  if (mesh.triangles.empty()) {
    EXPECT_TRUE(nodes.empty());
    return;
  }
  // The tree's triangles are the mesh's, permuted.
  auto key = [](const Triangle& t) { return std::vector<double>{t[0].x(), t[0].y(), t[0].z(), t[1].x(), t[1].y(), t[1].z(), t[2].x(), t[2].y(), t[2].z()}; };
  std::vector<std::vector<double>> ours, theirs;
  for (const Triangle& t : tree.triangles()) ours.push_back(key(t));
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) theirs.push_back(key(mesh.triangle(i)));
  std::sort(ours.begin(), ours.end());
  std::sort(theirs.begin(), theirs.end());
  EXPECT_EQ(ours, theirs);
  EXPECT_EQ(nodes[0].triangleCount, mesh.triangles.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const auto& n = nodes[i];
    for (std::uint32_t t = n.firstTriangle; t < n.firstTriangle + n.triangleCount; ++t)
      for (const V3& p : tree.triangles()[t]) ASSERT_TRUE(volumeHolds(n.volume, p)) << "node " << i << " triangle " << t;
    if (n.isLeaf()) {
      EXPECT_LE(n.triangleCount, std::uint32_t(leafSize));
      continue;
    }
    const auto& left = nodes[i + 1];
    const auto& right = nodes[n.secondChild];
    EXPECT_GT(left.triangleCount, 0u);
    EXPECT_GT(right.triangleCount, 0u);
    EXPECT_EQ(left.firstTriangle, n.firstTriangle);
    EXPECT_EQ(right.firstTriangle, n.firstTriangle + left.triangleCount);
    EXPECT_EQ(left.triangleCount + right.triangleCount, n.triangleCount);
  }
  EXPECT_LE(tree.depth(), kMaxMeanSplitDepth + int(std::ceil(std::log2(double(mesh.triangles.size())))) + 1);
}

// ---- Agreement with brute force. ----

struct Agreement {
  int boxes = 0, contacts = 0;
};

template <class Tree>
Agreement checkAgainstBruteForce(const Tree& tree, const TriangleMesh& mesh, unsigned seed, int overlapBoxes,
                                 int distanceBoxes, const char* label) {
  BoxMaker maker = boxesAround(mesh, seed);
  Agreement a;
  for (int n = 0; n < overlapBoxes; ++n) {
    const bool touchingCase = !mesh.vertices.empty() && n % 5 == 0;
    const Obb<double> box = touchingCase ? maker.touching(mesh.vertices[maker.rng() % mesh.vertices.size()]) : maker.random();
    const bool reference = bruteForceOverlaps(mesh, box);
    EXPECT_EQ(tree.overlaps(box), reference) << label << " box " << n;
    ++a.boxes;
    a.contacts += reference;
  }
  for (int n = 0; n < distanceBoxes; ++n) {
    const Obb<double> box = maker.random();
    const double reference = bruteForceDistance(mesh, box);
    const double d = tree.distance(box);
    if (std::isinf(reference)) {
      EXPECT_TRUE(std::isinf(d)) << label;
    } else {
      EXPECT_NEAR(d, reference, 1e-12 * reference) << label << " distance box " << n;
    }
  }
  return a;
}

template <class Tree>
void checkTree(const char* treeName) {
  unsigned seed = 7;
  for (const NamedMesh& m : testMeshes()) {
    for (int leafSize : {1, kDefaultLeafSize}) {
      const Tree tree(m.mesh, leafSize);
      checkStructure(tree, m.mesh, leafSize);
      const bool huge = std::string(m.name) == "exponential";  // coordinates up to 1e12: a few queries
      // Leaves of one triangle: a smaller sample (the default leaves get the full one).
      const int boxes = (huge ? 200 : 2000) / (leafSize == 1 ? 4 : 1), distanceBoxes = (huge ? 20 : 100) / (leafSize == 1 ? 4 : 1);
      const Agreement a = checkAgainstBruteForce(tree, m.mesh, ++seed, boxes, distanceBoxes, m.name);
      if (leafSize == kDefaultLeafSize)
        std::printf("[%s] %-20s %5zu triangles, %5zu nodes, depth %2d: %d boxes, %d in contact, all as brute force\n",
                    treeName, m.name, m.mesh.triangles.size(), tree.nodes().size(), tree.depth(), a.boxes, a.contacts);
      if (!m.mesh.triangles.empty() && !huge) {
        EXPECT_GT(a.contacts, a.boxes / 20) << m.name;
        EXPECT_LT(a.contacts, a.boxes) << m.name;
      }
    }
  }
}

TEST(MeshTree, KdopTreeAgreesWithBruteForce) { checkTree<KdopTree>("kdop18"); }

TEST(MeshTree, EmptyMeshHasNothing) {
  const TriangleMesh empty;
  const Obb<double> box{V3::Zero(), Mat3<double>::Identity(), V3::Ones()};
  MeshQueryCounters c;
  EXPECT_FALSE(KdopTree(empty).overlaps(box, &c));
  EXPECT_TRUE(std::isinf(KdopTree(empty).distance(box, &c)));
  EXPECT_EQ(c.nodeTests + c.triangleTests, 0u);
}

TEST(MeshTree, RejectsBadInput) {
  TriangleMesh bad = singleTriangle();
  bad.triangles.push_back({0, 1, 3});
  EXPECT_THROW(KdopTree{bad}, std::invalid_argument);
  TriangleMesh nan = singleTriangle();
  nan.vertices[1].x() = std::nan("");
  EXPECT_THROW(KdopTree{nan}, std::invalid_argument);
  EXPECT_THROW(KdopTree(singleTriangle(), 0), std::invalid_argument);
}

// ---- Work and time against brute force on a 5120-triangle sphere. ----

template <class Tree>
void measure(const char* treeName, const Tree& tree, const TriangleMesh& mesh, const std::vector<Obb<double>>& far,
             const std::vector<Obb<double>>& near) {
  MeshQueryCounters farCount, nearCount;
  for (const auto& b : far) {
    MeshQueryCounters c;
    tree.overlaps(b, &c);
    // A far box costs a handful of tests, nothing like the triangles.
    EXPECT_LT(c.nodeTests + c.triangleTests, mesh.triangles.size() / 10);
    farCount.nodeTests += c.nodeTests;
    farCount.triangleTests += c.triangleTests;
  }
  for (const auto& b : near) tree.overlaps(b, &nearCount);
  const double perNear = double(nearCount.nodeTests + nearCount.triangleTests) / double(near.size());
  EXPECT_LT(perNear, 0.1 * double(mesh.triangles.size()));

  auto microseconds = [](auto&& fn, int repeats) {
    const auto start = std::chrono::steady_clock::now();
    for (int r = 0; r < repeats; ++r) fn();
    return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count() / repeats;
  };
  int sink = 0;
  const double nearUs = microseconds([&] { for (const auto& b : near) sink += tree.overlaps(b); }, 5) / double(near.size());
  const double farUs = microseconds([&] { for (const auto& b : far) sink += tree.overlaps(b); }, 5) / double(far.size());
  const double distUs = microseconds([&] { for (const auto& b : near) sink += tree.distance(b) > 0; }, 1) / double(near.size());
  std::printf("[%s] near boxes: %.1f BV tests + %.1f triangle tests, %.2f us per overlaps(), %.2f us per distance(); "
              "far boxes: %.1f + %.1f tests, %.3f us (sink %d)\n",
              treeName, double(nearCount.nodeTests) / double(near.size()), double(nearCount.triangleTests) / double(near.size()),
              nearUs, distUs, double(farCount.nodeTests) / double(far.size()), double(farCount.triangleTests) / double(far.size()),
              farUs, sink);
}

TEST(MeshTree, FewTestsAndFastOnABigMesh) {
  const TriangleMesh sphere = icosphere(4, 1.0);  // 5120 triangles
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> u(-1, 1), ext(0.05, 0.3);
  std::vector<Obb<double>> far, near;
  for (int i = 0; i < 300; ++i) {
    const V3 dir = V3(u(rng), u(rng), u(rng)).normalized();
    const V3 half(ext(rng), ext(rng), ext(rng));
    far.push_back({dir * (2.5 + std::abs(u(rng))), testshapes::randomRotation(rng), half});
    // Near the surface: centre within +-1 half extent of the sphere (about half touch it).
    near.push_back({dir * (1.0 + u(rng) * half.norm()), testshapes::randomRotation(rng), half});
  }
  const auto t1 = std::chrono::steady_clock::now();
  const KdopTree kdop(sphere);
  const auto t2 = std::chrono::steady_clock::now();
  std::printf("[build] %zu triangles: kdop18 tree %.1f ms (%zu nodes)\n", sphere.triangles.size(),
              std::chrono::duration<double, std::milli>(t2 - t1).count(), kdop.nodes().size());
  measure("kdop18", kdop, sphere, far, near);

  std::vector<char> contact;
  const auto b0 = std::chrono::steady_clock::now();
  for (const auto& b : near) contact.push_back(bruteForceOverlaps(sphere, b));
  const double bruteUs = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - b0).count() / double(near.size());
  const long contacts = std::count(contact.begin(), contact.end(), 1);
  std::printf("[brute force] near boxes: %ld of %zu in contact, %.1f us per query (up to %zu triangle tests)\n", contacts,
              near.size(), bruteUs, sphere.triangles.size());
  EXPECT_GT(contacts, long(near.size()) / 5);
  for (std::size_t i = 0; i < near.size(); ++i) {
    ASSERT_EQ(kdop.overlaps(near[i]), bool(contact[i])) << i;
  }
}

// ---- Meshes from OSG nodes. ----

TEST(MeshTree, MeshFromNodeAppliesTransforms) {
  osg::ref_ptr<osg::Geometry> geometry = new osg::Geometry;
  osg::ref_ptr<osg::Vec3Array> points = new osg::Vec3Array;
  points->push_back(osg::Vec3(0, 0, 0));
  points->push_back(osg::Vec3(1, 0, 0));
  points->push_back(osg::Vec3(1, 1, 0));
  points->push_back(osg::Vec3(0, 1, 0));
  points->push_back(osg::Vec3(0, 0, 1));
  geometry->setVertexArray(points);
  osg::ref_ptr<osg::DrawElementsUInt> quad = new osg::DrawElementsUInt(GL_TRIANGLES);
  for (unsigned i : {0u, 1u, 2u, 0u, 2u, 3u}) quad->push_back(i);
  geometry->addPrimitiveSet(quad);
  geometry->addPrimitiveSet(new osg::DrawArrays(GL_TRIANGLE_STRIP, 2, 3));  // (2,3,4)
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->addDrawable(geometry);
  osg::ref_ptr<osg::MatrixTransform> transform = new osg::MatrixTransform;
  // OSG's row-vector convention: scale, then turn 90 degrees about z, then move.
  transform->setMatrix(osg::Matrixd::scale(2, 2, 2) * osg::Matrixd::rotate(std::numbers::pi / 2, osg::Vec3d(0, 0, 1)) *
                       osg::Matrixd::translate(10, 20, 30));
  transform->addChild(geode);

  const TriangleMesh mesh = collectModelGeometry(*transform, "transformed quad");
  ASSERT_EQ(mesh.triangles.size(), 3u);
  auto expected = [](double x, double y, double z) { return V3(10 - 2 * y, 20 + 2 * x, 30 + 2 * z); };
  const std::vector<Triangle> want = {{expected(0, 0, 0), expected(1, 0, 0), expected(1, 1, 0)},
                                      {expected(0, 0, 0), expected(1, 1, 0), expected(0, 1, 0)},
                                      {expected(1, 1, 0), expected(0, 1, 0), expected(0, 0, 1)}};
  for (std::size_t t = 0; t < 3; ++t)
    for (int i = 0; i < 3; ++i) EXPECT_LT((mesh.triangle(t)[i] - want[t][i]).norm(), 1e-12) << t << " " << i;

  // A box touching the transformed quad's corner (10, 20, 30) from below.
  const KdopTree tree(mesh);
  EXPECT_TRUE(tree.overlaps({V3(9.5, 19.5, 29.5), Mat3<double>::Identity(), V3::Constant(0.5)}));
  EXPECT_FALSE(tree.overlaps({V3(9.5, 19.5, 29.49), Mat3<double>::Identity(), V3::Constant(0.5)}));
  EXPECT_NEAR(tree.distance({V3(9.5, 19.5, 29.49), Mat3<double>::Identity(), V3::Constant(0.5)}), 0.01, 1e-12);

  const osg::ref_ptr<osg::Group> empty = new osg::Group;
  EXPECT_THROW(collectModelGeometry(*empty, "empty group"), InputError);
}

// ---- The bundled equipment models. ----

TEST(MeshTree, BundledModelsAgainstTheirInnerObb) {
  const std::filesystem::path dir = test::bundledSceneFolder() / "models";
  if (!std::filesystem::is_directory(dir)) GTEST_SKIP() << dir << " is absent (build the bundled_scene target)";
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.path().extension() == ".osgt") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  ASSERT_FALSE(files.empty());
  const V3 body(0.25, 0.25, 0.9);  // the bundled scene's viewer body half extents
  for (const auto& file : files) {
    const osg::ref_ptr<osg::Node> node = osgDB::readRefNodeFile(file.string());
    ASSERT_TRUE(node) << file;
    const TriangleMesh mesh = collectModelGeometry(*node, file.string());
    const Obb<double> inner = fitObb(mesh.vertices, ObbFitter::HullSearch);
    const KdopTree kdopTree(mesh);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1, 1), yaw(0, 2 * std::numbers::pi);
    const V3 reach = inner.halfExtents.cwiseAbs().maxCoeff() * V3::Ones() + body;
    int obbContacts = 0, meshContacts = 0;
    std::vector<double> falseContactGaps;
    for (int n = 0; n < 1000; ++n) {
      const Obb<double> box{inner.center + V3(u(rng), u(rng), u(rng)).cwiseProduct(reach),
                            Eigen::AngleAxisd(yaw(rng), V3::UnitZ()).toRotationMatrix(), body};
      const bool touchesMesh = bruteForceOverlaps(mesh, box);
      const bool touchesObb = satObbObb(inner, box).overlap;
      ASSERT_EQ(kdopTree.overlaps(box), touchesMesh) << file << " box " << n;
      ASSERT_TRUE(touchesObb || !touchesMesh) << file << " box " << n << ": a mesh contact outside the inner OBB";
      obbContacts += touchesObb;
      meshContacts += touchesMesh;
      if (touchesObb && !touchesMesh) falseContactGaps.push_back(kdopTree.distance(box));
    }
    std::sort(falseContactGaps.begin(), falseContactGaps.end());
    const auto gap = [&](double q) { return falseContactGaps.empty() ? 0.0 : falseContactGaps[std::size_t(q * double(falseContactGaps.size() - 1))]; };
    std::printf("[model] %-20s %4zu triangles: of 1000 body boxes %3d touch the inner OBB, %3d the triangles; "
                "false contacts %3zu, gap to the real surface median %.3f m, max %.3f m\n",
                file.filename().string().c_str(), mesh.triangles.size(), obbContacts, meshContacts,
                falseContactGaps.size(), gap(0.5), gap(1.0));
  }
}

}  // namespace
}  // namespace nestwalk
