// The run's summary JSON (nlohmann_json): what ran, how long each part of a step took, how much
// work the collision tests did, what blocked the viewer and whether the script's expectations
// held. Key layout in frame_record.h.
#include "engine/report/frame_record.h"

#include "engine/report/output_file.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <map>

namespace nestwalk {
namespace {

using json = nlohmann::ordered_json;  // keys in the order written, for people reading the file

/// {"p50", "p95", "p99", "max"} of a list of times (nearest rank).
json percentiles(const std::vector<double>& values) {
  return {{"p50", percentile(values, 50)},
          {"p95", percentile(values, 95)},
          {"p99", percentile(values, 99)},
          {"max", percentile(values, 100)}};
}

}  // namespace

void writeRunSummary(const std::string& path, const RunSummaryInfo& info, const std::vector<FrameRecord>& records,
                     const std::vector<ExpectationResult>& expectations) {
  json out;
  out["scene"] = info.scene;
  out["script"] = info.script;
  out["method"] = info.method;
  out["dt"] = info.dt;
  out["units"] = info.units;
  out["frames"] = records.size();
  out["simulated_seconds"] = records.empty() ? 0.0 : records.back().time;

  json steps = json::object();
  for (int part = 0; part < kStepParts; ++part) {
    std::vector<double> us;
    us.reserve(records.size());
    for (const FrameRecord& r : records) us.push_back(r.micros[std::size_t(part)]);
    steps[stepPartName(StepPart(part))] = percentiles(us);
  }
  out["step_us"] = steps;

  std::vector<const FrameRecord*> rendered;
  for (const FrameRecord& r : records)
    if (r.render.rendered) rendered.push_back(&r);
  if (!rendered.empty()) {
    json render = info.renderInfoJson.empty() ? json::object() : json::parse(info.renderInfoJson);
    render["frames"] = rendered.size();
    json ms = json::object();
    for (int part = 0; part < kRenderParts; ++part) {
      std::vector<double> v;
      v.reserve(rendered.size());
      for (const FrameRecord* r : rendered) v.push_back(r->render.micros[std::size_t(part)] / 1000.0);
      ms[renderPartName(RenderPart(part))] = percentiles(v);
    }
    render["ms"] = ms;
    std::uint64_t triangles = 0, maxTriangles = 0, drawn = 0, byAabb = 0, byObb = 0;
    double maxError = 0;
    for (const FrameRecord* r : rendered) {
      triangles += r->render.triangles;
      maxTriangles = std::max(maxTriangles, r->render.triangles);
      drawn += r->render.instancesDrawn;
      byAabb += r->render.culledByAabb;
      byObb += r->render.culledByObb;
      maxError = std::max(maxError, r->render.terrainErrorPx);
    }
    const double m = double(rendered.size());
    render["mean_triangles"] = double(triangles) / m;
    render["max_triangles"] = maxTriangles;
    render["max_terrain_error_px"] = maxError;
    render["mean_instances_drawn"] = double(drawn) / m;
    render["mean_culled_aabb"] = double(byAabb) / m;
    render["mean_culled_obb"] = double(byObb) / m;
    out["render"] = render;
  }

  // Sums in 64-bit integers (exact), divided once at the end.
  std::uint64_t sums[6] = {};
  std::uint64_t blocked = 0;
  std::map<std::string, std::uint64_t> blockers;
  for (const FrameRecord& r : records) {
    sums[0] += r.nodeTests;
    sums[1] += r.stageTests[0];
    sums[2] += r.stageTests[1];
    sums[3] += r.stageTests[2];
    sums[4] += r.primitiveTests;
    sums[5] += r.volumesUpdated;
    if (r.blocked) {
      ++blocked;
      ++blockers[r.blockedBy];
    }
  }
  const double n = records.empty() ? 1.0 : double(records.size());
  const char* counterNames[6] = {"node_tests", "aabb_aabb", "aabb_obb", "obb_obb", "np", "nu"};
  json means = json::object();
  for (int i = 0; i < 6; ++i) means[counterNames[i]] = double(sums[i]) / n;
  out["mean_per_frame"] = means;

  // Blockers by frames blocked, most first; ties by name (std::map order), so the file is stable.
  std::vector<std::pair<std::string, std::uint64_t>> byCount(blockers.begin(), blockers.end());
  std::stable_sort(byCount.begin(), byCount.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  json blockerList = json::array();
  for (const auto& [name, frames] : byCount) blockerList.push_back({{"name", name}, {"frames", frames}});
  out["contacts"] = {{"frames_blocked", blocked}, {"blockers", blockerList}};

  json list = json::array();
  std::size_t met = 0;
  for (const ExpectationResult& e : expectations) {
    met += e.met;
    list.push_back({{"script", e.script},
                    {"line", e.line},
                    {"text", e.text},
                    {"met", e.met},
                    {"frame", e.frame},
                    {"eye", {e.eye.x(), e.eye.y(), e.eye.z()}},
                    {"detail", e.detail}});
  }
  out["expectations"] = {{"met", met}, {"failed", expectations.size() - met}, {"list", list}};

  writeFileAtomically(path, out.dump(2) + "\n");
}

}  // namespace nestwalk
