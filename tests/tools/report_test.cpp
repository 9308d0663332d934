// `nestwalk report` on the bundled mining-dump scene (generated at build time into
// build/assets/mining_dump) and on the heavy-model flythroughs (tools/data/make_heavy_scene.py,
// with the shared data), quick settings: the report's files are written, every method ran over
// every flythrough without a missed contact, nested+mesh has no false block and stops within 1 mm
// of the real geometry, the plots read back as PNGs, and existing files are kept unless --overwrite.
#include "tests/common/build_paths.h"
#include "tests/common/run_command.h"
#include "tests/common/test_data.h"

#include <gdal.h>
#include <nlohmann/json.hpp>
#include <ogr_api.h>
#include <osg/Image>
#include <osgDB/ReadFile>

#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>

namespace nestwalk::test {
namespace {

namespace fs = std::filesystem;

const fs::path kScene = fs::path(nestwalk::test::build::bundledSceneDir()) / "scene.json";
const char* const kMethods[] = {"nested", "aabb", "obb", "nested+mesh", "kdop18", "auto"};
// In name order, as the report lists them.
const char* const kScripts[] = {"bench_patrol.txt", "equipment_fly.txt", "equipment_walk.txt", "low_flight.txt",
                                "ramp_descent.txt"};

class Report : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(kScene)) GTEST_SKIP() << kScene << " is absent: build the bundled_scene target";
  }
};

