// The GIS sample (assets/generators/gis_inputs.h) and the second bundled scene the build makes from
// it with `nestwalk build-scene` (build/assets/gis_dump from build/assets/gis_dump_inputs),
// against the generator's own placements (generated again here at the same site: the UTM
// positions and grid headings the GIS files were made from):
//  - the inputs are what a user brings: a DEM that is not the engine's terrain format (build-scene
//    imported it), layers in EPSG:4326 whose headings are true azimuths: each differs from the
//    generated grid heading by the grid convergence PROJ gives at that point (proj_factors, a
//    computation of its own), about 1 degree here;
//  - every piece of the built scene lies within 1 cm of the generated position and turns to the
//    generated grid heading within 1e-6 degrees; every fence has the generated number of pieces,
//    each within 1 cm of its generated piece;
//  - the pickup, written in millimetres with y up and its origin mid-body, loads upright at its
//    size (1.90 x 5.30 x 1.80 m) within 1 %;
//  - every flythrough of the inputs plays on the built scene with all its expectations met
//    (`nestwalk run`, auto method).
#include "assets/generators/gis_inputs.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "tests/common/build_paths.h"
#include "tests/common/run_command.h"

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <ogrsf_frmts.h>
#include <proj.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>

namespace nestwalk::assets {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::readText;

const fs::path kScene = fs::path(nestwalk::test::build::gisSceneDir()) / "scene.json";
const fs::path kInputs = nestwalk::test::build::gisInputsDir();

/// Degrees a - b, wrapped to (-180, 180].
double angleDifference(double a, double b) {
  double d = std::fmod(a - b, 360.0);
  if (d > 180) d -= 360;
  if (d <= -180) d += 360;
  return d;
}

class GisSample : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { generated_ = new GeneratedScene(generateScene(1, kGisSampleSite)); }
  static void TearDownTestSuite() {
    delete generated_;
    generated_ = nullptr;
  }
  void SetUp() override {
    if (!fs::exists(kScene)) GTEST_SKIP() << kScene << " is absent: build the gis_sample_scene target";
  }
  static const GeneratedScene& generated() { return *generated_; }
  static GeneratedScene* generated_;
};
GeneratedScene* GisSample::generated_ = nullptr;

TEST_F(GisSample, LayersCarryTrueAzimuthsAndTheDemIsImported) {
  const auto scene = nlohmann::json::parse(readText(kScene));
  EXPECT_TRUE(scene["source"]["terrain_imported"].get<bool>());
  EXPECT_EQ(scene["terrain"], "terrain.tif");

  std::map<std::string, const Placement*> byName;
  for (const Placement& p : generated().equipment) byName[p.name] = &p;
  GDALAllRegister();
  GDALDataset* ds = GDALDataset::Open((kInputs / "equipment.gpkg").string().c_str(), GDAL_OF_VECTOR);
  ASSERT_NE(ds, nullptr);
  OGRLayer* layer = ds->GetLayerByName("equipment");
  ASSERT_NE(layer, nullptr);
  EXPECT_EQ(std::string(layer->GetSpatialRef()->GetAuthorityCode(nullptr)), "4326");
  // PROJ's own convergence at each point: the angle of grid north from true north.
  PJ_CONTEXT* ctx = proj_context_create();
  PJ* utm = proj_create(ctx, kGisSampleSite.crs);
  ASSERT_NE(utm, nullptr);
  std::size_t points = 0;
  double worst = 0, smallest = 360;
  for (const auto& f : *layer) {
    const std::string name = f->GetFieldAsString("name");
    ASSERT_TRUE(byName.count(name)) << name;
    const Placement& p = *byName[name];
    const OGRPoint* point = f->GetGeometryRef()->toPoint();
    PJ_COORD lonlat = proj_coord(point->getX() * std::numbers::pi / 180, point->getY() * std::numbers::pi / 180, 0, 0);
    const PJ_FACTORS factors = proj_factors(utm, lonlat);
    const double convergence = factors.meridian_convergence * 180 / std::numbers::pi;
    const double trueAzimuth = f->GetFieldAsDouble("heading");
    worst = std::max(worst, std::abs(angleDifference(trueAzimuth - convergence, p.headingDeg)));
    smallest = std::min(smallest, std::abs(convergence));
    ++points;
  }
  proj_destroy(utm);
  proj_context_destroy(ctx);
  GDALClose(ds);
  std::size_t nonBarriers = 0;
  for (const Placement& p : generated().equipment) nonBarriers += p.model != ModelKind::JerseyBarrier;
  EXPECT_EQ(points, nonBarriers);
  std::printf("%zu points: true azimuth - PROJ's convergence = the grid heading within %.2g degrees; "
              "convergence at least %.3f degrees\n", points, worst, smallest);
  EXPECT_LE(worst, 1e-6);
  EXPECT_GT(smallest, 0.5);  // a heading left unconverted would be visibly wrong
}

