// Every shared real model (../shared/data/models) placed by build-scene on a shared real DEM
// (storml_elev_orig.tif, UTM 12N, alpine) with its catalog entry: upright, its size in metres
// within 1 % of the file's own bounding box (osg::ComputeBoundsVisitor, read here) times the
// catalog's units along the documented axes, and its base on the ground within 1 cm: no ground
// point under its footprint is below it (it never hangs in the air), and the lowest is within
// 1 cm of it (sampled every 2 cm by Heightfield::groundHeight). A DEM without a CRS
// (pre_runout_DEM.asc) is refused.
#include "nestwalk/core/input_error.h"
#include "nestwalk/gis/scene_builder.h"
#include "nestwalk/scene/model_geometry.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "tests/common/test_data.h"
#include "tests/gis/gis_test_util.h"

#include <gtest/gtest.h>
#include <osg/ComputeBoundsVisitor>
#include <osgDB/ReadFile>

#include <map>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

/// The catalog entries, and what they mean for the file's axes: which file axis becomes the
/// model's width (x), length (y) and height (z) once placed at heading 0.
struct RealModel {
  const char* type;
  const char* file;
  Json entry;
  int widthAxis, lengthAxis, heightAxis;  // file axes 0, 1, 2 (x, y, z)
  double metresPerUnit;
};
const RealModel kModels[] = {
    // A street lamp in metres, z up: a thin pole.
    {"lamp", "models/street_lamp.osgb", {{"units", "m"}, {"kind", "pole"}}, 0, 1, 2, 1.0},
    // The dump truck: about 30 file units long (x), z up, cab at +x: 0.3 m a unit makes it 8.9 m.
    {"truck", "models/dumptruck.osgt", {{"units", 0.3}, {"up", "z"}, {"forward", "+x"}, {"kind", "vehicle"}}, 1, 0, 2, 0.3},
    // The excavator's upper structure in metres, upside down along y as OSG's OBJ reader turns it
    // (-y up: its +z becomes forward); origin at the slewing joint in the file, at its base here.
    {"excavator", "models/excavator_chassis.obj", {{"units", "m"}, {"up", "-y"}, {"kind", "vehicle"}}, 0, 2, 1, 1.0},
    // The jeep, z up, length along +y: 0.25 m a unit makes it 4.2 m long.
    {"jeep", "models/jeep1/jeep1.3ds", {{"units", 0.25}, {"kind", "vehicle"}}, 0, 1, 2, 0.25},
};

/// The 2D convex hull (gift wrapping), independent of the engine's.
std::vector<Eigen::Vector2d> outline(const std::vector<Eigen::Vector2d>& pts) {
  std::size_t start = 0;
  for (std::size_t i = 1; i < pts.size(); ++i)
    if (pts[i].x() < pts[start].x() || (pts[i].x() == pts[start].x() && pts[i].y() < pts[start].y())) start = i;
  std::vector<Eigen::Vector2d> hull;
  std::size_t p = start;
  do {
    hull.push_back(pts[p]);
    std::size_t q = (p + 1) % pts.size();
    for (std::size_t r = 0; r < pts.size(); ++r) {
      const Eigen::Vector2d a = pts[q] - pts[p], b = pts[r] - pts[p];
      const double cross = a.x() * b.y() - a.y() * b.x();
      if (cross < 0 || (cross == 0 && b.norm() > a.norm())) q = r;
    }
    p = q;
  } while (p != start && hull.size() <= pts.size());
  return hull;
}

bool inside(const std::vector<Eigen::Vector2d>& hull, const Eigen::Vector2d& p) {
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Eigen::Vector2d a = hull[i], b = hull[(i + 1) % hull.size()];
    if ((b.x() - a.x()) * (p.y() - a.y()) - (b.y() - a.y()) * (p.x() - a.x()) < 0) return false;  // counter-clockwise hull
  }
  return true;
}

