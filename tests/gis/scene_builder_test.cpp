// build-scene on bad input (gis/scene_builder.h): every bad feature named in one error with its
// source, layer and feature id, nothing written; --skip-bad leaves them out and lists them; whole
// inputs that are wrong (source, layer, CRS, --where, catalog, output) stop with their name; a DEM
// that already is a terrain COG is used where it is; footprints on rising ground are reported.
#include "nestwalk/core/input_error.h"
#include "nestwalk/gis/scene_builder.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/terrain/terrain_imagery.h"
#include "nestwalk/terrain/terrain_import.h"
#include "tests/gis/gis_test_util.h"

#include <gtest/gtest.h>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

class SceneBuilder : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = std::make_unique<test::TempFolder>();
    terrain_ = {32612, 400000.0, 5100400.0, 200};
    test::writeUtmTerrain(dir() / "dem.tif", terrain_, std::pair{150, 150});  // a 7 x 7 hole near the south-east
    test::writeBoxModel(dir() / "box.osgt", {-0.5, -1.0, 0.0}, {0.5, 1.0, 1.0});
    test::writeBoxModel(dir() / "rail.osgt", {-0.1, -1.5, 0.0}, {0.1, 1.5, 0.8});
    test::writeText(dir() / "catalog.json", R"({"types": {"box": {"model": "box.osgt"}, "rail": {"model": "rail.osgt"}}})");
    proj_ = std::make_unique<test::ProjOracle>(terrain_.epsg);
  }
  void TearDown() override { folder_.reset(); }
  fs::path dir() const { return folder_->path(); }
  /// A GeoJSON point at UTM (x, y) of the terrain (offsets from its north-west corner).
  Json point(double dx, double dy, Json properties) const {
    const Eigen::Vector2d ll = proj_->toLonLat({terrain_.west + dx, terrain_.north - dy});
    return {{"type", "Feature"}, {"properties", properties}, {"geometry", {{"type", "Point"}, {"coordinates", {ll.x(), ll.y()}}}}};
  }
  std::string writeGeoJson(const std::string& name, const Json& features) const {
    test::writeText(dir() / name, Json{{"type", "FeatureCollection"}, {"features", features}}.dump());
    return (dir() / name).string();
  }
  gis::BuildSceneOptions options(std::vector<std::string> sources) const {
    gis::BuildSceneOptions o;
    o.terrain = (dir() / "dem.tif").string();
    o.catalog = (dir() / "catalog.json").string();
    o.out = (dir() / "scene").string();
    o.layers.sources = std::move(sources);
    return o;
  }
  std::string error(const gis::BuildSceneOptions& o) const {
    try {
      gis::buildScene(o);
    } catch (const InputError& e) {
      return e.what();
    }
    ADD_FAILURE() << "no error";
    return {};
  }
  std::unique_ptr<test::TempFolder> folder_;
  test::UtmTerrain terrain_;
  std::unique_ptr<test::ProjOracle> proj_;
};

Json badFeatures(const SceneBuilder& t, const std::function<Json(double, double, Json)>& point) {
  (void)t;
  Json f = Json::array();
  f.push_back(point(50, 50, {{"type", "box"}, {"name", "good"}}));                          // 0
  f.push_back(point(60, 50, {{"type", "crate"}, {"name", "unknown"}}));                     // 1: unknown type
  f.push_back(point(150, 150, {{"type", "box"}, {"name", "in the hole"}}));                  // 2: over nodata
  f.push_back(point(-30, 50, {{"type", "box"}, {"name", "off"}}));                          // 3: outside
  f.push_back(point(70, 50, {{"type", "box"}, {"name", "good"}}));                          // 4: name again
  f.push_back(point(80, 50, {{"type", "box"}, {"name", "turned"}, {"heading", "north"}}));   // 5: heading text
  Json collection = point(85, 50, {})["geometry"];                                            // 6: a collection
  f.push_back({{"type", "Feature"}, {"properties", {{"type", "box"}}},
               {"geometry", {{"type", "GeometryCollection"}, {"geometries", Json::array({collection})}}}});
  f.push_back(point(90, 50, {{"name", "untyped"}}));                                          // 7: no type
  f.push_back(point(100, 60, {{"type", "box"}, {"name", "also good"}}));                    // 8
  return f;
}

