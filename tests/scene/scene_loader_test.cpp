// Scene loading: small scenes on a planar GeoTIFF terrain written with GDAL, at the origin and at
// UTM magnitudes. Expected values come from the construction (the plane's formula) and from Eigen's
// own AngleAxis/Affine transforms of the model's vertices read separately. (The scene's drawing
// graph is tested with the renderer: tests/render/scene_graph_test.cpp.)
#include "nestwalk/geometry/volumes.h"
#include "nestwalk/scene/model_geometry.h"
#include "nestwalk/scene/node_geometry.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/terrain/imagery_import.h"
#include "nestwalk/terrain/terrain_imagery.h"
#include "nestwalk/terrain/terrain_pyramid.h"
#include "nestwalk/terrain/terrain_pyramid_writer.h"
#include "tests/common/build_paths.h"
#include "tests/common/box_model.h"
#include "tests/scene/scene_test_util.h"

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <chrono>
#include <numbers>
#include <optional>
#include <cstdlib>

namespace nestwalk {
namespace {

using test::inputError;
using test::weatherStation;
namespace fs = std::filesystem;
using Json = nlohmann::json;


/// Tolerance of comparisons between two double computations of the same local-frame point (tens
/// of metres from the origin): a few ulps of 100 m is ~1e-13; 1e-9 m leaves a wide margin while
/// still catching any real (millimetre) error.
constexpr double kLocalTol = 1e-9;

/// The independent model -> local transform: Eigen's AngleAxis in the documented order
/// Rz(-heading) Rx(pitch) Ry(roll), then scale, then the translation.
Eigen::Affine3d independentTransform(double heading, double pitch, double roll, double scale,
                                     const Eigen::Vector3d& translation) {
  constexpr double d = std::numbers::pi / 180.0;
  return Eigen::Translation3d(translation) * Eigen::AngleAxisd(-heading * d, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(pitch * d, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(roll * d, Eigen::Vector3d::UnitY()) *
         Eigen::Scaling(scale);
}

/// Where an instance without a z stands, computed independently of the loader: the lowest ground
/// under the x-y outline of its vertices placed by `xy` (map frame, at z 0). On the planar test
/// terrain the lowest point of a convex outline is one of its vertices, so the plane's formula at
/// every placed vertex gives it; `rise` (when given) receives the highest minus the lowest.
double standingZ(const std::vector<Vec3<double>>& modelVertices, const Eigen::Affine3d& xy, const test::PlaneTerrain& t,
                 double* rise = nullptr) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& p : modelVertices) {
    const Eigen::Vector3d q = xy * p;
    const double z = t.height(q.x(), q.y());
    lo = std::min(lo, z);
    hi = std::max(hi, z);
  }
  if (rise) *rise = hi - lo;
  return lo;
}


class SceneLoad : public test::PlaneTerrainTest {
 protected:
  /// Writes scene.json (terrain.tif beside it) with these equipment entries and loads it.
  Scene load(const Json& equipment, const SceneLoadOptions& options = {}, Json extra = Json::object()) {
    extra["terrain"] = "terrain.tif";
    extra["equipment"] = equipment;
    test::writeText(dir() / "scene.json", extra.dump(2));
    return loadScene((dir() / "scene.json").string(), options);
  }
  std::string scenePath() const { return (dir() / "scene.json").string(); }
};

TEST_P(SceneLoad, GroundHeightOriginAndModelsLoadedOnce) {
  const Json eq = Json::array({{{"model", weatherStation()}, {"position", at(20.3, 30.7)}},
                               {{"model", weatherStation()}, {"position", at(41.0, 12.5)}},
                               {{"model", weatherStation()}, {"position", {terrain_.sampleX(5), terrain_.sampleY(6), 7.25}}}});
  const Scene s = load(eq);
  ASSERT_EQ(s.models.size(), 1u);  // one file, loaded once
  ASSERT_EQ(s.instances.size(), 3u);
  // Default origin: the centre of the sample extent, z 0.
  EXPECT_EQ(s.origin, Eigen::Vector3d(0.5 * (terrain_.sampleX(0) + terrain_.sampleX(terrain_.cols - 1)),
                                      0.5 * (terrain_.sampleY(0) + terrain_.sampleY(terrain_.rows - 1)), 0.0));
  const std::vector<Vec3<double>> vertices = loadModelGeometry(weatherStation()).vertices;
  EXPECT_EQ(s.models[0].mesh.vertices, vertices) << "the scene keeps the mesh the file holds";
  EXPECT_FALSE(s.models[0].drawing.empty()) << "and the drawing side's .osgb bytes";
  for (int i = 0; i < 2; ++i) {
    const Eigen::Vector3d map = s.toMap(s.instances[i].toLocal.translation);
    const double x = eq[i]["position"][0].get<double>(), y = eq[i]["position"][1].get<double>();
    double rise = 0;
    const double z = standingZ(vertices, independentTransform(0, 0, 0, 1, Eigen::Vector3d(x, y, 0)), terrain_, &rise);
    EXPECT_NEAR(map.z(), z, 1e-9) << "the lowest ground under the footprint, by the plane's own formula";
    EXPECT_LT(map.z(), terrain_.height(x, y)) << "on the sloping plane, lower than the ground at the position itself";
    EXPECT_NEAR(s.instances[i].footprintRise, rise, 1e-9);
    EXPECT_NEAR(map.x(), x, 1e-9);
    EXPECT_NEAR(map.y(), y, 1e-9);
  }
  EXPECT_EQ(s.toMap(s.instances[2].toLocal.translation).z(), 7.25);  // z given: the ground is not asked
  // One unit per instance, named after it, in file order.
  ASSERT_EQ(s.units.size(), 3u);
  for (std::uint32_t i = 0; i < 3; ++i) {
    EXPECT_EQ(s.units[i].name, s.spec.equipment[i].name);
    EXPECT_EQ(s.instances[i].unit, i);
    EXPECT_EQ(s.units[i].instances, std::vector<std::uint32_t>{i});
    EXPECT_EQ(s.findUnit(s.spec.equipment[i].name), int(i));
  }
  EXPECT_EQ(s.findUnit("nothing"), -1);
}

/// Sets an environment variable for the scope, and restores it.
class ScopedEnvironment {
 public:
  ScopedEnvironment(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) saved_ = old;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnvironment() {
    if (saved_) ::setenv(name_, saved_->c_str(), 1);
    else ::unsetenv(name_);
  }

