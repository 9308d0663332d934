// `nestwalk make-scene`: writes the scene folder (terrain, models, scene.json, scripts), refuses an
// existing folder without --overwrite and leaves it as it was, and replaces it with --overwrite.
#include "tests/common/run_command.h"

#include <nlohmann/json.hpp>

#include <filesystem>

namespace nestwalk::test {
namespace {

namespace fs = std::filesystem;

TEST(MakeScene, WritesTheSceneAndKeepsAnExistingFolder) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const fs::path out = dir / "dump";
  const auto r = runNestwalk("make-scene " + quoted(out) + " --seed 3");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  for (const char* f : {"terrain.tif", "scene.json", "scripts/bench_patrol.txt", "scripts/ramp_descent.txt",
                        "scripts/low_flight.txt", "scripts/equipment_walk.txt", "scripts/equipment_fly.txt",
                        "models/sensor_pole.osgt", "models/weather_station.osgt"})
    EXPECT_TRUE(fs::is_regular_file(out / f)) << f;
  const auto scene = nlohmann::json::parse(readText(out / "scene.json"));
  EXPECT_EQ(scene["terrain"], "terrain.tif");
  EXPECT_GE(scene["equipment"].size(), 200u);
  for (const auto& e : scene["equipment"]) EXPECT_TRUE(fs::is_regular_file(out / e["model"].get<std::string>()));
  const std::string before = readText(out / "scene.json");

  // Without --overwrite: exit 1, the folder untouched (even with another seed).
  const auto again = runNestwalk("make-scene " + quoted(out) + " --seed 4");
  EXPECT_EQ(again.exitCode, 1);
  EXPECT_NE(again.err.find("already exists"), std::string::npos) << again.err;
  EXPECT_NE(again.err.find(out.string()), std::string::npos) << again.err;
  EXPECT_EQ(readText(out / "scene.json"), before);

  // With --overwrite: replaced, nothing left beside it.
  const auto over = runNestwalk("make-scene " + quoted(out) + " --seed 4 --overwrite");
  ASSERT_EQ(over.exitCode, 0) << over.err;
  EXPECT_NE(readText(out / "scene.json"), before);
  int entries = 0;
  for (const auto& f : fs::directory_iterator(dir)) entries += f.path().filename() != "capture";
  EXPECT_EQ(entries, 1);
}

}  // namespace
}  // namespace nestwalk::test
