// Scene files: defaults, path resolution, and every kind of bad input, each with the exact message
// (file, field path, problem). Files only need to exist here: nothing is loaded.
#include "nestwalk/scene/scene_file.h"
#include "tests/scene/scene_test_util.h"

#include <nlohmann/json.hpp>

#include <functional>

namespace nestwalk {
namespace {

using test::inputError;
using test::writeText;
namespace fs = std::filesystem;
using Json = nlohmann::json;

class SceneFile : public test::TempFolderTest {
 protected:
  void SetUp() override {
    TempFolderTest::SetUp();
    fs::create_directories(dir() / "models");
    for (const char* f : {"terrain.tif", "a.obj", "models/b.osgt"}) writeText(dir() / f, "x");
  }
  std::string scenePath() const { return (dir() / "scene.json").string(); }
  SceneSpec parse(const Json& j) const { return parseSceneJson(j.dump(2), scenePath()); }
  /// A valid scene: two instances.
  static Json base() {
    return Json{{"terrain", "terrain.tif"},
                {"equipment", Json::array({Json{{"model", "a.obj"}, {"position", {10.0, 20.0}}},
                                           Json{{"model", "models/b.osgt"}, {"position", {30.0, 40.0, 5.0}}}})}};
  }
  /// The message parsing `j` gives, with the scene path and ": " removed from its front.
  std::string error(const Json& j) const { return errorOfText(j.dump(2)); }
  std::string errorOfText(const std::string& text) const {
    const std::string e = inputError([&] { parseSceneJson(text, scenePath()); });
    const std::string prefix = scenePath() + ": ";
    EXPECT_EQ(e.rfind(prefix, 0), 0u) << "the message must start with the scene file: " << e;
    return e.substr(std::min(e.size(), prefix.size()));
  }
};

TEST_F(SceneFile, DefaultsAndResolvedPaths) {
  const SceneSpec s = parse(base());
  EXPECT_EQ(s.path, scenePath());
  EXPECT_EQ(s.terrain, (dir() / "terrain.tif").string());
  EXPECT_FALSE(s.imagery.has_value());
  EXPECT_FALSE(s.origin.has_value());
  ASSERT_EQ(s.equipment.size(), 2u);
  const EquipmentSpec& a = s.equipment[0];
  EXPECT_EQ(a.name, "a#0");
  EXPECT_EQ(a.model, (dir() / "a.obj").string());
  EXPECT_EQ(a.position, Eigen::Vector3d(10, 20, 0));
  EXPECT_FALSE(a.hasZ);
  EXPECT_EQ(a.headingDeg, 0.0);
  EXPECT_EQ(a.pitchDeg, 0.0);
  EXPECT_EQ(a.rollDeg, 0.0);
  EXPECT_EQ(a.scale, 1.0);
  EXPECT_EQ(a.group, "");
  EXPECT_FALSE(a.useOnly);
  EXPECT_EQ(a.kind, "");
  const EquipmentSpec& b = s.equipment[1];
  EXPECT_EQ(b.name, "b#1");
  EXPECT_EQ(b.model, (dir() / "models" / "b.osgt").string());
  EXPECT_TRUE(b.hasZ);
  EXPECT_EQ(b.position, Eigen::Vector3d(30, 40, 5));
  // Viewer and method defaults as scene_file.h gives them.
  EXPECT_EQ(s.viewer.eyeHeight, 1.7);
  EXPECT_EQ(s.viewer.bodyHalfExtents, Eigen::Vector3d(0.25, 0.25, 0.9));
  EXPECT_EQ(s.viewer.maxStep, 0.3);
  EXPECT_EQ(s.viewer.maxSlopeDeg, 30.0);
  EXPECT_EQ(s.viewer.speed, 1.4);
  EXPECT_EQ(s.viewer.flyClearance, 2.0);
  EXPECT_EQ(s.method.volumes, VolumeMethod::Nested);
  EXPECT_FALSE(s.method.templateHierarchy);
  EXPECT_EQ(s.method.autoTree.degree, 8);
  EXPECT_EQ(s.method.autoTree.axis, SplitAxis::LongestSide);
  EXPECT_EQ(s.method.autoTree.point, SplitPoint::Median);
  EXPECT_EQ(s.method.fitter, ObbFitter::HullSearch);
}

TEST_F(SceneFile, EveryFieldIsRead) {
  Json j = base();
  j["origin"] = {550000.5, 4650000.25, 12.0};
  j["equipment"][0] = {{"name", "bench3/station7/mast"}, {"model", "./models/../a.obj"}, {"position", {1.0, 2.0}},
                       {"heading", 90}, {"pitch", -5.5}, {"roll", 3}, {"scale", 2.5}, {"group", "bench3/station7"},
                       {"use_only", true}, {"kind", "pole"}};
  j["equipment"][1]["group"] = "bench3";
  j["viewer"] = {{"eye_height", 1.6}, {"body_half_extents", {0.3, 0.2, 0.8}}, {"max_step", 0.25},
                 {"max_slope_deg", 35}, {"speed", 2}, {"fly_clearance", 3}};
  j["method"] = {{"volumes", "obb"}, {"hierarchy", "template"}, {"degree", 8}, {"split_axis", "splatter"},
                 {"split_point", "mean"}, {"fitter", "covariance"}};
  const SceneSpec s = parse(j);
  ASSERT_TRUE(s.origin.has_value());
  EXPECT_EQ(*s.origin, Eigen::Vector3d(550000.5, 4650000.25, 12.0));
  const EquipmentSpec& a = s.equipment[0];
  EXPECT_EQ(a.name, "bench3/station7/mast");
  EXPECT_EQ(a.model, (dir() / "a.obj").string());  // normalised
  EXPECT_EQ(a.headingDeg, 90.0);
  EXPECT_EQ(a.pitchDeg, -5.5);
  EXPECT_EQ(a.rollDeg, 3.0);
  EXPECT_EQ(a.scale, 2.5);
  EXPECT_EQ(a.group, "bench3/station7");
  EXPECT_TRUE(a.useOnly);
  EXPECT_EQ(a.kind, "pole");
  EXPECT_EQ(s.equipment[1].name, "bench3/b#1");  // "<group>/<model stem>#<index>"
  EXPECT_EQ(s.viewer.eyeHeight, 1.6);
  EXPECT_EQ(s.viewer.bodyHalfExtents, Eigen::Vector3d(0.3, 0.2, 0.8));
  EXPECT_EQ(s.viewer.maxStep, 0.25);
  EXPECT_EQ(s.viewer.maxSlopeDeg, 35.0);
  EXPECT_EQ(s.viewer.speed, 2.0);
  EXPECT_EQ(s.viewer.flyClearance, 3.0);
  EXPECT_EQ(s.method.volumes, VolumeMethod::Obb);
  EXPECT_TRUE(s.method.templateHierarchy);
  EXPECT_EQ(s.method.autoTree.degree, 8);
  EXPECT_EQ(s.method.autoTree.axis, SplitAxis::Splatter);
  EXPECT_EQ(s.method.autoTree.point, SplitPoint::Mean);
  EXPECT_EQ(s.method.fitter, ObbFitter::Covariance);
}

// "imagery": optional, resolved like the terrain, and it must exist (it is not opened here).
TEST_F(SceneFile, ImageryIsResolvedAndMustExist) {
  fs::create_directories(dir() / "imagery");
  writeText(dir() / "imagery" / "ortho.tif", "x");
  Json j = base();
  j["imagery"] = "imagery/../imagery/ortho.tif";
  EXPECT_EQ(parse(j).imagery, std::optional<std::string>((dir() / "imagery" / "ortho.tif").string()));
  j["imagery"] = (dir() / "imagery" / "ortho.tif").string();
  EXPECT_EQ(parse(j).imagery, std::optional<std::string>((dir() / "imagery" / "ortho.tif").string()));
  // From disk, relative to the scene file's folder wherever the program runs.
  j["imagery"] = "imagery/ortho.tif";
  writeText(dir() / "scene.json", j.dump());
  EXPECT_EQ(readSceneFile(scenePath()).imagery, std::optional<std::string>((dir() / "imagery" / "ortho.tif").string()));
  // Bad values and a missing file: the scene file, the field and the problem.
  j["imagery"] = "gone.tif";
  EXPECT_EQ(error(j), "imagery: file not found: " + (dir() / "gone.tif").string());
  j["imagery"] = "imagery";
  EXPECT_EQ(error(j), "imagery: file not found: " + (dir() / "imagery").string()) << "a folder is no imagery file";
  j["imagery"] = 3;
  EXPECT_EQ(error(j), "imagery: expected a string, got number");
  j["imagery"] = "";
  EXPECT_EQ(error(j), "imagery: must not be empty");
}

TEST_F(SceneFile, ShadingDefaultsToHillshadeOnlyWithoutImagery) {
  fs::create_directories(dir() / "imagery");
  writeText(dir() / "imagery" / "ortho.tif", "x");
  Json j = base();
  EXPECT_FALSE(parse(j).hillshade.has_value());
  EXPECT_TRUE(parse(j).hillshadeOn()) << "no imagery: the height ramp is hillshaded";
  j["imagery"] = "imagery/ortho.tif";
  EXPECT_FALSE(parse(j).hillshadeOn()) << "an orthophoto carries its own shadows";
  j["shading"] = "hillshade";
  EXPECT_TRUE(parse(j).hillshadeOn());
  j.erase("imagery");
  j["shading"] = "none";
  EXPECT_FALSE(parse(j).hillshadeOn());
}

TEST_F(SceneFile, AbsolutePathsAreKeptAndEquipmentIsOptional) {
  Json j{{"terrain", (dir() / "terrain.tif").string()}};
  const SceneSpec s = parse(j);
  EXPECT_EQ(s.terrain, (dir() / "terrain.tif").string());
  EXPECT_TRUE(s.equipment.empty());
}

TEST_F(SceneFile, ReadFromDiskResolvesAgainstTheSceneFolder) {
  writeText(dir() / "scene.json", base().dump());
  const SceneSpec s = readSceneFile(scenePath());
  EXPECT_EQ(s.equipment[1].model, (dir() / "models" / "b.osgt").string());
  EXPECT_EQ(inputError([&] { readSceneFile((dir() / "none.json").string()); }),
            (dir() / "none.json").string() + ": scene file not found");
  EXPECT_EQ(inputError([&] { readSceneFile((dir() / "models").string()); }),
            (dir() / "models").string() + ": is a folder, not a scene file");
}

// One bad field at a time: the message names the field path and the problem.
TEST_F(SceneFile, BadFieldsAreNamed) {
  struct Case {
    std::function<void(Json&)> edit;
    std::string message;
  };
  const std::vector<Case> cases = {
      {[](Json& j) { j["terain"] = "x"; },
       "terain: unknown key (expected one of: terrain, imagery, shading, origin, types, equipment, viewer, method, source)"},
      {[](Json& j) { j.erase("terrain"); }, "terrain: missing (the terrain file is required)"},
      {[](Json& j) { j["terrain"] = 3; }, "terrain: expected a string, got number"},
      {[](Json& j) { j["terrain"] = ""; }, "terrain: must not be empty"},
      {[](Json& j) { j["origin"] = {1, 2}; }, "origin: expected 3 numbers, got 2"},
      {[](Json& j) { j["origin"] = {1, "2", 3}; }, "origin[1]: expected a number, got string"},
      {[](Json& j) { j["equipment"] = Json::object(); }, "equipment: expected an array, got object"},
      {[](Json& j) { j["equipment"][1] = 5; }, "equipment[1]: expected an object, got number"},
      {[](Json& j) { j["equipment"][1]["scale"] = 0; }, "equipment[1].scale: must be > 0"},
      {[](Json& j) { j["equipment"][1]["scale"] = -2; }, "equipment[1].scale: must be > 0"},
      {[](Json& j) { j["equipment"][0]["scale"] = "2"; }, "equipment[0].scale: expected a number, got string"},
      {[](Json& j) { j["equipment"][0]["heading"] = true; }, "equipment[0].heading: expected a number, got boolean"},
      {[](Json& j) { j["equipment"][0]["pitch"] = nullptr; }, "equipment[0].pitch: expected a number, got null"},
      {[](Json& j) { j["equipment"][0]["roll"] = {1}; }, "equipment[0].roll: expected a number, got array"},
      {[](Json& j) { j["equipment"][0]["colour"] = "red"; },
       "equipment[0].colour: unknown key (expected one of: name, model, type, position, heading, pitch, roll, scale, "
       "group, use_only, kind)"},
      {[](Json& j) { j["equipment"][0].erase("model"); }, "equipment[0].model: missing (a model file or a type is required)"},
      {[](Json& j) { j["equipment"][0]["model"] = ""; }, "equipment[0].model: must not be empty"},
      {[](Json& j) { j["equipment"][0].erase("position"); },
       "equipment[0].position: missing (map coordinates [x, y] or [x, y, z])"},
      {[](Json& j) { j["equipment"][0]["position"] = {1}; }, "equipment[0].position: expected 2 or 3 numbers, got 1"},
      {[](Json& j) { j["equipment"][0]["position"] = {1, 2, 3, 4}; },
       "equipment[0].position: expected 2 or 3 numbers, got 4"},
      {[](Json& j) { j["equipment"][0]["position"] = "here"; },
       "equipment[0].position: expected an array of 2 or 3 numbers, got string"},
      {[](Json& j) { j["equipment"][1]["position"] = {1, 2, "z"}; },
       "equipment[1].position[2]: expected a number, got string"},
      {[](Json& j) { j["equipment"][0]["group"] = "/bench3"; },
       "equipment[0].group: '/bench3' has an empty component (no leading, trailing or doubled '/')"},
      {[](Json& j) { j["equipment"][0]["group"] = "bench3//s7"; },
       "equipment[0].group: 'bench3//s7' has an empty component (no leading, trailing or doubled '/')"},
      {[](Json& j) { j["equipment"][0]["group"] = "bench3/"; },
       "equipment[0].group: 'bench3/' has an empty component (no leading, trailing or doubled '/')"},
      {[](Json& j) { j["equipment"][0]["use_only"] = "yes"; },
       "equipment[0].use_only: expected true or false, got string"},
      {[](Json& j) { j["equipment"][0]["use_only"] = true; },
       "equipment[0].use_only: a use_only instance needs a group (its volume is its group's)"},
      {[](Json& j) { j["equipment"][0]["name"] = ""; }, "equipment[0].name: must not be empty"},
      {[](Json& j) { j["equipment"][0]["kind"] = 3; }, "equipment[0].kind: expected a string, got number"},
      {[](Json& j) {
         j["equipment"][0]["name"] = "mast";
         j["equipment"][1]["name"] = "mast";
       },
       "equipment[1].name: name 'mast' is already the name of equipment[0]"},
      {[](Json& j) { j["equipment"][0]["name"] = "b#1"; },
       "equipment[1]: default name 'b#1' is already the name of equipment[0]"},
      {[](Json& j) {
         j["equipment"][0]["name"] = "bench3";
         j["equipment"][1]["group"] = "bench3";
         j["equipment"][1]["use_only"] = true;
       },
       "equipment[0].name: 'bench3' is also the name of the unit formed by group 'bench3''s use_only members (e.g. "
       "equipment[1])"},
      {[](Json& j) { j["viewer"] = {{"max_slope_deg", "30"}}; },
       "viewer.max_slope_deg: expected a number, got string"},
      {[](Json& j) { j["viewer"] = {{"max_slope_deg", 90}}; }, "viewer.max_slope_deg: must be > 0 and < 90 degrees"},
      {[](Json& j) { j["viewer"] = {{"eye_hieght", 1.7}}; },
       "viewer.eye_hieght: unknown key (expected one of: eye_height, body_half_extents, max_step, max_slope_deg, "
       "speed, fly_clearance)"},
      {[](Json& j) { j["viewer"] = {{"eye_height", 0}}; }, "viewer.eye_height: must be > 0"},
      {[](Json& j) { j["viewer"] = {{"body_half_extents", {0.3, 0, 0.9}}}; },
       "viewer.body_half_extents[1]: must be > 0"},
      {[](Json& j) { j["viewer"] = {{"body_half_extents", {0.3, 0.9}}}; },
       "viewer.body_half_extents: expected 3 numbers, got 2"},
      {[](Json& j) { j["viewer"] = {{"max_step", -0.1}}; }, "viewer.max_step: must be >= 0"},
      {[](Json& j) { j["viewer"] = {{"speed", 0}}; }, "viewer.speed: must be > 0"},
      {[](Json& j) { j["viewer"] = {{"fly_clearance", -1}}; }, "viewer.fly_clearance: must be >= 0"},
      {[](Json& j) { j["viewer"] = 1.7; }, "viewer: expected an object, got number"},
      {[](Json& j) { j["method"] = {{"volumes", "mesh"}}; }, "method.volumes: expected nested, aabb, obb, nested+mesh, kdop18 or auto, got 'mesh'"},
      {[](Json& j) { j["method"] = {{"hierarchy", "tree"}}; },
       "method.hierarchy: expected auto or template, got 'tree'"},
      {[](Json& j) { j["method"] = {{"degree", 3}}; }, "method.degree: expected 2, 4 or 8, got 3"},
      {[](Json& j) { j["method"] = {{"degree", 4.5}}; }, "method.degree: expected 2, 4 or 8, got 4.5"},
      {[](Json& j) { j["method"] = {{"split_axis", "shortest"}}; },
       "method.split_axis: expected longest or splatter, got 'shortest'"},
      {[](Json& j) { j["method"] = {{"split_point", "mode"}}; },
       "method.split_point: expected mean or median, got 'mode'"},
      {[](Json& j) { j["method"] = {{"fitter", "pca"}}; },
       "method.fitter: expected hull-search or covariance, got 'pca'"},
      {[](Json& j) { j["method"] = {{"fittr", "pca"}}; },
       "method.fittr: unknown key (expected one of: volumes, hierarchy, degree, split_axis, split_point, fitter)"},
      {[](Json& j) { j["shading"] = "flat"; }, "shading: expected hillshade or none, got 'flat'"},
      {[](Json& j) { j["shading"] = 1; }, "shading: expected a string, got number"},
      {[](Json& j) { j["terrain"] = "none.tif"; }, "terrain: file not found: "},  // path appended below
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    Json j = base();
    cases[i].edit(j);
    std::string want = cases[i].message;
    if (want == "terrain: file not found: ") want += (dir() / "none.tif").string();
    EXPECT_EQ(error(j), want) << "case " << i;
  }
}

TEST_F(SceneFile, NotAnObjectOrNotJson) {
  EXPECT_EQ(errorOfText("[1, 2]"), "expected an object, got array");
  const std::string e = errorOfText("{\n  \"terrain\": \"terrain.tif\",\n  \"equipment\": [\n}\n");
  EXPECT_EQ(e.rfind("not valid JSON: parse error at line 4, column 1: ", 0), 0u) << e;
}

TEST_F(SceneFile, DuplicateKeysAreErrors) {
  // nlohmann_json would keep the last value silently; a repeated key is a typo or a merge slip.
  EXPECT_EQ(errorOfText(R"({"terrain": "terrain.tif", "terrain": "terrain.tif"})"), "terrain: duplicate key");
  EXPECT_EQ(errorOfText(R"({"terrain": "terrain.tif", "equipment": [
      {"model": "a.obj", "position": [1, 2]},
      {"model": "a.obj", "position": [[3], 4], "scale": 1, "scale": 2}]})"),
            "equipment[1].scale: duplicate key");
  EXPECT_EQ(errorOfText(R"({"terrain": "terrain.tif", "viewer": {"speed": 1, "speed": 2}})"),
            "viewer.speed: duplicate key");
  // The same key in different objects is fine.
  EXPECT_NO_THROW(parseSceneJson(R"({"terrain": "terrain.tif", "equipment": [
      {"model": "a.obj", "position": [1, 2], "scale": 1}, {"model": "a.obj", "position": [1, 2], "scale": 2}]})",
                                 scenePath()));
}

