// Shared by the hard-case suite (tests/hard_cases): a temporary folder per test, GeoTIFF terrains
// written with GDAL, triangle models built here and written with osgDB, scene files, the models'
// triangles read back through OSG by this file's own visitor (not through the engine's loader),
// and FCL as the peer library for distances from a box to triangles.
//
// Nothing here calls the engine's geometry: the references the cases compare with are built from
// the construction (closed forms), from OSG's own reader, from Eigen and from FCL.
#pragma once

#include "nestwalk/geometry/volumes.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/walker/collision_world.h"
#include "nestwalk/walker/mesh_world.h"
#include "nestwalk/walker/walker.h"
#include "nestwalk/terrain/dem_reader.h"
#include "tests/common/temp_folder.h"
#include "tests/terrain/gdal_test_util.h"

#include <Eigen/Geometry>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/narrowphase/distance.h>
#include <gdal.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/MatrixTransform>
#include <osg/NodeVisitor>
#include <osgDB/ReadFile>
#include <osgDB/WriteFile>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace nestwalk::hardcase {

namespace fs = std::filesystem;
using V3 = Vec3<double>;
using Json = nlohmann::json;

/// A folder of its own for the running test, removed at the end unless the test failed.
using ScratchFolder = test::TempFolder;

/// A north-up Float32 GeoTIFF: `cols` x `rows` pixels of `cell` metres, outer corner (west, north)
/// (GDAL's geotransform origin, so sample (c, r) is at (west + (c + 0.5) cell, north - (r + 0.5)
/// cell)), pixel values height(c, r), and the band's nodata value when given.
inline void writeGeoTiff(const fs::path& path, int cols, int rows, double west, double north, double cell,
                         const std::function<double(int, int)>& height, std::optional<double> noData = std::nullopt) {
  terrain::initGdal();
  std::vector<double> values(std::size_t(cols) * std::size_t(rows));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) values[std::size_t(r) * std::size_t(cols) + std::size_t(c)] = height(c, r);
  GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), path.c_str(), cols, rows, 1, GDT_Float32, nullptr);
  ASSERT_NE(ds, nullptr) << path;
  double geo[6] = {west, cell, 0.0, north, 0.0, -cell};
  GDALSetGeoTransform(ds, geo);
  test::writeBands(ds, cols, rows, values, noData, 1);
  GDALClose(ds);
}

// ---- Triangle models. ----

/// Triangles by index, in a model's own frame (what the test writes and what it reads back).
struct Mesh {
  std::vector<V3> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;

  void append(const Mesh& other) {
    const auto base = std::uint32_t(vertices.size());
    vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
    for (const auto& t : other.triangles) triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  }
  std::array<V3, 3> corners(std::size_t i) const {
    return {vertices[triangles[i][0]], vertices[triangles[i][1]], vertices[triangles[i][2]]};
  }
};

/// A closed prism of `sides` faces around the +z axis from z = 0 to `height`, radius at the corners.
/// `upAxis` 1 stands it along +y instead (a model authored Y-up).
inline Mesh cylinderMesh(double radius, double height, int sides, int upAxis = 2) {
  Mesh m;
  auto put = [&](double a, double b, double h) {
    m.vertices.push_back(upAxis == 2 ? V3(a, b, h) : V3(a, h, -b));
  };
  for (int ring = 0; ring < 2; ++ring)
    for (int i = 0; i < sides; ++i) {
      const double phi = 2 * std::numbers::pi * i / sides;
      put(radius * std::cos(phi), radius * std::sin(phi), ring * height);
    }
  const auto n = std::uint32_t(sides);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t k = (i + 1) % n;
    m.triangles.push_back({i, k, n + k});
    m.triangles.push_back({i, n + k, n + i});
    if (i > 0 && i + 1 < n) {
      m.triangles.push_back({0, i + 1, i});
      m.triangles.push_back({n, n + i, n + i + 1});
    }
  }
  return m;
}

/// The closed axis-aligned box [lo, hi] as 12 triangles.
inline Mesh boxMesh(const V3& lo, const V3& hi) {
  Mesh m;
  for (int i = 0; i < 8; ++i) m.vertices.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  static const std::uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    m.triangles.push_back({f[0], f[1], f[2]});
    m.triangles.push_back({f[0], f[2], f[3]});
  }
  return m;
}

/// The mesh as an OSG Geode (float vertices, one GL_TRIANGLES DrawElementsUInt).
inline osg::ref_ptr<osg::Geode> toGeode(const Mesh& m) {
  osg::ref_ptr<osg::Vec3Array> v = new osg::Vec3Array;
  for (const V3& p : m.vertices) v->push_back(osg::Vec3(float(p.x()), float(p.y()), float(p.z())));
  osg::ref_ptr<osg::DrawElementsUInt> e = new osg::DrawElementsUInt(GL_TRIANGLES);
  for (const auto& t : m.triangles)
    for (std::uint32_t i : t) e->push_back(i);
  osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
  g->setVertexArray(v);
  if (!m.triangles.empty()) g->addPrimitiveSet(e);
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->addDrawable(g);
  return geode;
}