 private:
  const char* name_;
  std::optional<std::string> saved_;
};

TEST_P(SceneLoad, ATerrainsPyramidIsItsOwnWhenValidElseTheTerrainCachesImport) {
  const std::string terrainFile = (dir() / "terrain.tif").string();
  const Json none = Json::array();
  std::vector<std::string> notes;
  SceneLoadOptions options;
  options.note = [&](const std::string& text) { notes.push_back(text); };
  {
    const ScopedEnvironment off("NESTWALK_TERRAIN_CACHE", "off");
    EXPECT_EQ(load(none, options).terrainPyramid, nullptr);  // a plain GeoTIFF and no cache
  }
  const ScopedEnvironment cache("NESTWALK_TERRAIN_CACHE", (dir() / "cache").string());
  // A plain GeoTIFF: imported into the cache once (one note), then reused.
  Scene s = load(none, options);
  ASSERT_NE(s.terrainPyramid, nullptr);
  EXPECT_EQ(s.terrainPyramid->layout().cols, s.terrain->cols());
  EXPECT_NE(s.terrainPyramid->terrainPath().find((dir() / "cache").string()), std::string::npos);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("terrain cache"), std::string::npos) << notes[0];
  s = load(none, options);
  EXPECT_NE(s.terrainPyramid, nullptr);
  EXPECT_EQ(notes.size(), 1u);  // reused, not imported again
  // Its own pyramid beside it comes first.
  terrain::writeTerrainPyramid(terrainFile, terrain::pyramidPathOf(terrainFile));
  s = load(none, options);
  ASSERT_NE(s.terrainPyramid, nullptr);
  EXPECT_EQ(s.terrainPyramid->terrainPath(), terrainFile);
  // The terrain rewritten with another cell size: its own pyramid is set aside with the reason, the
  // cache imports the new one, and the scene loads as always.
  test::PlaneTerrain other = terrain_;
  other.cell = 1.5;
  test::writePlaneTiff(dir() / "terrain.tif", other);
  s = load(none, options);
  EXPECT_NE(s.terrainPyramidRefused.find("changed since"), std::string::npos) << s.terrainPyramidRefused;
  ASSERT_NE(s.terrainPyramid, nullptr);
  EXPECT_NE(s.terrainPyramid->terrainPath(), terrainFile);
  ASSERT_EQ(notes.size(), 3u);  // the refusal, then the new import
  EXPECT_EQ(notes[1], s.terrainPyramidRefused + " (not used)");
  EXPECT_NEAR(*s.terrain->groundHeight(other.sampleX(3), other.sampleY(4)), other.height(other.sampleX(3), other.sampleY(4)),
              1e-9);
}

TEST_P(SceneLoad, ImageryNotReadyToDrapeIsImportedOnceIntoTheTerrainCache) {
  // Over the terrain: an orthophoto 5000 pixels wide stored in strips without overviews (every coarse
  // view would read all of it: not ready to drape), and a small COG (ready as it is).
  const double pixel = 64.0 / 5000;
  std::vector<std::uint8_t> rgb(5000 * 4 * 3);
  for (std::size_t k = 0; k < rgb.size(); ++k) rgb[k] = std::uint8_t(k % 251);
  {
    terrain::initGdal();
    GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), (dir() / "wide.tif").c_str(), 5000, 4, 3, GDT_Byte, nullptr);
    ASSERT_NE(ds, nullptr);
    double gt[6] = {terrain_.west, pixel, 0.0, terrain_.north, 0.0, -pixel};
    GDALSetGeoTransform(ds, gt);
    int bands[3] = {1, 2, 3};
    ASSERT_EQ(GDALDatasetRasterIO(ds, GF_Write, 0, 0, 5000, 4, rgb.data(), 5000, 4, GDT_Byte, 3, bands, 3, 3 * 5000, 1),
              CE_None);
    GDALClose(ds);
  }
  terrain::writeImageryCog((dir() / "cog.tif").string(), 64, 64, std::vector<std::uint8_t>(64 * 64 * 3, 90),
                           terrain_.sampleX(0), terrain_.sampleY(0), 1, 1, "", false);
  std::vector<std::string> notes;
  SceneLoadOptions options;
  options.note = [&](const std::string& text) { notes.push_back(text); };
  const Json none = Json::array();
  {
    const ScopedEnvironment off("NESTWALK_TERRAIN_CACHE", "off");
    EXPECT_EQ(load(none, options, {{"imagery", "wide.tif"}}).drapedImagery, (dir() / "wide.tif").string());
  }
  const ScopedEnvironment cache("NESTWALK_TERRAIN_CACHE", (dir() / "cache").string());
  EXPECT_EQ(load(none, options, {{"imagery", "cog.tif"}}).drapedImagery, (dir() / "cog.tif").string());
  EXPECT_TRUE(load(none, options).drapedImagery.empty()) << "no imagery, nothing to drape";
  const std::size_t before = notes.size();
  const std::string imported = load(none, options, {{"imagery", "wide.tif"}}).drapedImagery;
  EXPECT_EQ(imported.find((dir() / "cache").string()), 0u) << imported;
  ASSERT_EQ(notes.size(), before + 1);
  EXPECT_NE(notes.back().find("importing it once into the terrain cache"), std::string::npos) << notes.back();
  // The import: the same pixels (lossy JPEG: within a few levels), tiled and ready.
  EXPECT_TRUE(terrain::imageryReadyToDrape(imported, ""));
  terrain::TerrainImagery original((dir() / "wide.tif").string(), ""), copy(imported, "");
  const auto a = original.read(terrain_.west + 10 * pixel, terrain_.north - 1.5 * pixel, pixel, pixel, 4000, 1);
  const auto b = copy.read(terrain_.west + 10 * pixel, terrain_.north - 1.5 * pixel, pixel, pixel, 4000, 1);
  ASSERT_EQ(a.size(), b.size());
  double error = 0;
  for (std::size_t k = 0; k < a.size(); ++k) error += std::abs(int(a[k]) - int(b[k])) / double(a.size());
  EXPECT_LT(error, 12.0) << "mean level difference (JPEG of a sawtooth)";
  // Reused while the file is unchanged; imported again when it changes.
  EXPECT_EQ(load(none, options, {{"imagery", "wide.tif"}}).drapedImagery, imported);
  EXPECT_EQ(notes.size(), before + 1);
  fs::last_write_time(dir() / "wide.tif", fs::last_write_time(dir() / "wide.tif") + std::chrono::seconds(5));
  EXPECT_EQ(load(none, options, {{"imagery", "wide.tif"}}).drapedImagery, imported);
  EXPECT_EQ(notes.size(), before + 2);
}

