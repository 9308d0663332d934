// The summary JSON (engine/report/run_summary.h) and the nearest-rank percentile (core/statistics.h), against values
// computed here independently: sorted lists indexed by integer rank, sums, counts.
#include "nestwalk/core/statistics.h"
#include "nestwalk/report/run_summary.h"
#include "tests/common/nearest_rank.h"

#include "nestwalk/core/input_error.h"
#include "tests/report/report_fixtures.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <map>
#include <random>

namespace nestwalk {
namespace {

using test::nearestRank;

using testing::readFile;
using testing::sampleRecords;
using testing::TempDir;


TEST(RunSummary, ValuesAgainstIndependentComputation) {
  TempDir dir;
  const std::vector<FrameRecord> records = sampleRecords(1000);
  std::vector<ExpectationResult> expectations(3);
  expectations[0] = {"patrol.txt", 12, "expect blocked by bench2", true, 40, {500000.5, 4400000.25, 300.125},
                     "blocked by bench2/station3/mast"};
  expectations[1] = {"patrol.txt", 15, "expect free", false, 77, {1, 2, 3}, "blocked by terrain:step"};
  expectations[2] = {"patrol.txt", 20, "expect ground within 0.01", true, 99, {4, 5, 6}, "eye 0.000001 m off"};
  RunSummaryInfo info{"dump.scene.json", "patrol.txt", "nested, auto tree (degree 4)", 1.0 / 60.0, 42, ""};
  const std::string path = dir / "summary.json";
  writeRunSummary(path, info, records, expectations);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"summary.json"});

  const nlohmann::json j = nlohmann::json::parse(readFile(path));
  EXPECT_EQ(j["scene"], "dump.scene.json");
  EXPECT_EQ(j["script"], "patrol.txt");
  EXPECT_EQ(j["method"], "nested, auto tree (degree 4)");
  EXPECT_EQ(j["dt"].get<double>(), 1.0 / 60.0);
  EXPECT_EQ(j["units"], 42);
  EXPECT_EQ(j["frames"], 1000);
  EXPECT_EQ(j["simulated_seconds"].get<double>(), records.back().time);

  const char* parts[] = {"ground", "broad", "narrow", "total"};
  for (std::size_t part = 0; part < kStepParts; ++part) {
    std::vector<double> us;
    for (const FrameRecord& r : records) us.push_back(r.micros.values[part]);
    const nlohmann::json& s = j["step_us"][parts[part]];
    EXPECT_EQ(s["p50"].get<double>(), nearestRank(us, 50)) << parts[part];
    EXPECT_EQ(s["p95"].get<double>(), nearestRank(us, 95)) << parts[part];
    EXPECT_EQ(s["p99"].get<double>(), nearestRank(us, 99)) << parts[part];
    EXPECT_EQ(s["max"].get<double>(), *std::max_element(us.begin(), us.end())) << parts[part];
  }

  double sums[6] = {};
  std::map<std::string, int> blockers;
  int blocked = 0;
  for (const FrameRecord& r : records) {
    sums[0] += double(r.nodeTests);
    sums[1] += double(r.stageTests[OverlapStage::AabbAabb]);
    sums[2] += double(r.stageTests[OverlapStage::AabbObb]);
    sums[3] += double(r.stageTests[OverlapStage::ObbObb]);
    sums[4] += double(r.primitiveTests);
    sums[5] += double(r.volumesUpdated);
    if (r.blocked) {
      ++blocked;
      ++blockers[r.blockedBy];
    }
  }
  const char* counters[] = {"node_tests", "aabb_aabb", "aabb_obb", "obb_obb", "np", "nu"};
  for (int i = 0; i < 6; ++i)
    EXPECT_DOUBLE_EQ(j["mean_per_frame"][counters[i]].get<double>(), sums[i] / 1000.0) << counters[i];

  EXPECT_EQ(j["contacts"]["frames_blocked"], blocked);
  const nlohmann::json& list = j["contacts"]["blockers"];
  ASSERT_EQ(list.size(), blockers.size());
  for (const nlohmann::json& b : list) EXPECT_EQ(b["frames"], blockers.at(b["name"].get<std::string>()));
  for (std::size_t i = 1; i < list.size(); ++i) EXPECT_GE(list[i - 1]["frames"], list[i]["frames"]);

