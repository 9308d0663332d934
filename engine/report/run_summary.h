// The summary of a run (summary.json): what ran, how long each part of a step took, how much work
// the collision tests did, what blocked the viewer and whether the script's expectations held.
// Thread safety: pure apart from the file written (one writer per path at a time,
// core/output_file.h).
#pragma once

#include "nestwalk/report/render_record.h"
#include "nestwalk/walker/frame_record.h"

#include <span>
#include <string>
#include <vector>

namespace nestwalk {

struct RunSummaryInfo {
  std::string scene, script, method;
  double dt = 0;
  std::size_t units = 0;
  // Rendering: how (e.g. {"route": "egl-surfaceless", "gl_renderer": ..., "size": [w, h]}), as JSON
  // text merged into "render"; empty when not rendering.
  std::string renderInfoJson;
};

/// Writes the summary JSON (keys in this order; percentiles nearest rank, core/statistics.h):
///   {"scene", "script", "method", "dt", "units", "frames", "simulated_seconds" (last record's time),
///    "step_us": {"ground"|"broad"|"narrow"|"total": {"p50", "p95", "p99", "max"}},
///    "render" (only when frames were rendered): {"frames", "ms": {"cull"|"draw"|"readback"|"total":
///        {"p50", "p95", "p99", "max"}}, "mean_triangles", "max_triangles", "max_terrain_error_px",
///        "mean_instances_drawn", "mean_culled_aabb", "mean_culled_obb", plus RunSummaryInfo's render},
///    "mean_per_frame": {"node_tests", "aabb_aabb", "aabb_obb", "obb_obb", "np", "nu"},
///    "contacts": {"frames_blocked", "blockers": [{"name", "frames"}, ...]},  (most frames first)
///    "expectations": {"met", "failed", "list": [{"script", "line", "text", "met", "frame",
///                                                 "eye": [x, y, z], "detail"}, ...]}}
/// `renders`: one per record, or empty (nothing rendered). Throws InputError naming `path` when it
/// cannot be written.
void writeRunSummary(const std::string& path, const RunSummaryInfo& info, const std::vector<FrameRecord>& records,
                     const std::vector<ExpectationResult>& expectations, std::span<const RenderRecord> renders = {});

}  // namespace nestwalk