TEST_P(SceneLoad, APagedTerrainPlacesEverythingAsTheResidentOneBitForBit) {
  const std::string terrainFile = (dir() / "terrain.tif").string();
  terrain::writeTerrainPyramid(terrainFile, terrain::pyramidPathOf(terrainFile));
  const Json eq = Json::array({{{"model", weatherStation()}, {"position", at(20.3, 30.7)}},
                               {{"model", weatherStation()}, {"position", at(41.0, 12.5)}, {"heading", 33}},
                               {{"model", weatherStation()}, {"position", at(3.2, 60.1)}}});
  for (const Eigen::Vector3d& shift : {Eigen::Vector3d::Zero().eval(), Eigen::Vector3d(-1000.5, 2000.25, 3.5)}) {
    SceneLoadOptions resident, paged, automatic;
    resident.terrainStorage = SceneLoadOptions::TerrainStorage::resident;
    paged.terrainStorage = SceneLoadOptions::TerrainStorage::paged;
    paged.terrainTileBudget = 1;  // one tile at a time
    resident.mapShift = paged.mapShift = automatic.mapShift = shift;
    const Scene a = load(eq, resident), b = load(eq, paged);
    ASSERT_FALSE(a.terrain->paged());
    ASSERT_TRUE(b.terrain->paged());
    EXPECT_FALSE(load(eq, automatic).terrain->paged()) << "65 x 65 samples: held";
    ASSERT_EQ(a.instances.size(), b.instances.size());
    EXPECT_EQ(a.origin, b.origin);
    for (std::size_t i = 0; i < a.instances.size(); ++i) {
      EXPECT_EQ(a.instances[i].toLocal.translation, b.instances[i].toLocal.translation) << i;
      EXPECT_EQ(a.instances[i].footprintRise, b.instances[i].footprintRise) << i;
    }
    for (int k = 0; k < 500; ++k) {
      const double x = terrain_.sampleX(-1 + 0.137 * k) + shift.x(), y = terrain_.sampleY(0.1291 * k) + shift.y();
      EXPECT_EQ(a.terrain->groundHeight(x, y), b.terrain->groundHeight(x, y)) << k;
    }
  }
  // A plain DEM paged: from the terrain cache's import.
  fs::remove(terrain::pyramidPathOf(terrainFile));
  const ScopedEnvironment cache("NESTWALK_TERRAIN_CACHE", (dir() / "cache").string());
  SceneLoadOptions paged;
  paged.terrainStorage = SceneLoadOptions::TerrainStorage::paged;
  paged.note = nullptr;
  const Scene c = load(eq, paged);
  ASSERT_TRUE(c.terrain->paged());
  ASSERT_NE(c.terrainPyramid, nullptr);
  EXPECT_NE(c.terrainPyramid->terrainPath().find((dir() / "cache").string()), std::string::npos);
  for (int k = 0; k < 100; ++k) {
    const double x = terrain_.sampleX(0.61 * k), y = terrain_.sampleY(0.59 * k);
    EXPECT_NEAR(*c.terrain->groundHeight(x, y), terrain_.height(x, y), 1e-9) << k;
  }
}