TEST_F(GisSample, BuiltSceneMatchesTheGeneratedPlacements) {
  const auto scene = nlohmann::json::parse(readText(kScene));
  std::map<std::string, const nlohmann::json*> built;
  for (const auto& e : scene["equipment"]) built[e["name"].get<std::string>()] = &e;
  std::map<std::string, std::vector<const Placement*>> fences;
  double worstPosition = 0, worstHeading = 0;
  for (const Placement& p : generated().equipment) {
    if (p.model == ModelKind::JerseyBarrier) {
      fences[p.group].push_back(&p);
      continue;
    }
    ASSERT_TRUE(built.count(p.name)) << p.name;
    const auto& e = *built[p.name];
    const Eigen::Vector2d at(e["position"][0].get<double>(), e["position"][1].get<double>());
    worstPosition = std::max(worstPosition, (at - p.position).norm());
    worstHeading = std::max(worstHeading, std::abs(angleDifference(e["heading"].get<double>(), p.headingDeg)));
    EXPECT_EQ(e["group"], p.group);
  }
  // Fences: the same number of pieces, each near its generated piece. A piece takes its heading
  // from its line's end points, which come from the generator's millimetre-rounded positions
  // (0.7 mm over a 12 m fence: up to ~0.007 degrees), not from its own heading.
  double worstFenceHeading = 0;
  for (const auto& [group, pieces] : fences) {
    std::vector<Eigen::Vector2d> ours;
    for (int k = 0; built.count(group + "/" + std::to_string(k)); ++k) {
      const auto& e = *built[group + "/" + std::to_string(k)];
      ours.emplace_back(e["position"][0].get<double>(), e["position"][1].get<double>());
      // A jersey barrier is symmetric end for end: the line may run either way.
      const double d = std::abs(angleDifference(e["heading"].get<double>(), pieces.front()->headingDeg));
      worstFenceHeading = std::max(worstFenceHeading, std::min(d, 180 - d));
    }
    ASSERT_EQ(ours.size(), pieces.size()) << group;
    for (const Placement* p : pieces) {
      double nearest = INFINITY;
      for (const Eigen::Vector2d& q : ours) nearest = std::min(nearest, (q - p->position).norm());
      worstPosition = std::max(worstPosition, nearest);
    }
  }
  std::printf("%zu generated pieces (%zu fences): built within %.2g m; headings within %.2g degrees (points), "
              "%.2g degrees (fence pieces)\n",
              generated().equipment.size(), fences.size(), worstPosition, worstHeading, worstFenceHeading);
  EXPECT_LE(worstPosition, 0.01);
  EXPECT_LE(worstHeading, 1e-6);
  EXPECT_LE(worstFenceHeading, 0.01);
}

TEST_F(GisSample, PickupFromMillimetresAndYUpStandsUprightAtItsSize) {
  const Scene scene = loadScene(kScene.string());
  bool found = false;
  for (const CollisionUnit& u : scene.units) {
    if (u.name.find("/pickup") == std::string::npos) continue;
    found = true;
    // Its inner box: the model's box (1.90 x 5.30 x 1.80), upright (one axis vertical).
    const Obb<double>& box = u.volume.inner;
    std::vector<double> sizes;
    int vertical = -1;
    for (int k = 0; k < 3; ++k) {
      sizes.push_back(2 * box.halfExtents[k]);
      if (std::abs(box.axes.col(k).z()) > 1 - 1e-9) vertical = k;
    }
    ASSERT_GE(vertical, 0) << u.name << ": not upright";
    EXPECT_NEAR(2 * box.halfExtents[vertical], 1.80, 0.018) << u.name;
    std::vector<double> horizontal;
    for (int k = 0; k < 3; ++k)
      if (k != vertical) horizontal.push_back(2 * box.halfExtents[k]);
    std::sort(horizontal.begin(), horizontal.end());
    EXPECT_NEAR(horizontal[0], 1.90, 0.019) << u.name;
    EXPECT_NEAR(horizontal[1], 5.30, 0.053) << u.name;
  }
  EXPECT_TRUE(found);
}

TEST_F(GisSample, EveryFlythroughPlaysWithItsExpectationsMet) {
  const test::TempFolder folder;
  for (const auto& [name, text] : generated().scripts) {
    const auto r = test::runNestwalk("run " + quoted(kScene) + " --script " + quoted(kInputs / "scripts" / name) +
                                     " --method auto --quiet --out " + quoted(folder / name));
    EXPECT_EQ(r.exitCode, 0) << name << "\n" << r.out << r.err;
  }
}

}  // namespace
}  // namespace nestwalk::assets