TEST_F(SceneBuilder, EveryBadFeatureInOneErrorAndNothingWritten) {
  const std::string src = writeGeoJson("eq.geojson", badFeatures(*this, [&](double x, double y, Json p) { return point(x, y, p); }));
  const std::string e = error(options({src}));
  const std::string layer = src + ": layer 'eq' feature ";
  EXPECT_EQ(e.rfind("7 bad features (fix them, or leave them out with --skip-bad): ", 0), 0u) << e;
  for (const std::string& want :
       {layer + "1: unknown type 'crate' (the catalog has: box, rail)",
        layer + "2: has no ground under it (outside the terrain, or over nodata) at (400150.000, 5100250.000)",
        layer + "3: has no ground under it (outside the terrain, or over nodata)",
        layer + "4: name 'good' is already the name of " + layer + "0",
        layer + "5: heading 'north' is not a number (degrees)",
        layer + "6: has an unsupported geometry (Geometry Collection): give points, lines or polygons",
        layer + "7: no type (the field 'type' is empty)"})
    EXPECT_NE(e.find(want), std::string::npos) << want << "\nin: " << e;
  EXPECT_EQ(e.find(layer + "0:"), std::string::npos) << e;
  EXPECT_EQ(e.find(layer + "8:"), std::string::npos) << e;
  EXPECT_FALSE(fs::exists(dir() / "scene"));
  for (const auto& entry : fs::directory_iterator(dir()))
    EXPECT_EQ(entry.path().filename().string().find(".scene"), std::string::npos) << "a temporary left: " << entry.path();
}

TEST_F(SceneBuilder, SkipBadLeavesThemOutAndListsThem) {
  const std::string src = writeGeoJson("eq.geojson", badFeatures(*this, [&](double x, double y, Json p) { return point(x, y, p); }));
  gis::BuildSceneOptions o = options({src});
  o.skipBad = true;
  const gis::BuildSceneSummary s = gis::buildScene(o);
  EXPECT_EQ(s.skipped.size(), 7u);
  EXPECT_EQ(s.pointInstances, 2u);
  const Scene scene = loadScene(s.sceneFile);
  ASSERT_EQ(scene.instances.size(), 2u);
  EXPECT_EQ(scene.spec.equipment[0].name, "good");
  EXPECT_EQ(scene.spec.equipment[1].name, "also good");
  const Json written = Json::parse(test::readText(s.sceneFile));
  ASSERT_EQ(written["source"]["skipped"].size(), 7u);
  EXPECT_EQ(written["source"]["skipped"][0]["feature"], src + ": layer 'eq' feature 1");
}

TEST_F(SceneBuilder, BadInputsAreNamed) {
  const std::string good = writeGeoJson("good.geojson", Json::array({point(50, 50, {{"type", "box"}})}));
  const std::string empty = writeGeoJson("empty.geojson", Json::array());
  auto with = [&](auto change) {
    gis::BuildSceneOptions o = options({good});
    change(o);
    return error(o);
  };
  EXPECT_EQ(with([&](auto& o) { o.layers.sources = {empty}; }), empty + ": layer 'empty': has no features");
  EXPECT_EQ(with([&](auto& o) { o.layers.where = "type = 'crate'"; }),
            good + ": layer 'good': --where 'type = 'crate'' matches no feature");
  EXPECT_EQ(with([&](auto& o) { o.layers.where = "type =="; }).rfind(good + ": layer 'good': --where 'type ==': ", 0), 0u);
  EXPECT_EQ(with([&](auto& o) { o.layers.layers = {"nothing"}; }), "--layer nothing: no such layer in the sources given");
  EXPECT_EQ(with([&](auto& o) { o.layers.sources = {(dir() / "none.gpkg").string()}; }), (dir() / "none.gpkg").string() + ": file not found");
  EXPECT_EQ(with([&](auto& o) { o.layers.fields.type = "kind"; }),
            good + ": layer 'good': has no field 'kind' for the equipment type (name the field with --type-field, or give --default-type)");
  // A CSV has no CRS: one must be given, and readable.
  test::writeText(dir() / "eq.csv", "x,y,type\n400050,5100350,box\n");
  const std::string csv = (dir() / "eq.csv").string();
  EXPECT_EQ(with([&](auto& o) { o.layers.sources = {csv}; }),
            csv + ": layer 'eq': has no CRS; give the CRS its coordinates are in with --layer-crs (e.g. EPSG:4326)");
  EXPECT_EQ(with([&](auto& o) {
              o.layers.sources = {csv};
              o.layers.assumedCrs = "EPSG:99999999";
            }).rfind(csv + ": layer 'eq': --layer-crs: cannot read the CRS 'EPSG:99999999'", 0),
            0u);
  // The catalog: a missing model, a bad unit.
  test::writeText(dir() / "bad_catalog.json", R"({"types": {"box": {"model": "gone.osgt"}}})");
  EXPECT_EQ(with([&](auto& o) { o.catalog = (dir() / "bad_catalog.json").string(); }),
            (dir() / "bad_catalog.json").string() + ": 1 model file not found: types.box.model: " + (dir() / "gone.osgt").string());
  test::writeText(dir() / "unit_catalog.json", R"({"types": {"box": {"model": "box.osgt", "units": "yards"}}})");
  EXPECT_EQ(with([&](auto& o) { o.catalog = (dir() / "unit_catalog.json").string(); }),
            (dir() / "unit_catalog.json").string() + ": types.box.units: expected mm, cm, m, in, ft or a number > 0, got 'yards'");
  // An existing output folder is kept without --overwrite.
  fs::create_directories(dir() / "scene");
  test::writeText(dir() / "scene" / "mine.txt", "keep");
  EXPECT_EQ(with([](auto&) {}), (dir() / "scene").string() + ": already exists (use --overwrite to replace it)");
  EXPECT_EQ(test::readText(dir() / "scene" / "mine.txt"), "keep");
  gis::BuildSceneOptions o = options({good});
  o.overwrite = true;
  gis::buildScene(o);
  EXPECT_FALSE(fs::exists(dir() / "scene" / "mine.txt"));
  EXPECT_TRUE(fs::exists(dir() / "scene" / "scene.json"));
}