TEST(SceneAttitude, ConventionsAndEigenAgree) {
  const Eigen::Vector3d forward = Eigen::Vector3d::UnitY(), right = Eigen::Vector3d::UnitX(), up = Eigen::Vector3d::UnitZ();
  EXPECT_EQ(attitudeRotation(90, 0, 0) * forward, Eigen::Vector3d(1, 0, 0)) << "heading 90: forward turns east";
  EXPECT_EQ(attitudeRotation(180, 0, 0) * forward, Eigen::Vector3d(0, -1, 0)) << "heading 180: south";
  EXPECT_EQ(attitudeRotation(-90, 0, 0) * forward, Eigen::Vector3d(-1, 0, 0)) << "heading -90: west";
  EXPECT_EQ(attitudeRotation(0, 90, 0) * forward, up) << "pitch 90: nose up";
  EXPECT_EQ(attitudeRotation(0, 0, 90) * right, -up) << "roll 90: right side down";
  EXPECT_EQ(attitudeRotation(90, 0, 0) * up, up);
  // Arbitrary angles: Eigen's AngleAxis in the documented order.
  for (const auto& [h, p, r] : {std::array<double, 3>{37, 4, -6}, {-123.5, 17, 81}, {400, -30, 200}}) {
    const Eigen::Matrix3d want = independentTransform(h, p, r, 1.0, Eigen::Vector3d::Zero()).linear();
    EXPECT_LT((attitudeRotation(h, p, r) - want).cwiseAbs().maxCoeff(), 1e-15) << h << " " << p << " " << r;
  }
}

