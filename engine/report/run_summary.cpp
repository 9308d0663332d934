// The run's summary JSON (nlohmann_json); key layout in run_summary.h.
#include "nestwalk/report/run_summary.h"

#include "nestwalk/core/output_file.h"
#include "nestwalk/core/statistics.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <map>
#include <stdexcept>

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

json renderSection(const RunSummaryInfo& info, std::span<const RenderRecord> renders) {
  std::vector<const RenderRecord*> rendered;
  for (const RenderRecord& r : renders)
    if (r.rendered) rendered.push_back(&r);
  if (rendered.empty()) return nullptr;
  json render = info.renderInfoJson.empty() ? json::object() : json::parse(info.renderInfoJson);
  render["frames"] = rendered.size();
  json ms = json::object();
  for (RenderPart part : kAllRenderParts) {
    std::vector<double> v;
    v.reserve(rendered.size());
    for (const RenderRecord* r : rendered) v.push_back(r->micros[part] / 1000.0);
    ms[renderPartName(part)] = percentiles(v);
  }
  render["ms"] = ms;
  std::uint64_t triangles = 0, maxTriangles = 0, drawn = 0, byAabb = 0, byObb = 0;
  double maxError = 0;
  for (const RenderRecord* r : rendered) {
    triangles += r->triangles;
    maxTriangles = std::max(maxTriangles, r->triangles);
    drawn += r->instancesDrawn;
    byAabb += r->culledByAabb;
    byObb += r->culledByObb;
    maxError = std::max(maxError, r->terrainErrorPx);
  }
  const double m = double(rendered.size());
  render["mean_triangles"] = double(triangles) / m;
  render["max_triangles"] = maxTriangles;
  render["max_terrain_error_px"] = maxError;
  render["mean_instances_drawn"] = double(drawn) / m;
  render["mean_culled_aabb"] = double(byAabb) / m;
  render["mean_culled_obb"] = double(byObb) / m;
  return render;
}

/// The work counters per frame, in the summary's order and names.
struct CounterColumn {
  const char* name;
  std::uint64_t (*of)(const FrameRecord&);
};
constexpr CounterColumn kCounters[] = {
    {"node_tests", [](const FrameRecord& r) { return r.nodeTests; }},
    {"aabb_aabb", [](const FrameRecord& r) { return r.stageTests[OverlapStage::AabbAabb]; }},
    {"aabb_obb", [](const FrameRecord& r) { return r.stageTests[OverlapStage::AabbObb]; }},
    {"obb_obb", [](const FrameRecord& r) { return r.stageTests[OverlapStage::ObbObb]; }},
    {"np", [](const FrameRecord& r) { return r.primitiveTests; }},
    {"nu", [](const FrameRecord& r) { return r.volumesUpdated; }},
};

}  // namespace

void writeRunSummary(const std::string& path, const RunSummaryInfo& info, const std::vector<FrameRecord>& records,
                     const std::vector<ExpectationResult>& expectations, std::span<const RenderRecord> renders) {
  if (!renders.empty() && renders.size() != records.size())
    throw std::invalid_argument("writeRunSummary: " + std::to_string(renders.size()) + " render records for " +
                                std::to_string(records.size()) + " frames");
  json out;
  out["scene"] = info.scene;
  out["script"] = info.script;
  out["method"] = info.method;
  out["dt"] = info.dt;
  out["units"] = info.units;
  out["frames"] = records.size();
  out["simulated_seconds"] = records.empty() ? 0.0 : records.back().time;

  json steps = json::object();
  for (StepPart part : kAllStepParts) {
    std::vector<double> us;
    us.reserve(records.size());
    for (const FrameRecord& r : records) us.push_back(r.micros[part]);
    steps[stepPartName(part)] = percentiles(us);
  }
  out["step_us"] = steps;
  if (json render = renderSection(info, renders); !render.is_null()) out["render"] = render;

  // Sums in 64-bit integers (exact), divided once at the end.
  const double n = records.empty() ? 1.0 : double(records.size());
  json means = json::object();
  for (const CounterColumn& c : kCounters) {
    std::uint64_t sum = 0;
    for (const FrameRecord& r : records) sum += c.of(r);
    means[c.name] = double(sum) / n;
  }
  out["mean_per_frame"] = means;

  // Blockers by frames blocked, most first; ties by name (std::map order), so the file is stable.
  std::uint64_t blocked = 0;
  std::map<std::string, std::uint64_t> blockers;
  for (const FrameRecord& r : records)
    if (r.blocked) {
      ++blocked;
      ++blockers[r.blockedBy];
    }
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
