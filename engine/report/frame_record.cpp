// The per-frame CSV and the percentile used by the summary and the plot.
#include "engine/report/frame_record.h"

#include "engine/report/output_file.h"

#include <algorithm>
#include <charconv>
#include <cmath>

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

const char* stepPartName(StepPart p) {
  switch (p) {
    case StepPart::Ground: return "ground";
    case StepPart::BroadPhase: return "broad";
    case StepPart::Narrow: return "narrow";
    case StepPart::Total: return "total";
  }
  return "?";
}

const char* renderPartName(RenderPart p) {
  switch (p) {
    case RenderPart::Cull: return "cull";
    case RenderPart::Draw: return "draw";
    case RenderPart::Readback: return "readback";
    case RenderPart::Total: return "total";
  }
  return "?";
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  const double n = double(values.size());
  // Nearest rank: the smallest value with at least p % of the values at or below it. p * n first,
  // so that integer p and n give an exact product (95 * 20 / 100 is 19, not 19.000000000000004).
  double rank = std::ceil(std::clamp(p, 0.0, 100.0) * n / 100.0);
  rank = std::clamp(rank, 1.0, n);
  const auto k = static_cast<std::ptrdiff_t>(rank) - 1;
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[std::size_t(k)];
}

void writeFrameCsv(const std::string& path, const std::vector<FrameRecord>& records) {
  std::string text =
      "frame,time,x,y,z,heading,pitch,flying,has_ground,ground,blocked,blocked_by,node_tests,aabb_aabb,aabb_obb,"
      "obb_obb,np,nu,rendered,triangles,instances_drawn,culled_aabb,culled_obb,terrain_error_px,us_ground,us_broad,"
      "us_narrow,us_total,us_render_cull,us_render_draw,us_render_readback,us_render_total\n";
  text.reserve(text.size() + records.size() * 200);
  for (const FrameRecord& r : records) {
    appendInt(text, r.frame);
    text += ',';
    appendFixed(text, r.time, kTimeDigits);
    for (int i = 0; i < 3; ++i) {
      text += ',';
      appendFixed(text, r.eye[i], kPositionDigits);
    }
    text += ',';
    appendFixed(text, r.headingDeg, kAngleDigits);
    text += ',';
    appendFixed(text, r.pitchDeg, kAngleDigits);
    text += r.flying ? ",1" : ",0";
    text += r.hasGround ? ",1," : ",0,";
    if (r.hasGround) appendFixed(text, r.ground, kPositionDigits);  // empty: no ground under the eye
    text += r.blocked ? ",1," : ",0,";
    appendField(text, r.blockedBy);
    const std::uint64_t counters[] = {r.nodeTests,     r.stageTests[0],  r.stageTests[1],
                                      r.stageTests[2], r.primitiveTests, r.volumesUpdated};
    for (std::uint64_t c : counters) {
      text += ',';
      appendInt(text, c);
    }
    text += r.render.rendered ? ",1" : ",0";
    const std::uint64_t drawn[] = {r.render.triangles, r.render.instancesDrawn, r.render.culledByAabb,
                                   r.render.culledByObb};
    for (std::uint64_t c : drawn) {
      text += ',';
      appendInt(text, c);
    }
    text += ',';
    appendFixed(text, r.render.terrainErrorPx, kPixelDigits);
    for (int part = 0; part < kStepParts; ++part) {
      text += ',';
      appendFixed(text, r.micros[std::size_t(part)], kMicrosDigits);
    }
    for (int part = 0; part < kRenderParts; ++part) {
      text += ',';
      appendFixed(text, r.render.micros[std::size_t(part)], kMicrosDigits);
    }
    text += '\n';
  }
  writeFileAtomically(path, text);
}

}  // namespace nestwalk