TEST_P(SceneLoad, VolumesMatchAnIndependentTransformOfTheVertices) {
  const Json eq = Json::array({{{"model", weatherStation()}, {"position", at(20.3, 30.7)}, {"heading", 37},
                                {"pitch", 4}, {"roll", -6}, {"scale", 1.7}},
                               {{"model", weatherStation()}, {"position", at(50.5, 50.5)}, {"heading", 90}}});
  const Scene s = load(eq);
  const TriangleMesh model = loadModelGeometry(weatherStation());  // read again, apart from the scene
  ASSERT_GT(model.vertices.size(), 10u);
  for (std::size_t i = 0; i < 2; ++i) {
    const auto& e = eq[i];
    Eigen::Vector3d map(e["position"][0].get<double>(), e["position"][1].get<double>(), 0.0);
    map.z() = standingZ(model.vertices,
                        independentTransform(e.value("heading", 0.0), e.value("pitch", 0.0), e.value("roll", 0.0),
                                             e.value("scale", 1.0), map),
                        terrain_);
    const Eigen::Affine3d t = independentTransform(e.value("heading", 0.0), e.value("pitch", 0.0), e.value("roll", 0.0),
                                                   e.value("scale", 1.0), map - s.origin);
    Aabb<double> bounds;
    const NestedVolume<double>& v = s.instances[i].volume;
    for (const auto& p : model.vertices) {
      const Eigen::Vector3d q = t * p;
      bounds.extend(q);
      EXPECT_TRUE(v.outer.contains(q, 1e-12)) << "outer AABB, instance " << i;  // 1e-12: the two roundings
      EXPECT_TRUE(v.inner.contains(q, kLocalTol)) << "inner OBB, instance " << i;
    }
    EXPECT_LT((v.outer.min - bounds.min).cwiseAbs().maxCoeff(), kLocalTol) << "outer = exact bounds, instance " << i;
    EXPECT_LT((v.outer.max - bounds.max).cwiseAbs().maxCoeff(), kLocalTol) << "outer = exact bounds, instance " << i;
    // The inner box is the model's box moved: same half extents times the scale.
    EXPECT_LT((v.inner.halfExtents - e.value("scale", 1.0) * s.models[0].obb.halfExtents).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT(axesError(v.inner.axes), kAxesTolerance<double>);
  }
}

TEST_P(SceneLoad, UseOnlyMembersFormOneUnitPerGroup) {
  test::writeBoxModel(dir() / "box.osgt", {0, 0, 0}, {2, 1, 0.5});  // 2 x 1 x 0.5 m, corner at the origin
  const Json eq = Json::array({
      {{"name", "lone"}, {"model", "box.osgt"}, {"position", at(5, 5)}, {"kind", "container"}},
      {{"model", weatherStation()}, {"position", at(20, 20)}, {"group", "bench1/st1"}, {"use_only", true}, {"kind", "mast"}},
      {{"name", "st1-pole"}, {"model", "box.osgt"}, {"position", at(22, 20)}, {"group", "bench1/st1"}},
      {{"model", "box.osgt"}, {"position", at(21, 23)}, {"heading", 45}, {"group", "bench1/st1"}, {"use_only", true},
       {"kind", "panel"}},
      {{"model", "box.osgt"}, {"position", at(40, 40)}, {"group", "bench2"}, {"use_only", true}, {"kind", "panel"}},
  });
  const Scene s = load(eq);
  ASSERT_EQ(s.units.size(), 4u);
  // File order; a group's unit where its first member appears.
  EXPECT_EQ(s.units[0].name, "lone");
  EXPECT_EQ(s.units[0].kind, "container");
  EXPECT_EQ(s.units[1].name, "bench1/st1");
  EXPECT_EQ(s.units[1].group, "bench1/st1");
  EXPECT_EQ(s.units[1].kind, "") << "mixed kinds: no label";
  EXPECT_EQ(s.units[1].instances, (std::vector<std::uint32_t>{1, 3}));
  EXPECT_EQ(s.units[2].name, "st1-pole");
  EXPECT_EQ(s.units[2].group, "bench1/st1");
  EXPECT_EQ(s.units[3].name, "bench2");
  EXPECT_EQ(s.units[3].kind, "panel");
  EXPECT_EQ(s.instances[1].unit, 1u);
  EXPECT_EQ(s.instances[3].unit, 1u);
  EXPECT_EQ(s.instances[2].unit, 2u);
  EXPECT_EQ(s.findUnit("bench1/st1"), 1);
  EXPECT_EQ(s.unitGroups(), (std::vector<std::string>{"", "bench1/st1", "bench1/st1", "bench2"}));
  const std::vector<Aabb<double>> boxes = s.unitBoxes();
  ASSERT_EQ(boxes.size(), 4u);
  // The group's volumes hold every vertex of both members (transformed independently).
  Aabb<double> bounds;
  for (std::uint32_t k : {1u, 3u}) {
    const auto& e = eq[k];
    const TriangleMesh g = loadModelGeometry(s.models[s.instances[k].model].path);
    const double x = e["position"][0].get<double>(), y = e["position"][1].get<double>();
    const double z = standingZ(g.vertices, independentTransform(e.value("heading", 0.0), 0, 0, 1, Eigen::Vector3d(x, y, 0)),
                               terrain_);
    const Eigen::Affine3d t = independentTransform(e.value("heading", 0.0), 0, 0, 1, Eigen::Vector3d(x, y, z) - s.origin);
    for (const auto& p : g.vertices) {
      const Eigen::Vector3d q = t * p;
      bounds.extend(q);
      EXPECT_TRUE(s.units[1].volume.inner.contains(q, kLocalTol));
      EXPECT_TRUE(boxes[1].contains(q, 1e-12));
    }
  }
  EXPECT_LT((boxes[1].min - bounds.min).cwiseAbs().maxCoeff(), kLocalTol);
  EXPECT_LT((boxes[1].max - bounds.max).cwiseAbs().maxCoeff(), kLocalTol);
  // The group unit's inner box is fitted to the members together: not either member's box.
  EXPECT_GT(s.units[1].volume.inner.volume(), s.instances[1].volume.inner.volume());
}

TEST_P(SceneLoad, ExplicitOriginAndMapShiftGiveTheSameLocalVolumes) {
  test::writeBoxModel(dir() / "box.osgt", {0, 0, 0}, {2, 1, 0.5});  // 2 x 1 x 0.5 m, corner at the origin
  const Json eq = Json::array({
      {{"model", weatherStation()}, {"position", at(20.3, 30.7)}, {"heading", 37}, {"pitch", 3}},
      {{"model", "box.osgt"}, {"position", at(44.4, 12.1)}, {"heading", 120}, {"group", "g"}, {"use_only", true}},
      {{"model", weatherStation()}, {"position", at(46.1, 13.7)}, {"group", "g"}, {"use_only", true}},
  });
  const Scene a = load(eq);
  SceneLoadOptions shift;
  shift.mapShift = {-GetParam().west, -(GetParam().north - 65.0), 0.0};  // the UTM case moves to the origin
  const Scene b = load(eq, shift);
  EXPECT_EQ(b.origin, a.origin + shift.mapShift);
  EXPECT_EQ(b.terrain->origin(), a.terrain->origin() + shift.mapShift.head<2>());
  ASSERT_EQ(a.units.size(), b.units.size());
  // The standing heights come from the ground under the footprints in map coordinates, where the
  // UTM case rounds to ~1e-9 m: the points the boxes are fitted to differ by that much, which turns
  // a fitted box's axes by up to ~1e-10 rad over metres (1e-9 m at its corners).
  constexpr double kAxesTol = 1e-10;
  auto near = [](const NestedVolume<double>& x, const NestedVolume<double>& y) {
    return (x.outer.min - y.outer.min).cwiseAbs().maxCoeff() <= kLocalTol &&
           (x.outer.max - y.outer.max).cwiseAbs().maxCoeff() <= kLocalTol &&
           (x.inner.center - y.inner.center).cwiseAbs().maxCoeff() <= kLocalTol &&
           (x.inner.axes - y.inner.axes).cwiseAbs().maxCoeff() <= kAxesTol &&
           (x.inner.halfExtents - y.inner.halfExtents).cwiseAbs().maxCoeff() <= kLocalTol;
  };
  for (std::size_t i = 0; i < a.instances.size(); ++i) EXPECT_TRUE(near(a.instances[i].volume, b.instances[i].volume)) << i;
  for (std::size_t i = 0; i < a.units.size(); ++i)
    EXPECT_TRUE(near(a.units[i].volume, b.units[i].volume))
        << i << ": outer " << (a.units[i].volume.outer.min - b.units[i].volume.outer.min).transpose() << " / "
        << (a.units[i].volume.outer.max - b.units[i].volume.outer.max).transpose() << ", centre "
        << (a.units[i].volume.inner.center - b.units[i].volume.inner.center).transpose() << ", axes "
        << (a.units[i].volume.inner.axes - b.units[i].volume.inner.axes).cwiseAbs().maxCoeff() << ", half "
        << (a.units[i].volume.inner.halfExtents - b.units[i].volume.inner.halfExtents).transpose();

  // An explicit origin is used as given (and moved by the shift).
  const Eigen::Vector3d origin(terrain_.sampleX(10), terrain_.sampleY(10), 50.0);
  const Scene c = load(eq, shift, Json{{"origin", {origin.x(), origin.y(), origin.z()}}});
  EXPECT_EQ(c.origin, origin + shift.mapShift);
  const Eigen::Vector3d mapA = a.toMap(a.instances[0].toLocal.translation), mapC = c.toMap(c.instances[0].toLocal.translation);
  EXPECT_LT((mapC - (mapA + shift.mapShift)).cwiseAbs().maxCoeff(), kLocalTol);
}

TEST_P(SceneLoad, UnreadableEmptyAndGroundlessAreErrors) {
  test::writeText(dir() / "junk.osgb", "not a model");
  test::writeText(dir() / "model.xyzzy", "no plugin for this");
  osgDB::writeNodeFile(*osg::ref_ptr<osg::Group>(new osg::Group), (dir() / "empty.osgt").string());
  // Every unreadable model in one error; a readable one is not named.
  std::string e = inputError([&] {
    load(Json::array({{{"model", "junk.osgb"}, {"position", at(5, 5)}},
                      {{"model", weatherStation()}, {"position", at(6, 6)}},
                      {{"model", "model.xyzzy"}, {"position", at(7, 7)}},
                      {{"model", "junk.osgb"}, {"position", at(8, 8)}}}));
  });
  EXPECT_EQ(e.rfind(scenePath() + ": 2 models could not be read: " + (dir() / "junk.osgb").string() + " (", 0), 0u) << e;
  EXPECT_NE(e.find("; " + (dir() / "model.xyzzy").string() + " (no OpenSceneGraph plugin reads it)"), std::string::npos) << e;
  EXPECT_EQ(e.find("weather_station"), std::string::npos) << e;

  e = inputError([&] { load(Json::array({{{"model", "empty.osgt"}, {"position", at(5, 5)}}})); });
  EXPECT_EQ(e.rfind(scenePath() + ": model " + (dir() / "empty.osgt").string() + ": the model holds no vertices", 0), 0u) << e;

  // No ground under all of the footprint: beyond the outermost sample centres (the raster's outer
  // half cell has none), entirely or in part.
  e = inputError([&] {
    load(Json::array({{{"name", "off-east"}, {"model", weatherStation()}, {"position", at(64.2, 5)}},
                      {{"model", weatherStation()}, {"position", at(5, 5)}},
                      {{"model", weatherStation()}, {"position", at(3, -3)}}}));
  });
  EXPECT_EQ(e.rfind(scenePath() + ": no ground under equipment[0] 'off-east' at (", 0), 0u) << e;
  EXPECT_NE(e.find("(under part of its footprint); equipment[2] 'weather_station#2' at ("), std::string::npos) << e;
  EXPECT_EQ(e.find("equipment[1]"), std::string::npos) << e;
  // With a z the ground is not needed: the instance stands where the file puts it, off the terrain.
  const Eigen::Vector3d offTerrain(terrain_.sampleX(70), terrain_.sampleY(5), 3.0);
  const Scene s = load(Json::array({{{"model", weatherStation()}, {"position", {offTerrain.x(), offTerrain.y(), offTerrain.z()}}}}));
  ASSERT_EQ(s.instances.size(), 1u);
  EXPECT_FALSE(s.terrain->groundHeight(offTerrain.x(), offTerrain.y()).has_value());
  const Eigen::Vector3d placed = s.toMap(s.instances[0].toLocal.translation);
  EXPECT_EQ(placed.z(), 3.0);
  EXPECT_NEAR(placed.x(), offTerrain.x(), 1e-9);
  EXPECT_NEAR(placed.y(), offTerrain.y(), 1e-9);

  // A terrain that is no raster: readDem's message, behind the scene file and field.
  test::writeText(dir() / "terrain.tif", "not a raster");
  e = inputError([&] { load(Json::array()); });
  EXPECT_EQ(e.rfind(scenePath() + ": terrain: " + (dir() / "terrain.tif").string(), 0), 0u) << e;
  fs::remove(dir() / "terrain.tif");
  e = inputError([&] { load(Json::array()); });
  EXPECT_EQ(e, scenePath() + ": terrain: file not found: " + (dir() / "terrain.tif").string());
}

INSTANTIATE_TEST_SUITE_P(Places, SceneLoad, ::testing::ValuesIn(test::kTerrainPlaces),
                         [](const auto& info) { return std::string(info.param.name); });

// The real models (shared data): every format they come in, each loaded once, volumes containing
// every vertex transformed independently.
TEST(SceneRealModels, VolumesContainEveryVertex) {
  const fs::path data = test::sharedData();
  if (data.empty()) GTEST_SKIP() << "shared data folder absent (" << nestwalk::test::build::sharedDataDir() << "): real models not tested";
  std::vector<std::string> models;
  for (const char* m : {"models/dumptruck.osgt", "models/street_lamp.osgb", "models/excavator_chassis.obj", "models/jeep1/jeep1.3ds"})
    if (fs::exists(data / m)) models.push_back((data / m).string());
  if (models.empty()) GTEST_SKIP() << "no real models in " << (data / "models");
  const test::TempFolder folder;
  const fs::path& dir = folder.path();
  // A terrain with room for the dump truck's 30 file units (no catalog: the file's own units).
  test::PlaneTerrain t;
  t.cols = t.rows = 170;
  t.west = 550000.0;
  t.north = 4650170.0;
  test::writePlaneTiff(dir / "terrain.tif", t);
  Json eq = Json::array();
  for (std::size_t i = 0; i < models.size(); ++i)
    for (double heading : {0.0, 63.0})
      eq.push_back({{"model", models[i]}, {"position", {t.sampleX(30.0 + 36.0 * double(i)), t.sampleY(heading == 0 ? 40 : 120)}},
                    {"heading", heading}});
  test::writeText(dir / "scene.json", Json{{"terrain", "terrain.tif"}, {"equipment", eq}}.dump());
  const auto start = std::chrono::steady_clock::now();
  const Scene s = loadScene((dir / "scene.json").string());
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("loaded %zu real models (%zu instances) in %.2f s\n", s.models.size(), s.instances.size(), seconds);
  ASSERT_EQ(s.models.size(), models.size());
  for (std::size_t i = 0; i < s.instances.size(); ++i) {
    const SceneInstance& inst = s.instances[i];
    const TriangleMesh g = loadModelGeometry(s.models[inst.model].path);  // read again, independently
    const auto& e = eq[i];
    const double x = e["position"][0].get<double>(), y = e["position"][1].get<double>();
    const double h = e["heading"].get<double>();
    const double z = standingZ(g.vertices, independentTransform(h, 0, 0, 1, Eigen::Vector3d(x, y, 0)), t);
    const Eigen::Affine3d tr = independentTransform(h, 0, 0, 1, Eigen::Vector3d(x, y, z) - s.origin);
    // Tolerances relative to the model's size: the fitter's 1e-9 relative containment.
    const double size = s.models[inst.model].aabb.size().norm();
    Aabb<double> bounds;
    std::size_t outside = 0;
    for (const auto& p : g.vertices) {
      const Eigen::Vector3d q = tr * p;
      bounds.extend(q);
      outside += !inst.volume.outer.contains(q, 1e-12 * size) || !inst.volume.inner.contains(q, 1e-9 * size);
    }
    EXPECT_EQ(outside, 0u) << s.models[inst.model].path;
    EXPECT_LT((inst.volume.outer.min - bounds.min).cwiseAbs().maxCoeff(), 1e-9 * size) << s.models[inst.model].path;
    EXPECT_LT((inst.volume.outer.max - bounds.max).cwiseAbs().maxCoeff(), 1e-9 * size) << s.models[inst.model].path;
  }
}

}  // namespace
}  // namespace nestwalk
