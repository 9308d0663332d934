#include "nestwalk/report/frame_csv.h"

#include "nestwalk/core/output_file.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>

namespace nestwalk {
namespace {

// Digits after the point, by column kind. Map coordinates at UTM magnitudes (1e6..1e7 m) keep
// 0.1 mm; angles 1e-6 degrees (2 mm at 100 km); time 1 µs (well below any step); timings 1 ns
// (below any clock's resolution).
constexpr int kPositionDigits = 4;
constexpr int kAngleDigits = 6;
constexpr int kTimeDigits = 6;
constexpr int kMicrosDigits = 3;
constexpr int kPixelDigits = 4;

/// Fixed-point text, independent of the C and C++ locales (std::to_chars).
void appendFixed(std::string& out, double v, int digits) {
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, digits);
  if (ec != std::errc()) {  // beyond 1e40 or so: cannot happen for our columns, but never truncate
    end = std::to_chars(buf, buf + sizeof buf, v).ptr;
  }
  out.append(buf, end);
}

void appendInt(std::string& out, std::uint64_t v) {
  char buf[24];
  const auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;
  out.append(buf, end);
}

/// RFC 4180 quoting: a field with a comma, a quote or a line break is quoted, quotes doubled.
void appendField(std::string& out, const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) {
    out += s;
    return;
  }
  out += '"';
  for (char ch : s) {
    if (ch == '"') out += '"';
    out += ch;
  }
  out += '"';
}

}  // namespace

const char* renderPartName(RenderPart p) {
  switch (p) {
    case RenderPart::Cull: return "cull";
    case RenderPart::Draw: return "draw";
    case RenderPart::Readback: return "readback";
    case RenderPart::Total: return "total";
  }
  return "?";
}

const std::vector<std::string>& frameCsvColumns() {
  static const std::vector<std::string> columns = {
      "frame",         "time",          "x",        "y",          "z",         "heading",        "pitch",
      "flying",        "has_ground",    "ground",   "blocked",    "blocked_by", "node_tests",    "aabb_aabb",
      "aabb_obb",      "obb_obb",       "np",       "nu",         "rendered",  "triangles",      "instances_drawn",
      "culled_aabb",   "culled_obb",    "terrain_error_px", "us_ground", "us_broad", "us_narrow", "us_total",
      "us_render_cull", "us_render_draw", "us_render_readback", "us_render_total"};
  return columns;
}

void frameCells(const FrameRecord& r, const RenderRecord& render, std::vector<FrameCell>& out) {
  out.clear();
  auto integer = [&](std::uint64_t v) { out.push_back({FrameCellKind::Integer, double(v), {}, 0}); };
  auto real = [&](std::optional<double> v, int digits) { out.push_back({FrameCellKind::Real, v, {}, digits}); };
  integer(r.frame);
  real(r.time, kTimeDigits);
  for (int axis = 0; axis < 3; ++axis) real(r.eye[axis], kPositionDigits);
  real(r.headingDeg, kAngleDigits);
  real(r.pitchDeg, kAngleDigits);
  integer(r.flying);
  integer(r.hasGround);
  real(r.hasGround ? std::optional<double>(r.ground) : std::nullopt, kPositionDigits);  // empty: no ground
  integer(r.blocked);
  out.push_back({FrameCellKind::Text, std::nullopt, r.blockedBy, 0});
  for (std::uint64_t c : {r.nodeTests, r.stageTests[OverlapStage::AabbAabb], r.stageTests[OverlapStage::AabbObb],
                          r.stageTests[OverlapStage::ObbObb], r.primitiveTests, r.volumesUpdated})
    integer(c);
  integer(render.rendered);
  for (std::uint64_t c : {render.triangles, render.instancesDrawn, render.culledByAabb, render.culledByObb}) integer(c);
  real(render.terrainErrorPx, kPixelDigits);
  for (double us : r.micros) real(us, kMicrosDigits);
  for (double us : render.micros) real(us, kMicrosDigits);
}

void writeFrameCsv(const std::string& path, const std::vector<FrameRecord>& records,
                   std::span<const RenderRecord> renders) {
  if (!renders.empty() && renders.size() != records.size())
    throw std::invalid_argument("writeFrameCsv: " + std::to_string(renders.size()) + " render records for " +
                                std::to_string(records.size()) + " frames");
  std::string text;
  for (const std::string& column : frameCsvColumns()) text += (text.empty() ? "" : ",") + column;
  text += '\n';
  text.reserve(text.size() + records.size() * 200);
  const RenderRecord notRendered;
  std::vector<FrameCell> cells;
  for (std::size_t i = 0; i < records.size(); ++i) {
    frameCells(records[i], renders.empty() ? notRendered : renders[i], cells);
    for (std::size_t c = 0; c < cells.size(); ++c) {
      if (c) text += ',';
      const FrameCell& cell = cells[c];
      if (cell.kind == FrameCellKind::Text) appendField(text, cell.text);
      else if (!cell.number) continue;
      else if (cell.kind == FrameCellKind::Integer) appendInt(text, std::uint64_t(*cell.number));
      else appendFixed(text, *cell.number, cell.digits);
    }
    text += '\n';
  }
  writeFileAtomically(path, text);
}

}  // namespace nestwalk