TEST_F(Report, QuickReportOnTheBundledScene) {
  const TempFolder folder;
  const fs::path dir = folder / "report";
  const auto r = runNestwalk("report --quick --out " + quoted(dir));
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  for (const char* f : {"report.md", "report.json", "pareto.png", "methods.png", "terrain_lod.png", "model_weight.png",
                        "contacts.gpkg"})
    ASSERT_TRUE(fs::exists(dir / f)) << f << "\n" << r.out << r.err;

  const auto j = nlohmann::json::parse(readText(dir / "report.json"));
  ASSERT_EQ(j["methods"].size(), std::size(kMethods));
  for (std::size_t m = 0; m < std::size(kMethods); ++m) {
    const auto& method = j["methods"][m];
    SCOPED_TRACE(kMethods[m]);
    EXPECT_EQ(method["method"], kMethods[m]);
    // The outer AABBs alone cannot land where the equipment walk starts, beside a diagonal fence
    // (its use_only group's boxes cover the lane): that play is reported, not played.
    const bool aabb = method["method"] == "aabb";
    EXPECT_EQ(method["complete"].get<bool>(), !aabb);
    ASSERT_EQ(method["flythroughs"].size(), std::size(kScripts));
    for (std::size_t s = 0; s < std::size(kScripts); ++s) {
      const auto& play = method["flythroughs"][s];
      SCOPED_TRACE(kScripts[s]);
      EXPECT_EQ(play["script"], kScripts[s]);
      if (aabb && play["script"] == "equipment_walk.txt") {
        ASSERT_TRUE(play.contains("error"));
        EXPECT_NE(play["error"].get<std::string>().find("cannot land here"), std::string::npos) << play["error"];
        continue;
      }
      ASSERT_FALSE(play.contains("error")) << play["error"];
      EXPECT_GT(play["frames"].get<long>(), 10);
      EXPECT_GT(play["sweeps"].get<long>(), 0);
      EXPECT_EQ(play["missed"].get<long>(), 0);
      if (method["method"] == "nested+mesh" || method["method"] == "auto") {
        EXPECT_EQ(play["false_blocks"].get<long>(), 0);
        EXPECT_EQ(play["early_stops"].get<long>(), 0);
        if (play["stop_gap_mm"]["samples"].get<long>() > 0) {
          EXPECT_LE(play["stop_gap_mm"]["max"].get<double>(), 1.0);
          EXPECT_GT(play["stop_gap_mm"]["max"].get<double>(), 0.0);  // never inside
        }
      }
    }
    EXPECT_EQ(method["missed"].get<long>(), 0);
    EXPECT_GT(method["us_per_frame"]["p50"].get<double>(), 0.0);
  }
  // Exact methods: every step blocked by equipment on the bundled patrol stops within 1 mm.
  const auto& exact = j["methods"][3];
  EXPECT_GT(exact["stop_gap_mm"]["samples"].get<long>(), 0) << "nested+mesh was never blocked";

  // The blocking events under the figures: at least those the scripts expect (each "expect
  // blocked by" line, counted here from the scripts themselves), on at least 5 kinds.
  std::size_t expected = 0;
  for (const char* script : kScripts) {
    std::istringstream text(readText(fs::path(nestwalk::test::build::bundledSceneDir()) / "scripts" / script));
    for (std::string line; std::getline(text, line);) expected += line.rfind("expect blocked by ", 0) == 0;
  }
  EXPECT_GE(expected, 20u);
  std::size_t events = 0;
  for (const auto& kind : j["blocking_events"]) events += kind["events"].get<std::size_t>();
  EXPECT_GE(events, expected);
  EXPECT_GE(j["blocking_events"].size(), 5u);
  // Auto: the targets of its issue, against the exact reference.
  const auto& automatic = j["methods"][5];
  EXPECT_EQ(automatic["false_blocks"].get<long>(), 0);
  EXPECT_TRUE(automatic["early_stop_mm"]["max"].is_null() || automatic["early_stop_mm"]["max"].get<double>() <= 10.0);
  std::size_t units = 0;
  for (const auto& kind : j["auto"]["kinds"]) units += kind["units"].get<std::size_t>();
  EXPECT_EQ(units, j["units"].get<std::size_t>());
  // Cost by model weight: every played frame of a method falls in exactly one class.
  for (const auto& method : j["methods"]) {
    if (!method["complete"].get<bool>()) continue;
    std::size_t frames = 0, byWeight = 0;
    for (const auto& play : method["flythroughs"]) frames += play["frames"].get<std::size_t>();
    for (const auto& row : j["by_model_weight"])
      if (row["method"] == method["method"]) byWeight += row["frames"].get<std::size_t>();
    EXPECT_EQ(byWeight, frames) << method["method"];
  }
  EXPECT_FALSE(j["terrain_lod"]["levels"].empty());
  for (const auto& level : j["terrain_lod"]["levels"])
    EXPECT_LE(level["max_error_m"].get<double>(), level["table_max_error_m"].get<double>() + 1e-6) << level["name"];
  EXPECT_FALSE(j["fitters"]["models"].empty());
  for (const auto& model : j["fitters"]["models"]) {
    const auto& v = model["volume"];
    EXPECT_LE(v["hull_search"].get<double>(), v["covariance"].get<double>() * (1 + 1e-9)) << model["model"];
    EXPECT_GT(v["cgal_optimal"].get<double>(), 0.0) << model["model"];
  }

  // contacts.gpkg: every method's blocking events in one layer; per method and flythrough, the
  // equipment's are the report's blocking events.
  {
    GDALAllRegister();
    GDALDatasetH ds = GDALOpenEx((dir / "contacts.gpkg").c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr);
    ASSERT_NE(ds, nullptr);
    OGRLayerH l = GDALDatasetGetLayerByName(ds, "contacts");
    ASSERT_NE(l, nullptr);
    std::map<std::pair<std::string, std::string>, std::size_t> equipment;
    for (OGRFeatureH f = OGR_L_GetNextFeature(l); f; f = OGR_L_GetNextFeature(l)) {
      const std::string kind = OGR_F_GetFieldAsString(f, OGR_F_GetFieldIndex(f, "kind"));
      if (kind != "terrain")
        ++equipment[{OGR_F_GetFieldAsString(f, OGR_F_GetFieldIndex(f, "method")),
                     OGR_F_GetFieldAsString(f, OGR_F_GetFieldIndex(f, "script"))}];
      OGR_F_Destroy(f);
    }
    GDALClose(ds);
    std::size_t events = 0;
    for (const auto& method : j["methods"])
      for (const auto& play : method["flythroughs"]) {
        if (play.contains("error")) continue;
        const std::size_t want = play["blocking_events"].get<std::size_t>();
        EXPECT_EQ((equipment[{method["method"].get<std::string>(), play["script"].get<std::string>()}]), want)
            << method["method"] << " " << play["script"];
        events += want;
      }
    EXPECT_GT(events, 20u);
  }

  const std::string md = readText(dir / "report.md");
  for (const char* m : kMethods) EXPECT_NE(md.find(std::string("| ") + m + " |"), std::string::npos) << m;
  EXPECT_NE(md.find("![time against stop gap](pareto.png)"), std::string::npos);
  EXPECT_NE(md.find("Nested: false-block rate and stop gap per flythrough"), std::string::npos);
  EXPECT_NE(md.find("### Cost by model weight"), std::string::npos);
  for (const char* s : kScripts) EXPECT_NE(md.find(std::string("| ") + s + " |"), std::string::npos) << s;

  for (const char* png : {"pareto.png", "methods.png", "terrain_lod.png", "model_weight.png"}) {
    osg::ref_ptr<osg::Image> image = osgDB::readImageFile((dir / png).string());
    ASSERT_TRUE(image.valid()) << png;
    EXPECT_GE(image->s(), 400) << png;
    EXPECT_GE(image->t(), 300) << png;
  }

  // Existing files are kept unless --overwrite; the message names the file.
  const auto again = runNestwalk("report --quick --out " + quoted(dir));
  EXPECT_EQ(again.exitCode, 1);
  EXPECT_NE(again.err.find((dir / "report.md").string()), std::string::npos) << again.err;
  EXPECT_NE(again.err.find("--overwrite"), std::string::npos) << again.err;
}

