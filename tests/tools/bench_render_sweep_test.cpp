// `nestwalk bench render --terrain-sizes --quick --json`: a smoke run of the terrain-size sweep
// (tools/bench/render_terrain_sweep.h) a user runs, offscreen without a display, into a DEM cache
// of the test's own. Times are not asserted; what it checks is what the sweep promises: every size
// measured, on the generator's sample count, every pose rendered once, p50 <= p95, a peak resident
// memory that does not shrink as the terrain grows, a first frame that took time, ratios that are
// the ratios of the values shown, the targets computed from the largest size's row, and a second
// run that reuses the cached DEM. Bad sizes and a bad cache folder are input errors naming their
// option.
#include "tests/common/run_command.h"
#include "tests/common/temp_folder.h"
#include "tests/common/test_data.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace nestwalk::test {
namespace {

/// --quick's sizes (metres) and the generator's cell (metres): samples = (size / cell)^2.
const std::vector<double> kQuickSizesM = {250.0, 500.0};
constexpr double kCellM = 1.0;
/// --quick's poses: 8 sampled frames per bundled flythrough, 5 flythroughs.
constexpr long kQuickPoses = 8 * 5;
/// How far the peak resident memory of a larger size may fall below a smaller one's, MiB: the
/// quick sizes' terrains differ by about 1 MiB of heights, less than the run-to-run variation of
/// the allocator, the GL driver's threads and the loader's timing; a peak that fell by more would
/// mean the memory is not the size's own run.
constexpr double kRssNoiseMiB = 32.0;

TEST(BenchRenderSweep, QuickJsonRunMeasuresEverySize) {
  if (!std::filesystem::exists(test::bundledSceneFile()))
    GTEST_SKIP() << "the bundled scene is absent: build the bundled_scene target";
  const TempFolder cache("cache");
  const CommandResult r =
      runNestwalk("bench render --terrain-sizes --quick --json --terrain-cache " + quoted(cache.path()));
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["benchmark"], "render terrain sweep");
  EXPECT_EQ(j["route"], "egl-surfaceless");
  EXPECT_EQ(j["poses"].get<long>(), kQuickPoses);
  ASSERT_EQ(j["sizes"].size(), kQuickSizesM.size());
  const nlohmann::json& base = j["sizes"][0];
  double previousRss = 0;
  for (std::size_t i = 0; i < kQuickSizesM.size(); ++i) {
    SCOPED_TRACE("size " + std::to_string(kQuickSizesM[i]));
    const nlohmann::json& s = j["sizes"][i];
    EXPECT_EQ(s["size_m"].get<double>(), kQuickSizesM[i]);
    const double side = kQuickSizesM[i] / kCellM;
    EXPECT_EQ(s["samples"].get<double>(), side * side);
    EXPECT_TRUE(s["dem_generated"].get<bool>());
    EXPECT_TRUE(std::filesystem::exists(s["dem_file"].get<std::string>()));
    EXPECT_EQ(std::filesystem::path(s["dem_file"].get<std::string>()).parent_path(), cache.path());
    EXPECT_EQ(s["frames"].get<long>(), kQuickPoses);
    EXPECT_GT(s["first_frame_ms"].get<double>(), 0.0);
    EXPECT_GT(s["dem_load_s"].get<double>(), 0.0);
    EXPECT_LE(s["ms_p50"].get<double>(), s["ms_p95"].get<double>());
    EXPECT_GT(s["ms_p50"].get<double>(), 0.0);
    EXPECT_LE(s["frames_loading"].get<long>(), kQuickPoses);
    if (s["frames_loading"].get<long>() > 0)
      EXPECT_GE(s["worst_loading_ms"].get<double>(), 0.0);
    else
      EXPECT_TRUE(s["worst_loading_ms"].is_null());
    EXPECT_GE(s["chunks_resident_max"].get<long>(), 1);  // the root at least
    EXPECT_GT(s["resident_mib_max"].get<double>(), 0.0);
    EXPECT_DOUBLE_EQ(s["chunks_loaded_per_s"].get<double>(),
                     s["chunks_loaded"].get<double>() / s["run_s"].get<double>());
    EXPECT_GE(s["settled_error_px"].get<double>(), 0.0);
    EXPECT_GT(s["settled_ms_p50"].get<double>(), 0.0);
    EXPECT_GE(s["settle_s"].get<double>(), 0.0);
    // The first view settled after its first frame, and it did settle.
    EXPECT_GE(s["first_view_settled_s"].get<double>(), s["first_frame_ms"].get<double>() / 1000.0);
    EXPECT_TRUE(s["first_view_settled"].get<bool>());
    EXPECT_EQ(s["load_error"], "");
    const double rss = s["peak_rss_mib"].get<double>();
    EXPECT_GT(rss, 0.0);
    EXPECT_GE(rss, previousRss - kRssNoiseMiB);
    previousRss = rss;
    EXPECT_DOUBLE_EQ(s["ratio"]["p50"].get<double>(), s["ms_p50"].get<double>() / base["ms_p50"].get<double>());
    EXPECT_DOUBLE_EQ(s["ratio"]["p95"].get<double>(), s["ms_p95"].get<double>() / base["ms_p95"].get<double>());
  }
  EXPECT_DOUBLE_EQ(base["ratio"]["p50"].get<double>(), 1.0);
  // The targets: the largest size's p50 and p95 ratios, peak RSS, the scene's opening, first frame,
  // settling, the walker's step p99 and waits, and the settled view ratio.
  const nlohmann::json& big = j["sizes"].back();
  ASSERT_EQ(j["targets"].size(), 11u);
  EXPECT_DOUBLE_EQ(j["targets"][0]["value"].get<double>(), big["ratio"]["p50"].get<double>());
  EXPECT_DOUBLE_EQ(j["targets"][1]["value"].get<double>(), big["ratio"]["p95"].get<double>());
  EXPECT_DOUBLE_EQ(j["targets"][2]["value"].get<double>(), big["peak_rss_mib"].get<double>());
  EXPECT_DOUBLE_EQ(j["targets"][3]["value"].get<double>(), big["dem_load_s"].get<double>());
  // The import: a process of its own reading the DEM and writing a terrain and its pyramid.
  EXPECT_GT(big["import_s"].get<double>(), 0.0);
  EXPECT_GT(big["import_peak_mib"].get<double>(), 10.0);
  EXPECT_DOUBLE_EQ(big["import_msamples_per_s"].get<double>(),
                   big["samples"].get<double>() / 1e6 / big["import_s"].get<double>());
  EXPECT_DOUBLE_EQ(j["targets"][4]["value"].get<double>(), big["import_msamples_per_s"].get<double>());
  EXPECT_DOUBLE_EQ(j["targets"][5]["value"].get<double>(), big["import_peak_mib"].get<double>());
  EXPECT_DOUBLE_EQ(j["targets"][6]["value"].get<double>(), big["first_frame_ms"].get<double>());
  EXPECT_DOUBLE_EQ(j["targets"][7]["value"].get<double>(), big["first_view_settled_s"].get<double>());
  EXPECT_DOUBLE_EQ(j["targets"][8]["value"].get<double>(), big["walker_step_us_p99"].get<double>());
  EXPECT_DOUBLE_EQ(j["targets"][9]["value"].get<double>(), big["ground_waits"].get<double>());
  EXPECT_GT(big["walker_steps"].get<double>(), 100.0);
  EXPECT_DOUBLE_EQ(j["targets"][10]["value"].get<double>(),
                   big["settled_ms_p50"].get<double>() / j["sizes"][0]["settled_ms_p50"].get<double>());

