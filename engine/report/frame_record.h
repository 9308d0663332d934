// What a run records per frame, and the files it writes from the records: the per-frame CSV, the
// summary JSON and the frame-time plot (PNG). All files are written to a temporary name in the
// target folder and renamed at the end.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace nestwalk {

// Timed parts of a step, in the order they run.
enum class StepPart : std::uint8_t { Ground = 0, BroadPhase = 1, Narrow = 2, Total = 3 };
inline constexpr int kStepParts = 4;
const char* stepPartName(StepPart p);  // "ground", "broad", "narrow", "total"

// What rendering a frame drew and cost (nestwalk run --render); all zero for frames not rendered.
// Timed parts of a rendered frame, in the order they run.
enum class RenderPart : std::uint8_t { Cull = 0, Draw = 1, Readback = 2, Total = 3 };
inline constexpr int kRenderParts = 4;
const char* renderPartName(RenderPart p);  // "cull", "draw", "readback", "total"

struct RenderRecord {
  bool rendered = false;
  std::uint64_t triangles = 0;          // triangles drawn: terrain levels in view + equipment kept
  std::uint64_t instancesDrawn = 0;     // equipment instances kept by the view culling
  std::uint64_t culledByAabb = 0;       // instances culled by the outer AABB test
  std::uint64_t culledByObb = 0;        // instances the AABB could not decide, culled by the inner OBB
  double terrainErrorPx = 0;            // largest projected vertical error of a drawn terrain level
  std::array<double, kRenderParts> micros{};  // wall-clock µs per part (timing columns)
};

struct FrameRecord {
  std::uint64_t frame = 0;
  double time = 0;                                      // seconds of simulated time at the frame's end
  Eigen::Vector3d eye = Eigen::Vector3d::Zero();        // map frame
  double headingDeg = 0, pitchDeg = 0;
  bool flying = false;
  bool hasGround = false;
  double ground = 0;                                    // terrain height under the eye (map z)
  bool blocked = false;
  std::string blockedBy;                                // unit name, or "terrain:step" / "terrain:slope"
                                                        // / "terrain:edge"; "" when free
  std::uint64_t nodeTests = 0;                          // hierarchy BV tests (Nv broad phase)
  std::array<std::uint64_t, 3> stageTests{};            // Nv: AABB-AABB, AABB-OBB, OBB-OBB
  std::uint64_t primitiveTests = 0;                     // Np (triangle tests; 0 for volume methods)
  std::uint64_t volumesUpdated = 0;                     // Nu (the viewer's volumes rebuilt)
  std::array<double, kStepParts> micros{};              // wall-clock µs per part (timing columns)
  RenderRecord render;                                  // rendering (run --render)
};

// CSV with a header; the timing columns (names starting with "us_") come last, so that two runs
// with the same inputs give byte-identical files once those columns are cut. Columns:
//   frame,time,x,y,z,heading,pitch,flying,has_ground,ground,blocked,blocked_by,
//   node_tests,aabb_aabb,aabb_obb,obb_obb,np,nu,
//   rendered,triangles,instances_drawn,culled_aabb,culled_obb,terrain_error_px,
//   us_ground,us_broad,us_narrow,us_total,us_render_cull,us_render_draw,us_render_readback,us_render_total
// time %.6f s; x, y, z, ground %.4f m (ground empty without ground); heading, pitch %.6f degrees;
// flags 0/1; counters integers; terrain_error_px %.4f; us_* %.3f µs. Numbers are locale-independent (std::to_chars);
// blocked_by is quoted (RFC 4180) when it holds a comma, a quote or a line break.
void writeFrameCsv(const std::string& path, const std::vector<FrameRecord>& records);

struct ExpectationResult {
  std::string script;     // file
  int line = 0;
  std::string text;       // the expectation as written
  bool met = false;
  std::uint64_t frame = 0;
  Eigen::Vector3d eye = Eigen::Vector3d::Zero();
  std::string detail;     // what was found, e.g. "blocked by bench2/station3/mast" or "free"
};

struct RunSummaryInfo {
  std::string scene, script, method;
  double dt = 0;
  std::size_t units = 0;
  // Rendering: how (e.g. {"route": "egl-surfaceless", "gl_renderer": ..., "size": [w, h]}), as JSON
  // text merged into "render"; empty when not rendering.
  std::string renderInfoJson;
};

// Summary JSON: frames, simulated seconds, p50/p95/p99/max µs per part, mean counters per frame,
// contacts (frames blocked, distinct units that blocked), expectations (each with met/failed):
//   {"scene", "script", "method", "dt", "units", "frames", "simulated_seconds" (last record's time),
//    "step_us": {"ground"|"broad"|"narrow"|"total": {"p50", "p95", "p99", "max"}},  (nearest rank)
//    "render" (only when frames were rendered): {"frames", "ms": {"cull"|"draw"|"readback"|"total":
//        {"p50", "p95", "p99", "max"}}, "mean_triangles", "max_triangles", "max_terrain_error_px",
//        "mean_instances_drawn", "mean_culled_aabb", "mean_culled_obb", plus RunSummaryInfo::render},
//    "mean_per_frame": {"node_tests", "aabb_aabb", "aabb_obb", "obb_obb", "np", "nu"},
//    "contacts": {"frames_blocked", "blockers": [{"name", "frames"}, ...]},  (most frames first)
//    "expectations": {"met", "failed", "list": [{"script", "line", "text", "met", "frame",
//                                                 "eye": [x, y, z], "detail"}, ...]}}
void writeRunSummary(const std::string& path, const RunSummaryInfo& info, const std::vector<FrameRecord>& records,
                     const std::vector<ExpectationResult>& expectations);

// Frame-time plot: µs per frame for each part against the frame number, with p50/p99 lines and a
// legend; when frames were rendered, the render time (total) through the rendered frames as well; PNG through osgDB's image writer (its png plugin). The y axis is log10 over whole
// decades (parts differ by orders of magnitude; a time of 0 sits on the floor); the x axis runs
// from the first record's frame to the last's. Colours (RGB): ground green (44,160,44), broad
// blue (31,119,180), narrow orange (255,127,14), total red (214,39,40), render pink
// (227,119,194); p50 of the (step) total a
// dashed purple (148,103,189) line, p99 a dashed brown (140,86,75) one; white background, black
// axes and labels, light grey (224,224,224) decade and frame grid. Throws InputError for a size
// below 172 x 114 pixels or when the PNG cannot be written.
void writeFrameTimePlot(const std::string& path, const std::vector<FrameRecord>& records, int width = 1200,
                        int height = 500);

// Percentile (nearest-rank, p in [0, 100]) of a list of values; 0 for an empty list.
double percentile(std::vector<double> values, double p);

}  // namespace nestwalk
