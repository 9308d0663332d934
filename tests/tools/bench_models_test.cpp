// `nestwalk bench models --quick --json`: the model-read benchmark runs on the bundled models and
// reports, per model, the three reads it times (direct, guarded first read, guarded from the
// cache) with their ratios as the stated quotients, and its target. Times are not asserted.
#include "tests/common/run_command.h"
#include "tests/common/test_data.h"

#include <nlohmann/json.hpp>

#include <filesystem>

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
  ASSERT_EQ(j["targets"].size(), 1u);
  double worst = 0;
  for (const auto& m : j["models"]) worst = std::max(worst, m["ratio"]["cached"].get<double>());
  EXPECT_DOUBLE_EQ(j["targets"][0]["value"].get<double>(), worst);
}

}  // namespace
}  // namespace nestwalk::test