inline void writeModel(const osg::Node& node, const fs::path& path) {
  ASSERT_TRUE(osgDB::writeNodeFile(node, path.string())) << path;
}

/// The GL_TRIANGLES of every Geometry under a node, with the node path's matrices applied (in
/// double). Only what this suite writes is understood (indexed or plain triangle lists).
class TriangleReader : public osg::NodeVisitor {
 public:
  TriangleReader() : osg::NodeVisitor(TRAVERSE_ALL_CHILDREN) {}
  void apply(osg::Geometry& g) override {
    const auto* v = dynamic_cast<const osg::Vec3Array*>(g.getVertexArray());
    if (!v) return;
    const osg::Matrixd world = osg::computeLocalToWorld(getNodePath());
    const auto base = std::uint32_t(mesh.vertices.size());
    for (const osg::Vec3& p : *v) {
      const osg::Vec3d q = osg::Vec3d(p) * world;
      mesh.vertices.emplace_back(q.x(), q.y(), q.z());
    }
    for (unsigned s = 0; s < g.getNumPrimitiveSets(); ++s) {
      const osg::PrimitiveSet* ps = g.getPrimitiveSet(s);
      if (ps->getMode() != GL_TRIANGLES) continue;
      for (unsigned i = 0; i + 2 < ps->getNumIndices(); i += 3)
        mesh.triangles.push_back({base + ps->index(i), base + ps->index(i + 1), base + ps->index(i + 2)});
    }
  }
  Mesh mesh;
};

/// The model file as OSG's reader returns it.
inline Mesh readBack(const fs::path& path) {
  osg::ref_ptr<osg::Node> node = osgDB::readRefNodeFile(path.string());
  EXPECT_TRUE(node) << path;
  TriangleReader reader;
  if (node) node->accept(reader);
  return reader.mesh;
}

/// model -> local frame of a scene instance as documented in scene.h and README ("heading
/// clockwise from north, pitch nose up about the right axis, roll right side down about the
/// forward axis; roll first, heading last"), composed here from Eigen quaternions.
inline Eigen::Affine3d instanceToLocal(double headingDeg, double pitchDeg, double rollDeg, double scale, const V3& t) {
  const double k = std::numbers::pi / 180.0;
  const Eigen::Quaterniond q = Eigen::Quaterniond(Eigen::AngleAxisd(-headingDeg * k, V3::UnitZ())) *
                               Eigen::Quaterniond(Eigen::AngleAxisd(pitchDeg * k, V3::UnitX())) *
                               Eigen::Quaterniond(Eigen::AngleAxisd(rollDeg * k, V3::UnitY()));
  Eigen::Affine3d a = Eigen::Affine3d::Identity();
  a.linear() = scale * q.toRotationMatrix();
  a.translation() = t;
  return a;
}

inline Mesh transformed(const Mesh& m, const Eigen::Affine3d& a) {
  Mesh out = m;
  for (V3& p : out.vertices) p = a * p;
  return out;
}

// ---- FCL: the peer library's distances. ----

/// Whether p lies in the closed box (in the box's frame, to `tol`).
inline bool insideBox(const Obb<double>& b, const V3& p, double tol = 0.0) {
  const V3 q = b.axes.transpose() * (p - b.center);
  return (q.cwiseAbs().array() <= b.halfExtents.array() + tol).all();
}

/// Distance from the solid box to the triangles, by FCL: 0 when a triangle corner lies in the box,
/// else the distance between the box's surface (12 triangles) and the triangles, through FCL's
/// BVH-BVH distance (PQP's triangle-triangle distance). The surfaces are 0 apart when they cross;
/// separated solids have the distance of their surfaces.
inline double fclBoxMeshDistance(const Obb<double>& box, const Mesh& mesh) {
  if (mesh.triangles.empty()) return std::numeric_limits<double>::infinity();
  for (const auto& t : mesh.triangles)
    for (std::uint32_t i : t)
      if (insideBox(box, mesh.vertices[i])) return 0.0;
  auto model = [](const Mesh& m) {
    auto bvh = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
    std::vector<fcl::Vector3d> v(m.vertices.begin(), m.vertices.end());
    std::vector<fcl::Triangle> t;
    for (const auto& tri : m.triangles) t.emplace_back(tri[0], tri[1], tri[2]);
    bvh->beginModel();
    bvh->addSubModel(v, t);
    bvh->endModel();
    return bvh;
  };
  const auto shape = model(boxMesh(-box.halfExtents, box.halfExtents));
  const auto target = model(mesh);
  fcl::Transform3d pose = fcl::Transform3d::Identity();
  pose.linear() = box.axes;
  pose.translation() = box.center;
  fcl::DistanceRequestd request;
  fcl::DistanceResultd result;
  const double d = fcl::distance(shape.get(), pose, target.get(), fcl::Transform3d::Identity(), request, result);
  return std::max(d, 0.0);
}