  const nlohmann::json& e = j["expectations"];
  EXPECT_EQ(e["met"], 2);
  EXPECT_EQ(e["failed"], 1);
  ASSERT_EQ(e["list"].size(), 3u);
  EXPECT_EQ(e["list"][1]["script"], "patrol.txt");
  EXPECT_EQ(e["list"][1]["line"], 15);
  EXPECT_EQ(e["list"][1]["text"], "expect free");
  EXPECT_EQ(e["list"][1]["met"], false);
  EXPECT_EQ(e["list"][1]["frame"], 77);
  EXPECT_EQ(e["list"][1]["detail"], "blocked by terrain:step");
  EXPECT_EQ(e["list"][0]["eye"], nlohmann::json::array({500000.5, 4400000.25, 300.125}));
  EXPECT_EQ(e["list"][0]["met"], true);
}

TEST(RunSummary, EmptyRun) {
  TempDir dir;
  writeRunSummary(dir / "s.json", RunSummaryInfo{"s", "t", "m", 0.01, 0, ""}, {}, {});
  const nlohmann::json j = nlohmann::json::parse(readFile(dir / "s.json"));
  EXPECT_EQ(j["frames"], 0);
  EXPECT_EQ(j["simulated_seconds"].get<double>(), 0.0);
  EXPECT_EQ(j["step_us"]["total"]["p99"].get<double>(), 0.0);
  EXPECT_EQ(j["mean_per_frame"]["node_tests"].get<double>(), 0.0);
  EXPECT_EQ(j["contacts"]["frames_blocked"], 0);
  EXPECT_TRUE(j["contacts"]["blockers"].empty());
  EXPECT_EQ(j["expectations"]["met"], 0);
  EXPECT_EQ(j["expectations"]["failed"], 0);
}

TEST(RunSummary, UnwritableFolderNamesTheFile) {
  TempDir dir;
  const std::string path = dir / "no/summary.json";
  try {
    writeRunSummary(path, RunSummaryInfo{}, sampleRecords(3), {});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nestwalk

namespace nestwalk {
namespace {

TEST(RunSummary, RenderSectionOverRenderedFramesOnly) {
  testing::TempDir dir;
  const std::vector<FrameRecord> records = testing::sampleRecords(300);
  const std::vector<RenderRecord> renders = testing::sampleRenders(300);
  RunSummaryInfo info{"s.json", "p.txt", "nested", 1.0 / 60.0, 7, ""};
  info.renderInfoJson = R"({"route": "egl-surfaceless", "size": [640, 360]})";
  writeRunSummary(dir / "summary.json", info, records, {}, renders);
  const nlohmann::json j = nlohmann::json::parse(testing::readFile(dir / "summary.json"));
  ASSERT_TRUE(j.contains("render"));
  const nlohmann::json& r = j["render"];
  EXPECT_EQ(r["route"], "egl-surfaceless");
  EXPECT_EQ(r["size"][1], 360);
  std::size_t frames = 0;
  double triangles = 0, maxError = 0;
  std::vector<double> totalMs, drawMs;
  for (const RenderRecord& f : renders)
    if (f.rendered) {
      ++frames;
      triangles += double(f.triangles);
      maxError = std::max(maxError, f.terrainErrorPx);
      totalMs.push_back(f.micros[RenderPart::Total] / 1000.0);
      drawMs.push_back(f.micros[RenderPart::Draw] / 1000.0);
    }
  EXPECT_EQ(r["frames"], frames);
  EXPECT_EQ(frames, 100u);
  EXPECT_DOUBLE_EQ(r["mean_triangles"].get<double>(), triangles / double(frames));
  EXPECT_EQ(r["max_terrain_error_px"].get<double>(), maxError);
  EXPECT_EQ(r["ms"]["total"]["p50"].get<double>(), nearestRank(totalMs, 50));
  EXPECT_EQ(r["ms"]["draw"]["p95"].get<double>(), nearestRank(drawMs, 95));
  EXPECT_EQ(r["ms"]["total"]["max"].get<double>(), *std::max_element(totalMs.begin(), totalMs.end()));

  // Without rendered frames there is no render section.
  writeRunSummary(dir / "plain.json", info, records, {}, std::vector<RenderRecord>(records.size()));
  EXPECT_FALSE(nlohmann::json::parse(testing::readFile(dir / "plain.json")).contains("render"));
}

}  // namespace
}  // namespace nestwalk