TEST_F(SceneFile, MissingModelsAreListedInOneError) {
  Json j = base();
  j["equipment"].push_back({{"model", "gone1.osgb"}, {"position", {1, 2}}});
  j["equipment"].push_back({{"model", "models/gone2.obj"}, {"position", {1, 2}}});
  j["equipment"].push_back({{"model", "gone1.osgb"}, {"position", {3, 4}}});  // listed once
  j["equipment"].push_back({{"model", "models"}, {"position", {3, 4}}});      // a folder is no model file
  EXPECT_EQ(error(j), "3 model files not found: equipment[2].model: " + (dir() / "gone1.osgb").string() +
                          "; equipment[3].model: " + (dir() / "models" / "gone2.obj").string() +
                          "; equipment[5].model: " + (dir() / "models").string());
}

TEST(SceneMethod, Describe) {
  MethodSpec m;
  EXPECT_EQ(describe(m), "nested, auto delta=8 longest/median, hull-search");
  m.volumes = VolumeMethod::Aabb;
  m.templateHierarchy = true;
  m.fitter = ObbFitter::Covariance;
  EXPECT_EQ(describe(m), "aabb, template, covariance");
  EXPECT_STREQ(volumeMethodName(VolumeMethod::Obb), "obb");
}

}  // namespace
}  // namespace nestwalk