TEST(RealModels, UprightInMetresOnTheGround) {
  const fs::path data = test::sharedData();
  if (data.empty()) GTEST_SKIP() << "shared data folder absent (NESTWALK_SHARED_DATA): no real models or DEM";
  const test::TempFolder dir;
  Json types = Json::object();
  std::string csv = "x,y,type,name\n";
  double x = 325480.0;
  for (const RealModel& m : kModels) {
    Json e = m.entry;
    e["model"] = (data / m.file).string();
    types[m.type] = e;
    csv += std::to_string(x) + ",5103500," + m.type + "," + m.type + "\n";
    x += 25.0;
  }
  test::writeText(dir / "catalog.json", Json{{"types", types}}.dump(2));
  test::writeText(dir / "eq.csv", csv);
  gis::BuildSceneOptions o;
  o.terrain = (data / "terrain" / "storml_elev_orig.tif").string();
  o.catalog = (dir / "catalog.json").string();
  o.out = (dir / "scene").string();
  o.layers.sources = {(dir / "eq.csv").string()};
  o.layers.assumedCrs = "EPSG:26912";
  o.maxFootprintRise = 5.0;  // the alpine slope under a truck
  const gis::BuildSceneSummary summary = gis::buildScene(o);
  const Scene scene = loadScene(summary.sceneFile);
  ASSERT_EQ(scene.instances.size(), std::size(kModels));

  for (std::size_t i = 0; i < std::size(kModels); ++i) {
    const RealModel& m = kModels[i];
    // The file's own bounds, through OSG's visitor.
    osg::ref_ptr<osg::Node> node = osgDB::readRefNodeFile((data / m.file).string());
    ASSERT_TRUE(node) << m.file;
    osg::ComputeBoundsVisitor bounds;
    node->accept(bounds);
    const osg::BoundingBox& b = bounds.getBoundingBox();
    const double extent[3] = {b.xMax() - b.xMin(), b.yMax() - b.yMin(), b.zMax() - b.zMin()};
    const Eigen::Vector3d want(extent[m.widthAxis], extent[m.lengthAxis], extent[m.heightAxis]);
    const Aabb<double>& placed = scene.instances[i].volume.outer;
    const Eigen::Vector3d got = placed.size();
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(got[k], want[k] * m.metresPerUnit, 0.01 * want[k] * m.metresPerUnit) << m.type << " axis " << k;
    std::printf("[real model] %-9s %.3f x %.3f x %.3f m (width x length x height)\n", m.type, got.x(), got.y(), got.z());

    // Its footprint: every placed vertex seen from above (the model's triangles' vertices).
    const TriangleMesh mesh = loadModelGeometry((data / m.file).string());
    std::vector<Eigen::Vector2d> xy;
    for (const auto& v : mesh.vertices) xy.push_back(scene.toMap(scene.instances[i].toLocal.apply(v)).head<2>());
    const std::vector<Eigen::Vector2d> hull = outline(xy);
    const double base = scene.toMap(placed.min).z();
    double lowest = INFINITY;
    const Eigen::Vector3d lo = scene.toMap(placed.min), hi = scene.toMap(placed.max);
    for (double px = lo.x(); px <= hi.x(); px += 0.02)
      for (double py = lo.y(); py <= hi.y(); py += 0.02)
        if (inside(hull, {px, py})) lowest = std::min(lowest, *scene.terrain->groundHeight(px, py));
    EXPECT_GE(lowest, base - 1e-6) << m.type << ": ground below its base: it would hang in the air";
    EXPECT_LT(lowest - base, 0.01) << m.type << ": base more than 1 cm under the lowest ground";
    std::printf("[real model] %-9s base %.4f m, lowest ground under it %.4f m (sampled every 2 cm), rise %.3f m\n", m.type,
                base, lowest, scene.instances[i].footprintRise);
  }
}

TEST(RealModels, ADemWithoutCrsIsRefused) {
  const fs::path data = test::sharedData();
  if (data.empty()) GTEST_SKIP() << "shared data folder absent (NESTWALK_SHARED_DATA)";
  const test::TempFolder dir;
  test::writeBoxModel(dir / "box.osgt", {-0.5, -0.5, 0}, {0.5, 0.5, 1});
  test::writeText(dir / "catalog.json", R"({"types": {"box": {"model": "box.osgt"}}})");
  test::writeText(dir / "eq.csv", "x,y,type\n361100,70300,box\n");
  gis::BuildSceneOptions o;
  o.terrain = (data / "terrain" / "pre_runout_DEM.asc").string();
  o.catalog = (dir / "catalog.json").string();
  o.out = (dir / "scene").string();
  o.layers.sources = {(dir / "eq.csv").string()};
  o.layers.assumedCrs = "EPSG:32149";
  try {
    gis::buildScene(o);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), o.terrain + ": has no CRS, so the layers cannot be placed on it (import it with --crs first)");
  }
  EXPECT_FALSE(fs::exists(dir / "scene"));
}

}  // namespace
}  // namespace nestwalk
