// The model catalog (scene/model_catalog.h): every field read and checked with errors naming the
// file and field; the type transform against Eigen's own rotations of the same points; typed
// instances in a scene standing upright, in metres, their base at the lowest ground.
#include "nestwalk/scene/model_catalog.h"

#include "nestwalk/scene/model_geometry.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "tests/common/box_model.h"
#include "tests/scene/scene_test_util.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <osg/Geode>
#include <osg/Geometry>
#include <osgDB/WriteFile>

#include <numbers>

namespace nestwalk {
namespace {

using Json = nlohmann::json;
namespace fs = std::filesystem;


class ModelCatalogTest : public test::TempFolderTest {
 protected:
  std::string write(const Json& j) {
    test::writeText(dir() / "catalog.json", j.dump(2));
    return (dir() / "catalog.json").string();
  }
  std::string error(const Json& j) {
    const std::string path = write(j);
    return test::inputError([&] { readModelCatalog(path); });
  }
};

TEST_F(ModelCatalogTest, ReadsEveryFieldWithItsDefaults) {
  test::writeBoxModel(dir() / "box.osgt", {0, 0, 0}, {1, 1, 1});
  const ModelCatalog c = readModelCatalog(write(
      {{"types",
        {{"gauge", {{"model", "box.osgt"}, {"units", "mm"}, {"up", "y"}, {"forward", "-x"}, {"origin", "centre"},
                    {"kind", "station"}, {"use_only", true}, {"scale", 2}}},
         {"barrier", {{"model", "box.osgt"}, {"units", 0.3}, {"piece_length", 3.0}, {"max_gap", 0.2}, {"max_overlap", 0.4}}},
         {"plain", {{"model", (dir() / "box.osgt").string()}}}}}}));
  ASSERT_EQ(c.types.size(), 3u);
  const ModelType& g = c.types.at("gauge");
  EXPECT_EQ(g.model, (dir() / "box.osgt").string()) << "relative to the catalog's folder";
  EXPECT_EQ(g.metresPerUnit, 0.001);
  EXPECT_EQ(g.up, ModelUp::Y);
  EXPECT_EQ(g.forward, ModelForward::MinusX);
  EXPECT_EQ(g.origin, ModelOrigin::Centre);
  EXPECT_EQ(g.kind, "station");
  EXPECT_TRUE(g.useOnly);
  EXPECT_EQ(g.scale, 2.0);
  const ModelType& b = c.types.at("barrier");
  EXPECT_EQ(b.metresPerUnit, 0.3);
  EXPECT_EQ(*b.pieceLength, 3.0);
  EXPECT_EQ(maxGap(b, 3.0), 0.2);
  EXPECT_EQ(maxOverlap(b, 3.0), 0.4);
  const ModelType& p = c.types.at("plain");
  EXPECT_EQ(p.metresPerUnit, 1.0);
  EXPECT_EQ(p.up, ModelUp::Z);
  EXPECT_EQ(p.forward, ModelForward::PlusY);
  EXPECT_EQ(p.origin, ModelOrigin::Base);
  EXPECT_FALSE(p.useOnly);
  EXPECT_EQ(maxGap(p, 3.0), 0.1 * 3.0);
  EXPECT_EQ(maxOverlap(p, 3.0), 0.5 * 3.0);
  // The exact conversions of the named units.
  for (const auto& [name, metres] : {std::pair{"cm", 0.01}, {"m", 1.0}, {"in", 0.0254}, {"ft", 0.3048}}) {
    const ModelCatalog u = readModelCatalog(write({{"types", {{"t", {{"model", "box.osgt"}, {"units", name}}}}}}));
    EXPECT_EQ(u.types.at("t").metresPerUnit, metres) << name;
  }
  // Written back as JSON, read again: the same type.
  const Json again = {{"types", {{"gauge", modelTypeJson(g, "box.osgt")}}}};
  const ModelCatalog readAgain = readModelCatalog(write(again));
  const ModelType& g2 = readAgain.types.at("gauge");
  EXPECT_EQ(g2.metresPerUnit, g.metresPerUnit);
  EXPECT_EQ(g2.up, g.up);
  EXPECT_EQ(g2.forward, g.forward);
  EXPECT_EQ(g2.origin, g.origin);
  EXPECT_EQ(g2.useOnly, g.useOnly);
}

TEST_F(ModelCatalogTest, BadFieldsAreNamed) {
  test::writeBoxModel(dir() / "box.osgt", {0, 0, 0}, {1, 1, 1});
  const std::string f = (dir() / "catalog.json").string() + ": ";
  auto typeWith = [](const char* key, Json value) {
    Json t = {{"model", "box.osgt"}};
    t[key] = value;
    return Json{{"types", {{"gauge", t}}}};
  };
  EXPECT_EQ(error(typeWith("units", "furlong")), f + "types.gauge.units: expected mm, cm, m, in, ft or a number > 0, got 'furlong'");
  EXPECT_EQ(error(typeWith("units", -1)), f + "types.gauge.units: must be > 0");
  EXPECT_EQ(error(typeWith("up", "x")), f + "types.gauge.up: expected z, y, -y or -z, got 'x'");
  EXPECT_EQ(error(typeWith("forward", "north")), f + "types.gauge.forward: expected +y, -y, +x or -x, got 'north'");
  EXPECT_EQ(error(typeWith("origin", "top")), f + "types.gauge.origin: expected base, centre or file, got 'top'");
  EXPECT_EQ(error(typeWith("scale", 0)), f + "types.gauge.scale: must be > 0");
  EXPECT_EQ(error(typeWith("colour", "red")),
            f + "types.gauge.colour: unknown key (expected one of: model, units, up, forward, origin, kind, use_only, scale, "
                "piece_length, max_gap, max_overlap)");
  EXPECT_EQ(error({{"types", {{"gauge", {{"units", "m"}}}}}}), f + "types.gauge.model: missing (the model file is required)");
  EXPECT_EQ(error({{"types", Json::object()}}), f + "types: no type: a catalog needs at least one");
  EXPECT_EQ(error({{"kinds", Json::object()}}), f + "kinds: unknown key (expected one of: types)");
  EXPECT_EQ(error({{"types", {{"a", {{"model", "none1.stl"}}}, {"b", {{"model", "none2.stl"}}}}}}),
            f + "2 model files not found: types.a.model: " + (dir() / "none1.stl").string() +
                "; types.b.model: " + (dir() / "none2.stl").string());
  test::writeText(dir() / "catalog.json", "{\"types\": {\"a\": {\"model\": \"box.osgt\", \"model\": \"x\"}}}");
  EXPECT_EQ(test::inputError([&] { readModelCatalog((dir() / "catalog.json").string()); }), f + "types.a.model: duplicate key");
  EXPECT_EQ(test::inputError([&] { readModelCatalog((dir() / "none.json").string()); }),
            (dir() / "none.json").string() + ": catalog not found");
}

TEST(ModelTypeTransform, AgainstEigensRotationsOfTheSamePoints) {
  // A box from (1, 2, 3) to (4, 10, 5) file units: millimetres, y up, forward along -x once upright.
  std::vector<Vec3<double>> points;
  for (int k = 0; k < 8; ++k) points.push_back({(k & 1) ? 4.0 : 1.0, (k & 2) ? 10.0 : 2.0, (k & 4) ? 5.0 : 3.0});
  ModelType t;
  t.metresPerUnit = 0.001;
  t.up = ModelUp::Y;
  t.forward = ModelForward::MinusX;
  const double quarter = std::numbers::pi / 2;
  // Independent: y up -> z up is +90 degrees about x; then -x forward -> +y is -90 degrees about z.
  const Eigen::Matrix3d rotation = (Eigen::AngleAxisd(-quarter, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(quarter, Eigen::Vector3d::UnitX())).toRotationMatrix();
  EXPECT_LT((modelTypeRotation(t) - rotation).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(modelTypeRotation(t).cwiseAbs().maxCoeff(), 1.0);  // exact entries
  Aabb<double> box;
  for (const auto& p : points) box.extend(rotation * (0.001 * p));
  for (const auto& [origin, want] : {std::pair{ModelOrigin::Base, Eigen::Vector3d(box.center().x(), box.center().y(), box.min.z())},
                                     {ModelOrigin::Centre, box.center()},
                                     {ModelOrigin::File, Eigen::Vector3d::Zero()}}) {
    t.origin = origin;
    const Similarity<double> s = modelTypeTransform(t, points);
    for (const auto& p : points) EXPECT_LT((s.apply(p) - (rotation * (0.001 * p) - want)).norm(), 1e-15);
  }
  // Upright: the file's y extent (8 mm) is now the height, its -x side faces north (+y).
  t.origin = ModelOrigin::Base;
  const Similarity<double> s = modelTypeTransform(t, points);
  Aabb<double> placed;
  for (const auto& p : points) placed.extend(s.apply(p));
  EXPECT_NEAR(placed.size().z(), 0.008, 1e-15);
  EXPECT_NEAR(placed.min.z(), 0.0, 1e-15);
  EXPECT_NEAR(s.apply({1.0, 6.0, 4.0}).y(), placed.max.y(), 1e-15) << "the file's lowest x is the front";
  // The piece length along forward: the file's x extent (3 mm), times the scale.
  t.scale = 2.0;
  EXPECT_NEAR(pieceLength(t, points), 0.006, 1e-15);
}

TEST_F(ModelCatalogTest, TypedInstancesStandUprightInMetresOnTheGround) {
  test::PlaneTerrain terrain;
  test::writePlaneTiff(dir() / "terrain.tif", terrain);
  // A 600 x 250 x 400 mm cabinet drawn y up, forward along +x, origin far from the model.
  test::writeBoxModel(dir() / "cabinet.osgt", {1000, 2000, 3000}, {1600, 2400, 3250});
  const Json scene = {
      {"terrain", "terrain.tif"},
      {"types", {{"cabinet", {{"model", "cabinet.osgt"}, {"units", "mm"}, {"up", "y"}, {"forward", "+x"}, {"kind", "logger"}}}}},
      {"equipment", {{{"type", "cabinet"}, {"position", {terrain.sampleX(20), terrain.sampleY(30)}}},
                     {{"type", "cabinet"}, {"position", {terrain.sampleX(40), terrain.sampleY(10)}}, {"heading", 90}, {"scale", 2}}}}};
  test::writeText(dir() / "scene.json", scene.dump());
  const Scene s = loadScene((dir() / "scene.json").string());
  ASSERT_EQ(s.instances.size(), 2u);
  EXPECT_EQ(s.spec.equipment[0].name, "cabinet#0");
  EXPECT_EQ(s.spec.equipment[0].kind, "logger") << "the type's kind";
  for (std::size_t i = 0; i < 2; ++i) {
    const double scale = i == 0 ? 1.0 : 2.0;
    const Aabb<double>& box = s.instances[i].volume.outer;
    // Upright (the file's y extent is the height) and in metres; heading 0 points the front north,
    // so the 0.6 m the file draws along x runs along map y; heading 90 turns it east.
    const Eigen::Vector3d size = box.size();
    EXPECT_NEAR(size.z(), 0.4 * scale, 1e-9) << i;
    EXPECT_NEAR(i == 0 ? size.y() : size.x(), 0.6 * scale, 1e-9) << i;
    EXPECT_NEAR(i == 0 ? size.x() : size.y(), 0.25 * scale, 1e-9) << i;
    // Centred on its position, base at the lowest ground under it: on the plane, a corner.
    const Eigen::Vector3d centre = s.toMap(box.center());
    const Eigen::Vector2d at(s.spec.equipment[i].position.x(), s.spec.equipment[i].position.y());
    EXPECT_NEAR(centre.x(), at.x(), 1e-9);
    EXPECT_NEAR(centre.y(), at.y(), 1e-9);
    const Eigen::Vector3d lo = s.toMap(box.min), hi = s.toMap(box.max);
    double lowest = INFINITY;
    for (double x : {lo.x(), hi.x()})
      for (double y : {lo.y(), hi.y()}) lowest = std::min(lowest, terrain.height(x, y));
    EXPECT_NEAR(lo.z(), lowest, 1e-9) << i;
  }
}

}  // namespace
}  // namespace nestwalk