// ---- Scene files. ----

/// One equipment entry of a scene file.
inline Json equipment(const std::string& name, const fs::path& model, double x, double y, double heading = 0,
                      double pitch = 0, double scale = 1) {
  return {{"name", name}, {"model", model.string()}, {"position", {x, y}}, {"heading", heading},
          {"pitch", pitch}, {"scale", scale}};
}

/// Writes `dir/scene.json` (terrain and origin given) and returns its path.
inline fs::path writeSceneFile(const fs::path& dir, const fs::path& terrain, const V3& origin, const Json& items) {
  const Json scene = {{"terrain", terrain.string()}, {"origin", {origin.x(), origin.y(), origin.z()}}, {"equipment", items}};
  const fs::path path = dir / "scene.json";
  std::ofstream(path) << scene.dump(2);
  return path;
}

// ---- Sites: a flat terrain with models on it. ----

/// A level site: a GeoTIFF of 64 x 64 pixels of 1 m at height 0 whose outer north-west corner is
/// `corner`; the scene's origin is its middle, so that local = map - origin spans [-32, 32].
struct FlatSite {
  Eigen::Vector2d corner;
  V3 origin() const { return {corner.x() + 32.0, corner.y() - 32.0, 0.0}; }
  /// Map position of a local point.
  Eigen::Vector2d map(double lx, double ly) const { return {corner.x() + 32.0 + lx, corner.y() - 32.0 + ly}; }
  fs::path writeTerrain(const fs::path& dir) const {
    const fs::path path = dir / "flat.tif";
    writeGeoTiff(path, 64, 64, corner.x(), corner.y(), 1.0, [](int, int) { return 0.0; });
    return path;
  }
};

/// A loaded scene, one collision world over it per method (sharing the scene's triangle trees),
/// and a walker on each. Not movable: walkers hold references.
class SceneRig {
 public:
  explicit SceneRig(const fs::path& sceneFile, const SceneLoadOptions& options = {})
      : scene_(loadScene(sceneFile.string(), options)), meshes_(MeshWorld::fromScene(scene_)) {}
  SceneRig(const SceneRig&) = delete;
  SceneRig& operator=(const SceneRig&) = delete;

  const Scene& scene() const { return scene_; }
  const MeshWorld& meshes() const { return *meshes_; }
  /// A fresh walker (WalkerOptions from the scene's viewer) on a world of the method.
  Walker& walker(VolumeMethod method) {
    MethodSpec m = scene_.spec.method;
    m.volumes = method;
    worlds_.push_back(std::make_unique<CollisionWorld>(CollisionWorld::fromScene(scene_, m, meshes_)));
    WalkerOptions options;
    options.viewer = scene_.spec.viewer;
    walkers_.push_back(std::make_unique<Walker>(*scene_.terrain, *worlds_.back(), scene_.origin, options));
    return *walkers_.back();
  }

 private:
  Scene scene_;
  std::shared_ptr<const MeshWorld> meshes_;
  std::vector<std::unique_ptr<CollisionWorld>> worlds_;
  std::vector<std::unique_ptr<Walker>> walkers_;
};

/// The walker's body box (local frame) as it stands.
inline Obb<double> bodyBox(const Walker& w) { return w.bodyVolume(w.state().feet, w.state().bodyYawDeg).inner; }

// ---- Walking. ----

/// Steps the walker toward map (x, y) at `speed` with the view (and body) at `headingDeg`, until it
/// arrives or has made no progress for three steps (blocked); `afterStep` sees every step.
/// Returns the number of steps. `onReport`, when given, sees each step's report.
inline int walkToward(Walker& w, const Eigen::Vector2d& target, double speed, double headingDeg,
                      const std::function<void(const Walker&)>& afterStep = {}, int maxSteps = 50000,
                      const std::function<void(const StepReport&)>& onReport = {}) {
  int stuck = 0, n = 0;
  for (; n < maxSteps && stuck < 3; ++n) {
    const Eigen::Vector2d to = target - w.state().feet.head<2>();
    const double dist = to.norm();
    if (dist < 1e-9) break;
    StepInput in;
    const double len = std::min(dist, speed * w.options().dt);
    in.move = Eigen::Vector3d(to.x(), to.y(), 0) * (len / dist);
    in.headingDeg = headingDeg;
    const Eigen::Vector3d before = w.state().feet;
    const StepReport report = w.step(in);
    if (onReport) onReport(report);
    if (afterStep) afterStep(w);
    stuck = (w.state().feet - before).norm() < 1e-12 ? stuck + 1 : 0;
  }
  return n;
}

}  // namespace nestwalk::hardcase
