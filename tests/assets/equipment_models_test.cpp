// assets/generators/equipment_models.h: every bundled model is written as OSG native text (.osgt),
// read back through osgDB (engine/scene/model_geometry.h) and measured from its vertices against
// the real-world sizes the models stand for (written here from the equipment's specifications,
// not from the generator's constants).
#include "assets/generators/equipment_models.h"
#include "nestwalk/core/input_error.h"
#include "nestwalk/scene/model_geometry.h"
#include "tests/common/temp_folder.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <osg/Material>
#include <osgDB/ReadFile>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <filesystem>
#include <unistd.h>

namespace nestwalk::assets {
namespace {

namespace fs = std::filesystem;

constexpr double kSizeTol = 1e-5;  // metres: the vertices are stored as float (about 2e-7 m at 3 m)

struct Expected {
  ModelKind model;
  double width, depth, height;  // x, y, z extents of the whole model, metres
};

// Sizes from the equipment: a 3 m sensor pole with its head; a 3 m weather mast whose cross-arm
// is 1 m; a 1.6 x 1.0 m panel tilted 30 degrees with its low edge 0.5 m up (depth 1.0 cos 30 +
// 0.04 sin 30, height 0.5 + 1.0 sin 30 + 0.04 cos 30); a piezometer pad 0.6 m square under a
// 0.8 m casing and 0.08 m cap; ISO 668 1CC container 6.058 x 2.438 x 2.591 m (to the cm); a 3 m
// jersey barrier 0.6 m at the base, 0.8 m high; a pickup 5.3 x 1.9 x 1.8 m.
const Expected kExpected[] = {
    {ModelKind::SensorPole, 0.14, 0.18, 3.0},
    {ModelKind::WeatherStation, -1, -1, 3.0},  // width and depth: checked below (anemometer, panel)
    {ModelKind::SolarPanel, 1.6, std::cos(std::numbers::pi / 6) + 0.04 * 0.5, 0.5 + 0.5 + 0.04 * std::cos(std::numbers::pi / 6)},
    {ModelKind::LoggerBox, 0.56, 0.40, 1.53},
    {ModelKind::Piezometer, 0.6, 0.6, 0.1 + 0.8 + 0.08},
    {ModelKind::Container20ft, 2.44, 6.06, 2.59},
    {ModelKind::JerseyBarrier, 0.6, 3.0, 0.8},
    {ModelKind::Pickup, 1.9, 5.3, 1.8},
};

/// One folder for the whole program's models (written once per kind, read by several tests).
const fs::path& tempDir() {
  static const test::TempFolder folder("models");
  return folder.path();
}

TriangleMesh writeAndLoad(ModelKind m) {
  const fs::path p = tempDir() / modelFileName(m);
  writeModel(m, p.string());
  return loadModelGeometry(p.string());
}

Aabb<double> boundsOf(const TriangleMesh& g, double zLo = -1e9, double zHi = 1e9) {
  Aabb<double> b;
  for (const auto& v : g.vertices)
    if (v.z() >= zLo && v.z() <= zHi) b.extend(v);
  return b;
}

TEST(EquipmentModels, LoadWithOsgDbAndHaveTheirRealSizes) {
  for (const Expected& e : kExpected) {
    SCOPED_TRACE(modelStem(e.model));
    const TriangleMesh g = writeAndLoad(e.model);
    EXPECT_GT(g.triangles.size(), 10u);
    EXPECT_LE(g.triangles.size(), 400u);  // a few hundred at most
    const Aabb<double> b = boundsOf(g);
    EXPECT_NEAR(b.min.z(), 0.0, kSizeTol);  // stands on z = 0
    EXPECT_NEAR(b.size().z(), e.height, kSizeTol);
    if (e.width > 0) {
      EXPECT_NEAR(b.size().x(), e.width, kSizeTol);
      EXPECT_NEAR(b.size().y(), e.depth, kSizeTol);
    }
    // The base (the vertices on the ground) is centred on x = y = 0.
    const Aabb<double> base = boundsOf(g, -kSizeTol, kSizeTol);
    ASSERT_FALSE(base.isEmpty());
    EXPECT_NEAR(base.center().x(), 0.0, kSizeTol);
    EXPECT_NEAR(base.center().y(), 0.0, kSizeTol);
  }
}

TEST(EquipmentModels, TheDrillRigIsTheHeavyModel) {
  // A crawler drill rig 2.3 m wide, 5 m long, its mast up to 10.2 m; counted part by part from its
  // construction (a prism of n sides is 4n - 4 triangles, a box 12): tracks 2 x (frame 12 + 28 pads
  // x 12 + 7 rollers of 24 sides x 92), five boxes of the deck, cab, engine house, counterweight and
  // mast foot, 4 chords of 44 segments of 32 sides (124 each), 22 levels of 4 struts and 4 braces
  // of 16 sides (60 each), the rod in 45 segments of 32 sides and its head.
  const std::size_t tracks = 2 * (12 + 28 * 12 + 7 * 92), boxes = 5 * 12, chords = 4 * 44 * 124,
                    bars = 22 * 8 * 60, rod = 45 * 124 + 12;
  const TriangleMesh g = writeAndLoad(ModelKind::DrillRig);
  EXPECT_EQ(g.triangles.size(), tracks + boxes + chords + bars + rod);
  EXPECT_GE(g.triangles.size(), 30000u);  // the heavy model: 30k to 100k triangles
  EXPECT_LE(g.triangles.size(), 100000u);
  const Aabb<double> b = boundsOf(g);
  EXPECT_NEAR(b.min.z(), 0.0, kSizeTol);
  EXPECT_NEAR(b.size().x(), 2.31, kSizeTol);   // the rollers stand 3 cm out of the 2.25 m tracks
  EXPECT_NEAR(b.size().y(), 5.0, kSizeTol);
  EXPECT_NEAR(b.size().z(), 10.2 + 0.015, kSizeTol);  // the top strut's radius above the chords
  const Aabb<double> base = boundsOf(g, -kSizeTol, kSizeTol);
  EXPECT_NEAR(base.center().x(), 0.0, kSizeTol);
  EXPECT_NEAR(base.center().y(), 0.0, kSizeTol);
  std::printf("[drill rig] %zu triangles, %.3f x %.3f x %.3f m\n", g.triangles.size(), b.size().x(), b.size().y(),
              b.size().z());
}

/// Bounds of the vertices of the triangles spanning exactly z0 .. z1: the side faces of a prism
/// standing from z0 to z1.
Aabb<double> sideBounds(const TriangleMesh& g, double z0, double z1, double radius) {
  Aabb<double> b;
  for (const auto& t : g.triangles) {
    double lo = 1e9, hi = -1e9;
    for (auto i : t) lo = std::min(lo, g.vertices[i].z()), hi = std::max(hi, g.vertices[i].z());
    if (std::abs(lo - z0) > kSizeTol || std::abs(hi - z1) > kSizeTol) continue;
    for (auto i : t) {
      b.extend(g.vertices[i]);
      EXPECT_NEAR(std::hypot(g.vertices[i].x(), g.vertices[i].y()), radius, kSizeTol);  // on the circle
    }
  }
  return b;
}

TEST(EquipmentModels, PoleIsFiveCentimetresAndCylindersAreRound) {
  // The pole: a prism 0.05 m across on both axes, from the ground to 3 m.
  const Aabb<double> pole = sideBounds(writeAndLoad(ModelKind::SensorPole), 0.0, 3.0, 0.025);
  EXPECT_NEAR(pole.size().x(), 0.05, kSizeTol);
  EXPECT_NEAR(pole.size().y(), 0.05, kSizeTol);
  const TriangleMesh mastModel = writeAndLoad(ModelKind::WeatherStation);
  const Aabb<double> mast = sideBounds(mastModel, 0.0, 3.0, 0.03);
  EXPECT_NEAR(mast.size().x(), 0.06, kSizeTol);
  EXPECT_NEAR(mast.size().y(), 0.06, kSizeTol);
  // The whole station: the 1 m cross-arm and the anemometer's cups across, the logger and panel in front.
  Aabb<double> station;
  for (const auto& v : mastModel.vertices) station.extend(v);
  EXPECT_GT(station.size().x(), 1.0);
  EXPECT_LT(station.size().x(), 1.3);
  EXPECT_LT(station.size().y(), 0.6);
  // Piezometer casing: 0.15 m across, 0.8 m from the pad's top (0.1 m) to the cap.
  const Aabb<double> casing = sideBounds(writeAndLoad(ModelKind::Piezometer), 0.1, 0.9, 0.075);
  EXPECT_NEAR(casing.size().x(), 0.15, kSizeTol);
  EXPECT_NEAR(casing.size().y(), 0.15, kSizeTol);
}

TEST(EquipmentModels, SolarPanelIsTiltedThirtyDegreesFacingForward) {
  const TriangleMesh g = writeAndLoad(ModelKind::SolarPanel);
  // The panel's top face: the triangles of area above 0.5 m^2 facing up.
  int found = 0;
  for (const auto& t : g.triangles) {
    const Vec3<double> a = g.vertices[t[0]], b = g.vertices[t[1]], c = g.vertices[t[2]];
    const Vec3<double> n = (b - a).cross(c - a);
    if (0.5 * n.norm() < 0.5 || n.z() <= 0) continue;
    const Vec3<double> u = n.normalized();
    EXPECT_NEAR(std::acos(u.z()) * 180 / std::numbers::pi, 30.0, 1e-3);
    EXPECT_GT(u.y(), 0.0);  // facing +y, forward
    ++found;
  }
  EXPECT_EQ(found, 2);
}

TEST(EquipmentModels, OneMaterialPerModel) {
  for (ModelKind m : kAllModels) {
    SCOPED_TRACE(modelStem(m));
    const fs::path p = tempDir() / modelFileName(m);
    writeModel(m, p.string());
    const osg::ref_ptr<osg::Node> node = osgDB::readNodeFile(p.string());
    ASSERT_TRUE(node);
    const osg::StateSet* ss = node->getStateSet();
    ASSERT_NE(ss, nullptr);
    EXPECT_NE(ss->getAttribute(osg::StateAttribute::MATERIAL), nullptr);
  }
  fs::remove_all(tempDir());
}

TEST(EquipmentModels, WritingToAnUnwritablePlaceNamesThePath) {
  try {
    writeModel(ModelKind::SensorPole, "/nonexistent-folder/pole.osgt");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-folder/pole.osgt"), std::string::npos);
  }
}

}  // namespace
}  // namespace nestwalk::assets
