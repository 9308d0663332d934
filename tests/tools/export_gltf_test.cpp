// `nestwalk export SCENE OUT.glb|.gltf` on the bundled mining-dump scene: the Khronos validator
// finds no error; at a 1-pixel error of a 1280 x 720 view from 500 m the GLB holds at most 25 MB;
// the asset's extras give the scene's map origin and CRS; every instance is a node named after it
// whose matrix is the scene's own placement (Scene::instances, loaded here), and the equipment read
// back by nestwalk's glTF reader has the scene's triangle count; each model's meshes are written
// once, however many instances it has. OUT is replaced only with --overwrite.
#include "nestwalk/render/view_options.h"
#include "nestwalk/scene/gltf_model.h"
#include "nestwalk/scene/node_geometry.h"
#include "nestwalk/scene/scene_loader.h"
#include "tests/common/gltf_validator.h"
#include "tests/common/run_command.h"
#include "tests/common/temp_folder.h"
#include "tests/common/test_data.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <set>

namespace nestwalk::test {
namespace {

namespace fs = std::filesystem;

/// The size budget: the bundled scene's GLB at one pixel's error of a 1280 x 720 view (the
/// renderer's vertical field of view) from 500 m.
constexpr double kViewDistanceM = 500.0;
constexpr int kViewHeightPx = 720;
constexpr std::uintmax_t kMaxGlbBytes = 25'000'000;

double onePixelAt500m() {
  const double fovY = RenderOptions{}.fovYDegrees * M_PI / 180.0;
  return kViewDistanceM * 2.0 * std::tan(fovY / 2.0) / kViewHeightPx;
}

std::string readAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(ExportGltf, BundledSceneIsValidSmallAndOnTheMap) {
  if (!fs::exists(bundledSceneFile())) GTEST_SKIP() << "build the bundled_scene target";
  const TempFolder dir;
  const fs::path out = dir / "dump.glb";
  const std::string error = std::to_string(onePixelAt500m());
  const CommandResult r =
      runNestwalk("export " + quoted(bundledSceneFile()) + " " + quoted(out) + " --volumes --max-error " + error);
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  std::printf("%s", r.out.c_str());
  EXPECT_NE(r.out.find("glTF: "), std::string::npos) << r.out;
  const std::uintmax_t bytes = fs::file_size(out);
  std::printf("bundled scene at %s m error: %.2f MB\n", error.c_str(), bytes / 1e6);
  EXPECT_LE(bytes, kMaxGlbBytes);

  const nlohmann::json report = validateGltf(out);
  ASSERT_FALSE(report.is_null());
  EXPECT_EQ(report["errors"], 0) << report.dump(1);
  std::printf("validator: %d errors, %d warnings, %d infos\n", report["errors"].get<int>(),
              report["warnings"].get<int>(), report["infos"].get<int>());

  const Scene scene = loadScene(bundledSceneFile().string());
  const nlohmann::json doc = glbJson(readAll(out));
  const nlohmann::json& extras = doc["asset"]["extras"]["nestwalk"];
  EXPECT_EQ(extras["map_origin"], nlohmann::json({scene.origin.x(), scene.origin.y(), scene.origin.z()}));
  EXPECT_EQ(extras["crs"], scene.terrain->crsWkt());
  EXPECT_FALSE(extras["crs_name"].get<std::string>().empty());
}

TEST(ExportGltf, EveryInstanceIsANodeAtItsPlacementOverItsModelsMeshes) {
  if (!fs::exists(bundledSceneFile())) GTEST_SKIP() << "build the bundled_scene target";
  const TempFolder dir;
  const fs::path out = dir / "equipment.glb";
  const CommandResult r = runNestwalk("export " + quoted(bundledSceneFile()) + " " + quoted(out) + " --no-terrain");
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const Scene scene = loadScene(bundledSceneFile().string());
  const nlohmann::json doc = glbJson(readAll(out));

  std::map<std::string, const nlohmann::json*> byName;
  for (const auto& n : doc["nodes"])
    if (n.contains("name")) byName[n["name"].get<std::string>()] = &n;
  std::size_t triangles = 0;
  std::set<int> meshesUsed;
  for (const SceneInstance& inst : scene.instances) {
    const std::string& name = scene.spec.equipment[inst.spec].name;
    SCOPED_TRACE(name);
    ASSERT_TRUE(byName.count(name));
    const nlohmann::json& node = *byName[name];
    ASSERT_TRUE(node.contains("matrix"));
    const Similarity<double>& t = inst.toLocal;
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(node["matrix"][4 * c + k].get<double>(), t.scale * t.rotation(k, c), 1e-12);  // column-major
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(node["matrix"][12 + k].get<double>(), t.translation[k], 1e-9);
    triangles += scene.models[inst.model].mesh.triangles.size();
    std::vector<const nlohmann::json*> stack = {&node};
    while (!stack.empty()) {
      const nlohmann::json& n = *stack.back();
      stack.pop_back();
      if (n.contains("mesh")) meshesUsed.insert(n["mesh"].get<int>());
      if (n.contains("children"))
        for (const auto& c : n["children"]) stack.push_back(&doc["nodes"][c.get<std::size_t>()]);
    }
  }
  // Each model's meshes once: no more meshes than models' geodes, far fewer than instances.
  EXPECT_EQ(meshesUsed.size(), doc["meshes"].size());
  EXPECT_LT(doc["meshes"].size(), scene.instances.size() / 10);
  std::printf("%zu instances of %zu models: %zu glTF meshes\n", scene.instances.size(), scene.models.size(),
              doc["meshes"].size());

  const GltfModel back = readGltfModel(out.string());
  ASSERT_TRUE(back.node) << back.problem;
  EXPECT_EQ(collectModelGeometry(*back.node, out.string()).triangles.size(), triangles);
}

TEST(ExportGltf, TextFormValidatesAndAnExistingFileIsKept) {
  if (!fs::exists(bundledSceneFile())) GTEST_SKIP() << "build the bundled_scene target";
  const TempFolder dir;
  const fs::path out = dir / "dump.gltf";
  const std::string args = "export " + quoted(bundledSceneFile()) + " " + quoted(out) + " --no-terrain";
  ASSERT_EQ(runNestwalk(args).exitCode, 0);
  const nlohmann::json report = validateGltf(out);
  ASSERT_FALSE(report.is_null());
  EXPECT_EQ(report["errors"], 0) << report.dump(1);
  const std::string before = readAll(out);
  const CommandResult again = runNestwalk(args);
  EXPECT_EQ(again.exitCode, 1);
  EXPECT_NE(again.err.find(out.string() + ": exists; pass --overwrite to replace it"), std::string::npos) << again.err;
  EXPECT_EQ(readAll(out), before);
  EXPECT_EQ(runNestwalk(args + " --overwrite").exitCode, 0);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"dump.gltf"});  // no temporary file left behind
}

}  // namespace
}  // namespace nestwalk::test