TEST_F(SceneBuilder, TerrainCogUsedWhereItIsAndRisingGroundReported) {
  terrain::importTerrain((dir() / "dem.tif").string(), (dir() / "terrain_cog.tif").string(), {});
  test::writeText(dir() / "big_catalog.json", R"({"types": {"slab": {"model": "box.osgt", "scale": 40}}})");
  const std::string src = writeGeoJson("eq.geojson", Json::array({point(100, 60, {{"type", "slab"}, {"name", "slab"}})}));
  gis::BuildSceneOptions o = options({src});
  o.terrain = (dir() / "terrain_cog.tif").string();
  o.catalog = (dir() / "big_catalog.json").string();
  o.maxFootprintRise = 0.5;
  const gis::BuildSceneSummary s = gis::buildScene(o);
  EXPECT_FALSE(s.terrainImported);
  EXPECT_FALSE(fs::exists(dir() / "scene" / "terrain.tif"));
  EXPECT_EQ(Json::parse(test::readText(s.sceneFile))["terrain"], "../terrain_cog.tif");
  // A 40 x 80 m slab on a 2 % + 1 % slope with waves: well over 0.5 m of ground under it.
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("feature 0: stands on "), std::string::npos) << s.warnings[0];
  const Scene scene = loadScene(s.sceneFile);
  EXPECT_GT(scene.instances[0].footprintRise, 0.5);
}

TEST_F(SceneBuilder, ImageryIsNamedWhereItIsOrImportedAndMustOverlapTheTerrain) {
  const std::string src = writeGeoJson("eq.geojson", Json::array({point(50, 50, {{"type", "box"}, {"name", "a"}})}));
  const std::string crs = "EPSG:" + std::to_string(terrain_.epsg);
  const std::vector<std::uint8_t> grey(100 * 100 * 3, 120);
  // Ready to drape (a COG in the terrain's CRS): named where it is.
  terrain::writeImageryCog((dir() / "ready.tif").string(), 100, 100, grey, terrain_.west + 1, terrain_.north - 1, 2, 2,
                           crs, false);
  gis::BuildSceneOptions o = options({src});
  o.imagery = (dir() / "ready.tif").string();
  gis::BuildSceneSummary s = gis::buildScene(o);
  EXPECT_FALSE(s.imageryImported);
  EXPECT_EQ(Json::parse(test::readText(s.sceneFile))["imagery"], "../ready.tif");
  EXPECT_EQ(loadScene(s.sceneFile).drapedImagery, (dir() / "scene" / ".." / "ready.tif").lexically_normal().string());
  // In longitude and latitude: imported beside the terrain, in its CRS.
  const Eigen::Vector2d nw = proj_->toLonLat({terrain_.west, terrain_.north});
  const Eigen::Vector2d se = proj_->toLonLat({terrain_.west + terrain_.size, terrain_.north - terrain_.size});
  terrain::writeImageryCog((dir() / "lonlat.tif").string(), 100, 100, grey, nw.x(), nw.y(), (se.x() - nw.x()) / 100,
                           (nw.y() - se.y()) / 100, "EPSG:4326", false);
  o.imagery = (dir() / "lonlat.tif").string();
  o.overwrite = true;
  s = gis::buildScene(o);
  EXPECT_TRUE(s.imageryImported);
  EXPECT_EQ(Json::parse(test::readText(s.sceneFile))["imagery"], "imagery.tif");
  const Scene scene = loadScene(s.sceneFile);
  EXPECT_FALSE(terrain::TerrainImagery(scene.drapedImagery, scene.terrain->crsWkt()).reprojected());
  // Ten kilometres east: nothing to drape, an error naming the file, and the scene kept as it was.
  terrain::writeImageryCog((dir() / "elsewhere.tif").string(), 100, 100, grey, terrain_.west + 10000, terrain_.north, 2,
                           2, crs, false);
  o.imagery = (dir() / "elsewhere.tif").string();
  EXPECT_NE(error(o).find(o.imagery + ": does not overlap the terrain"), std::string::npos) << error(o);
  EXPECT_EQ(Json::parse(test::readText(s.sceneFile))["imagery"], "imagery.tif");
}

}  // namespace
}  // namespace nestwalk