  // Again with one of the sizes given: its DEM comes from the cache.
  const CommandResult again = runNestwalk("bench render --terrain-sizes 250 --quick --json --terrain-cache " +
                                          quoted(cache.path()));
  ASSERT_EQ(again.exitCode, 0) << again.out << again.err;
  const nlohmann::json k = nlohmann::json::parse(again.out);
  ASSERT_EQ(k["sizes"].size(), 1u);
  EXPECT_FALSE(k["sizes"][0]["dem_generated"].get<bool>());
  EXPECT_EQ(k["sizes"][0]["dem_file"], j["sizes"][0]["dem_file"]);
  // And its import's figures, measured once, from beside it.
  EXPECT_DOUBLE_EQ(k["sizes"][0]["import_s"].get<double>(), j["sizes"][0]["import_s"].get<double>());
}

TEST(BenchRenderSweep, TheFinerShapeMeasuresTheBundledDumpAtEachCellWithFineRelief) {
  if (!std::filesystem::exists(test::bundledSceneFile()))
    GTEST_SKIP() << "the bundled scene is absent: build the bundled_scene target";
  const TempFolder cache;
  const CommandResult r =
      runNestwalk("bench render --terrain-cells 8,16 --quick --json --terrain-cache " + quoted(cache.path()));
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["sizes"].size(), 2u);
  const double cells[] = {16, 8};  // coarse to fine
  for (std::size_t i = 0; i < 2; ++i) {
    const nlohmann::json& s = j["sizes"][i];
    EXPECT_EQ(s["size_m"].get<double>(), 1000.0);
    EXPECT_EQ(s["cell_m"].get<double>(), cells[i]);
    EXPECT_TRUE(s["fine_relief"].get<bool>());
    const double n = double(std::lround(1000.0 / cells[i]));
    EXPECT_EQ(s["samples"].get<double>(), n * n);
    EXPECT_TRUE(std::filesystem::exists(s["dem_file"].get<std::string>())) << s["dem_file"];
  }
  const CommandResult both = runNestwalk("bench render --terrain-cells 8 --terrain-sizes 250 --quick");
  EXPECT_EQ(both.exitCode, 1);
  EXPECT_NE(both.err.find("--terrain-cells"), std::string::npos) << both.err;
  const CommandResult tiny = runNestwalk("bench render --terrain-cells 100 --quick");
  EXPECT_EQ(tiny.exitCode, 1);
  EXPECT_NE(tiny.err.find("--terrain-cells"), std::string::npos) << tiny.err;
}

TEST(BenchRenderSweep, BadSizesAndCacheAreInputErrors) {
  if (!std::filesystem::exists(test::bundledSceneFile()))
    GTEST_SKIP() << "the bundled scene is absent: build the bundled_scene target";
  const TempFolder folder;
  const std::string cache = " --terrain-cache " + quoted(folder.path() / "cache");
  for (const char* sizes : {"8", "250,250", "250 abc", "70000"}) {
    SCOPED_TRACE(sizes);
    const CommandResult r = runNestwalk(std::string("bench render --terrain-sizes ") + sizes + cache);
    EXPECT_EQ(r.exitCode, 1) << r.out << r.err;
    EXPECT_NE(r.err.find("--terrain-sizes"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "cache"));  // refused before anything was made
  {
    std::ofstream(folder.path() / "file") << "not a folder";
  }
  const CommandResult r =
      runNestwalk("bench render --terrain-sizes 250 --terrain-cache " + quoted(folder.path() / "file"));
  EXPECT_EQ(r.exitCode, 1) << r.out << r.err;
  EXPECT_NE(r.err.find("--terrain-cache"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace nestwalk::test
