// `nestwalk bench models --quick --json`: the model-read benchmark runs on the bundled models and
// reports, per model, the three reads it times (direct, guarded first read, guarded from the
// cache) with their ratios as the stated quotients, and its targets (the guard's, and glTF copies
// against their OBJ originals). Times are not asserted.
#include "tests/common/run_command.h"
#include "tests/common/test_data.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>

namespace nestwalk::test {
namespace {

TEST(BenchModels, QuickJsonRunReportsEveryReadKind) {
  if (!std::filesystem::exists(bundledSceneFile())) GTEST_SKIP() << "build the bundled_scene target";
  const CommandResult r = runNestwalk("bench models --quick --json");
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_GE(j["models"].size(), 8u);  // the bundled scene's eight at least
  for (const auto& m : j["models"]) {
    SCOPED_TRACE(m["model"].get<std::string>());
    EXPECT_GT(m["triangles"].get<long>(), 0);
    for (const char* k : {"direct", "first", "cached"}) EXPECT_GT(m["ms"][k].get<double>(), 0.0) << k;
    EXPECT_DOUBLE_EQ(m["ratio"]["first"].get<double>(), m["ms"]["first"].get<double>() / m["ms"]["direct"].get<double>());
    EXPECT_DOUBLE_EQ(m["ratio"]["cached"].get<double>(),
                     m["ms"]["cached"].get<double>() / m["ms"]["direct"].get<double>());
  }
  // Two targets: the guard's cost on the models OSG's plugins read, and the glTF copies' reads
  // against their OBJ originals (assimp, which writes the copies, is installed with the rest).
  ASSERT_EQ(j["targets"].size(), 2u) << r.out;
  double worstCached = 0, worstGltf = 0;
  std::map<std::string, double> objDirect;
  for (const auto& m : j["models"])
    if (m["format"] == "obj") objDirect[std::filesystem::path(m["model"].get<std::string>()).stem().string()] = m["ms"]["direct"];
  for (const auto& m : j["models"]) {
    if (m["format"] != "glb") {
      worstCached = std::max(worstCached, m["ratio"]["cached"].get<double>());
      continue;
    }
    const std::string stem = std::filesystem::path(m["model"].get<std::string>()).stem().string();
    ASSERT_TRUE(objDirect.count(stem)) << stem << ": a glTF copy without its OBJ";
    worstGltf = std::max(worstGltf, m["ms"]["direct"].get<double>() / objDirect[stem]);
  }
  EXPECT_DOUBLE_EQ(j["targets"][0]["value"].get<double>(), worstCached);
  EXPECT_DOUBLE_EQ(j["targets"][1]["value"].get<double>(), worstGltf);
  EXPECT_EQ(objDirect.size(), 1u + (std::filesystem::exists(sharedData() / "models/excavator_chassis.obj") ? 1u : 0u));
}

}  // namespace
}  // namespace nestwalk::test