TEST_F(Report, HeavyModelFlythroughsBlockExactlyOnEverySide) {
  // The heavy-model hard cases as flythroughs (tools/data/make_heavy_scene.py: the shared truck,
  // excavator, jeep and lamp and the bundled drill rig on the dump's top bench, each walked into
  // from 16 sides): every exact method is blocked 16 times in each model's flythrough, each time by
  // that model (contacts.gpkg), 0 < gap <= 1 mm from its real triangles (the report's exact
  // distance per contact), with no missed contact, early stop or false block against the
  // advancement reference; the nested test alone stops short (the trade-off these models show);
  // the frames beside the 10k-99k-triangle units fall in their own weight class.
  const fs::path data = sharedData();
  if (data.empty()) GTEST_SKIP() << "shared data folder absent (NESTWALK_SHARED_DATA): no heavy real models";
  if (runCommand("command -v python3").exitCode != 0) GTEST_SKIP() << "python3 absent (tools/setup-deps.sh installs it)";
  constexpr double kMostStopGap = 1e-3;  // metres: the exact methods stop within a millimetre
  const TempFolder folder;
  const fs::path heavy = folder / "heavy", dir = folder / "report";
  const auto made = runCommand("python3 " + quoted(fs::path(build::sourceDir()) / "tools" / "data" / "make_heavy_scene.py") +
                               " " + quoted(fs::path(build::bundledSceneDir())) + " " + quoted(data) + " " + quoted(heavy));
  ASSERT_EQ(made.exitCode, 0) << made.out << made.err;
  const char* const names[] = {"drill_rig", "excavator", "jeep", "lamp", "truck"};  // the scene's unit names
  auto scriptOf = [](const std::string& name) { return "approach_" + name + ".txt"; };
  std::string scripts;
  for (const char* name : names) scripts += " " + quoted(heavy / "scripts" / scriptOf(name));
  const auto r = runNestwalk("report " + quoted(heavy / "scene.json") + " --quick --out " + quoted(dir) + " --scripts" + scripts);
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const auto j = nlohmann::json::parse(readText(dir / "report.json"));
  const std::set<std::string> exact = {"nested+mesh", "kdop18", "auto"};
  long nestedEarlyStops = 0;
  std::size_t exactSeen = 0;
  for (const auto& method : j["methods"]) {
    const std::string m = method["method"];
    SCOPED_TRACE(m);
    if (m == "nested") nestedEarlyStops = method["early_stops"].get<long>();
    if (!exact.count(m)) continue;
    ++exactSeen;
    EXPECT_TRUE(method["complete"].get<bool>());
    ASSERT_EQ(method["flythroughs"].size(), std::size(names));
    for (std::size_t s = 0; s < std::size(names); ++s) {
      const auto& play = method["flythroughs"][s];
      ASSERT_EQ(play["script"], scriptOf(names[s]));  // in the order given
      SCOPED_TRACE(scriptOf(names[s]));
      ASSERT_FALSE(play.contains("error")) << play["error"];
      EXPECT_EQ(play["missed"].get<long>(), 0);
      EXPECT_EQ(play["early_stops"].get<long>(), 0);
      EXPECT_EQ(play["false_blocks"].get<long>(), 0);
    }
  }
  EXPECT_EQ(exactSeen, exact.size());
  EXPECT_GT(nestedEarlyStops, 0);

  // Every blocking event of the exact methods, by method and flythrough: the unit and its gap.
  GDALAllRegister();
  GDALDatasetH ds = GDALOpenEx((dir / "contacts.gpkg").c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr);
  ASSERT_NE(ds, nullptr);
  OGRLayerH layer = GDALDatasetGetLayerByName(ds, "contacts");
  ASSERT_NE(layer, nullptr);
  std::map<std::pair<std::string, std::string>, std::size_t> byTheModel;  // (method, script) -> events
  for (OGRFeatureH f = OGR_L_GetNextFeature(layer); f; f = OGR_L_GetNextFeature(layer)) {
    const std::string method = OGR_F_GetFieldAsString(f, OGR_F_GetFieldIndex(f, "method"));
    const std::string script = OGR_F_GetFieldAsString(f, OGR_F_GetFieldIndex(f, "script"));
    const std::string unit = OGR_F_GetFieldAsString(f, OGR_F_GetFieldIndex(f, "unit"));
    const double gap = OGR_F_GetFieldAsDouble(f, OGR_F_GetFieldIndex(f, "stop_gap_m"));
    OGR_F_Destroy(f);
    if (!exact.count(method)) continue;
    EXPECT_EQ(scriptOf(unit), script) << method << ": blocked by " << unit;
    EXPECT_GT(gap, 0.0) << method << " " << script;
    EXPECT_LE(gap, kMostStopGap) << method << " " << script;
    ++byTheModel[{method, script}];
  }
  GDALClose(ds);
  for (const std::string& m : exact)
    for (const char* name : names) EXPECT_EQ((byTheModel[{m, scriptOf(name)}]), 16u) << m << " " << name;

  std::size_t heavyFrames = 0;
  for (const auto& row : j["by_model_weight"])
    if (row["method"] == "nested+mesh" && row["weight"] == "10k-99k triangles") heavyFrames += row["frames"].get<std::size_t>();
  EXPECT_GT(heavyFrames, 1000u);
}

TEST_F(Report, MissingScriptIsNamed) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const auto r = runNestwalk("report " + quoted(kScene) + " --scripts " + quoted(dir / "nope.txt") + " --out " +
                             quoted(dir / "report"));
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find("nope.txt"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "report" / "report.md"));
}

}  // namespace
}  // namespace nestwalk::test
