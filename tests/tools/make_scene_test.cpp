// `nestwalk make-scene`: writes the scene folder (terrain, orthophoto, models, scene.json, scripts),
// refuses an existing folder without --overwrite and leaves it as it was, and replaces it with
// --overwrite. The orthophoto lies on the terrain's grid and shows the right materials where the
// scene's own scripts and the terrain's slopes say what is there: the patrol's lane on a berm, the
// ramp descent's start on the top and its end on the ramp, the steep samples on faces.
#include "nestwalk/terrain/dem_reader.h"
#include "tests/common/run_command.h"
#include "tests/tools/ortho_material.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>

namespace nestwalk::test {
namespace {

namespace fs = std::filesystem;

TEST(MakeScene, WritesTheSceneAndKeepsAnExistingFolder) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const fs::path out = dir / "dump";
  const auto r = runNestwalk("make-scene " + quoted(out) + " --seed 3");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  for (const char* f : {"terrain.tif", "ortho.tif", "scene.json", "scripts/bench_patrol.txt", "scripts/ramp_descent.txt",
                        "scripts/low_flight.txt", "scripts/equipment_walk.txt", "scripts/equipment_fly.txt",
                        "models/sensor_pole.osgt", "models/weather_station.osgt"})
    EXPECT_TRUE(fs::is_regular_file(out / f)) << f;
  const auto scene = nlohmann::json::parse(readText(out / "scene.json"));
  EXPECT_EQ(scene["terrain"], "terrain.tif");
  EXPECT_EQ(scene["imagery"], "ortho.tif");
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

/// The "start X Y" (or, with `keyword` "goto", the first "goto X Y") of a script.
std::array<double, 2> scriptPoint(const fs::path& script, const std::string& keyword) {
  const std::string text = readText(script);
  const auto at = text.find("\n" + keyword + " ");
  std::array<double, 2> p{NAN, NAN};
  if (at == std::string::npos) {
    ADD_FAILURE() << script << " has no " << keyword;
    return p;
  }
  EXPECT_EQ(std::sscanf(text.c_str() + at + 1 + keyword.size(), "%lf %lf", &p[0], &p[1]), 2) << script;
  return p;
}

/// Degrees: a sample whose slope (central differences over 2 m) is at least this lies on a face,
/// a ramp's side slope or a pit's wall (the generator's 35-degree slopes; nothing else is steeper than
/// a few degrees).
constexpr double kSteepDeg = 30.0;

TEST(MakeScene, TheOrthophotoShowsTheMaterialsWhereTheSceneHasThem) {
  const TempFolder folder;
  const fs::path out = folder / "dump";
  const auto r = runNestwalk("make-scene " + quoted(out) + " --seed 3");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("ortho.tif"), std::string::npos) << r.out;
  const OrthoProbe probe(out / "ortho.tif");
  probe.expectOnTheGridOf(out / "terrain.tif");

  const auto patrol = scriptPoint(out / "scripts" / "bench_patrol.txt", "start");
  EXPECT_EQ(probe.materialAt(patrol[0], patrol[1]), "berm") << "the patrol walks a berm's lane";
  const auto rampTop = scriptPoint(out / "scripts" / "ramp_descent.txt", "start");
  EXPECT_EQ(probe.materialAt(rampTop[0], rampTop[1]), "top") << "the descent starts on the top";
  const auto rampToe = scriptPoint(out / "scripts" / "ramp_descent.txt", "goto");
  EXPECT_EQ(probe.materialAt(rampToe[0], rampToe[1]), "ramp") << "and ends on the ramp";

  // Every steep sample of the terrain away from where slopes end shows a steep material, most of them
  // a bench face.
  const terrain::Heightfield hf = terrain::readDem((out / "terrain.tif").string());
  auto slopeDeg = [&](int c, int r) {
    const double gx = (hf.sample(c + 1, r) - hf.sample(c - 1, r)) / (2 * hf.dx()),
                 gy = (hf.sample(c, r - 1) - hf.sample(c, r + 1)) / (2 * hf.dy());
    return std::atan(std::hypot(gx, gy)) * 180.0 / std::numbers::pi;
  };
  std::map<std::string, int> steep;
  int total = 0;
  for (int r = 2; r < hf.rows() - 2; r += 3)
    for (int c = 2; c < hf.cols() - 2; c += 3) {
      bool allSteep = true;
      for (int dr = -1; dr <= 1 && allSteep; ++dr)
        for (int dc = -1; dc <= 1 && allSteep; ++dc) allSteep = slopeDeg(c + dc, r + dr) >= kSteepDeg;
      if (!allSteep) continue;
      ++total;
      ++steep[probe.materialAt(hf.origin().x() + c * hf.dx(), hf.origin().y() - r * hf.dy())];
    }
  for (const auto& [material, count] : steep) std::printf("[ ortho    ] steep samples shown as %s: %d\n", material.c_str(), count);
  ASSERT_GT(total, 1000);
  EXPECT_EQ(steep["face"] + steep["ramp side"] + steep["pit"], total) << "a steep sample shows a steep material";
  EXPECT_GT(steep["face"], 0.8 * total) << "most steep ground is bench faces";
}

TEST(MakeScene, OrthoPixelWritesADronesOrthophotoOverTheTerrainAndACoarserOneIsRefused) {
  const TempFolder folder;
  const fs::path out = folder / "dump";
  const auto r = runNestwalk("make-scene " + quoted(out) + " --seed 3 --ortho-pixel 0.25");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("ortho.tif, a drone's synthetic orthophoto at 0.25 m"), std::string::npos) << r.out;
  // Through GDAL: the terrain's outer bounds at 0.25 m pixels (4 a terrain cell), with overviews.
  const OrthoProbe probe(out / "ortho.tif");
  GDALDatasetH dem = GDALOpen((out / "terrain.tif").c_str(), GA_ReadOnly);
  ASSERT_NE(dem, nullptr);
  double d[6], o[6];
  GDALGetGeoTransform(dem, d);
  GDALGetGeoTransform(probe.dataset(), o);
  const int demCols = GDALGetRasterXSize(dem), demRows = GDALGetRasterYSize(dem);
  GDALClose(dem);
  EXPECT_DOUBLE_EQ(o[1], 0.25);
  EXPECT_DOUBLE_EQ(o[5], -0.25);
  // The orthophoto's pixels tile the DEM raster's extent.
  EXPECT_DOUBLE_EQ(o[0], d[0]);
  EXPECT_DOUBLE_EQ(o[3], d[3]);
  EXPECT_NEAR(GDALGetRasterXSize(probe.dataset()) * o[1], demCols * d[1], 1e-6);
  EXPECT_NEAR(GDALGetRasterYSize(probe.dataset()) * -o[5], demRows * -d[5], 1e-6);
  EXPECT_GT(GDALGetOverviewCount(GDALGetRasterBand(probe.dataset(), 1)), 2);

  const fs::path coarse = folder / "coarse";
  const auto refused = runNestwalk("make-scene " + quoted(coarse) + " --ortho-pixel 2");
  EXPECT_EQ(refused.exitCode, 1);
  EXPECT_NE(refused.err.find("an orthophoto pixel of 2 m is coarser than the terrain's 1 m cell"), std::string::npos)
      << refused.err;
  EXPECT_FALSE(fs::exists(coarse));
}

}  // namespace
}  // namespace nestwalk::test
