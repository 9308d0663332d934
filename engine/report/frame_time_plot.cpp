// The frame-time plot: µs per step for each timed part against the frame number, drawn into an
// osg::Image and written as PNG by osgDB's image writer plugin. Colours, scale and layout are
// documented in frame_record.h. Pixels are addressed y-up (row 0 is the bottom row, as in
// osg::Image; the PNG plugin flips rows on writing and reading); the canvas and font are canvas.h's.
#include "nestwalk/report/frame_time_plot.h"

#include "nestwalk/core/statistics.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/report/canvas.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>

namespace nestwalk {
namespace {

// Colours (the legend and frame_record.h name them).
constexpr Rgb kBackground{255, 255, 255};
constexpr Rgb kInk{0, 0, 0};          // axes, ticks, text
constexpr Rgb kGrid{224, 224, 224};   // decade and frame grid lines
constexpr Rgb kPartColour[kStepParts] = {
    {44, 160, 44},   // ground: green
    {31, 119, 180},  // broad: blue
    {255, 127, 14},  // narrow: orange
    {214, 39, 40},   // total: red
};
constexpr Rgb kRenderColour{227, 119, 194};  // rendering (run --render): pink, rendered frames only
constexpr Rgb kP50Colour{148, 103, 189};  // p50 of total: purple, dashed
constexpr Rgb kP99Colour{140, 86, 75};    // p99 of total: brown, dashed

// Layout, pixels. The left margin holds y labels up to 7 glyphs ("0.00001"), the top margin the
// legend, the bottom margin the frame labels.
constexpr int kLeftMargin = 8 * kGlyphAdvance + 8;
constexpr int kRightMargin = 16;
constexpr int kTopMargin = 2 * kGlyphHeight + 12;
constexpr int kBottomMargin = 2 * kGlyphHeight + 14;  // tick labels, then "FRAME" below them
constexpr int kTickLength = 4;
constexpr int kDataInset = 3;  // data starts this far inside the axes, so the axes never hide it
constexpr int kDashOn = 6, kDashOff = 4;  // percentile lines


// Below this the log axis stops (a part that took 0 µs, e.g. with timing off, sits on the floor).
constexpr double kFloorMicros = 1e-3;
constexpr int kFrameTicksWanted = 8;

/// Label of the decade 10^k: plain decimals from 0.00001 to 1000000, "1E-9" style beyond.
std::string decadeLabel(int k) {
  if (k >= 0 && k <= 6) return "1" + std::string(std::size_t(k), '0');
  if (k < 0 && k >= -5) return "0." + std::string(std::size_t(-k - 1), '0') + "1";
  return "1E" + std::to_string(k);
}

/// A 1-2-5 step giving about `wanted` intervals over `span`.
std::uint64_t niceStep(std::uint64_t span, int wanted) {
  std::uint64_t step = 1;
  for (;;) {
    for (std::uint64_t m : {1ull, 2ull, 5ull})
      if (span / (step * m) <= std::uint64_t(wanted)) return step * m;
    step *= 10;
  }
}

}  // namespace

void writeFrameTimePlot(const std::string& path, const std::vector<FrameRecord>& records,
                        std::span<const RenderRecord> renders, int width, int height) {
  if (width < kMinFrameTimePlotWidth || height < kMinFrameTimePlotHeight)
    throw InputError(path + ": frame-time plot of " + std::to_string(width) + " x " + std::to_string(height) +
                     " pixels is too small (at least " + std::to_string(kMinFrameTimePlotWidth) + " x " +
                     std::to_string(kMinFrameTimePlotHeight) + ")");
  Canvas canvas(width, height, kBackground);
  const int px0 = kLeftMargin, px1 = width - 1 - kRightMargin;   // plot area, columns
  const int py0 = kBottomMargin, py1 = height - 1 - kTopMargin;  // plot area, rows (y up)

  // Log10 y axis over whole decades holding every positive time (at least one decade).
  double lo = HUGE_VAL, hi = 0;
  bool rendered = false;
  auto cover = [&](double us) {
    if (us > 0 && std::isfinite(us)) {
      lo = std::min(lo, std::max(us, kFloorMicros));
      hi = std::max(hi, us);
    }
  };
  for (const FrameRecord& r : records)
    for (double us : r.micros) cover(us);
  for (const RenderRecord& r : renders)
    if (r.rendered) {
      rendered = true;
      cover(r.micros[RenderPart::Total]);
    }
  int kLo = 0, kHi = 1;
  if (hi > 0) {
    kLo = int(std::floor(std::log10(lo)));
    kHi = std::max(kLo + 1, int(std::ceil(std::log10(hi))));
  }
  auto yOf = [&](double us) {
    const double l = us > 0 && std::isfinite(us) ? std::clamp(std::log10(us), double(kLo), double(kHi)) : double(kLo);
    return py0 + kDataInset + int(std::lround((l - kLo) / (kHi - kLo) * (py1 - py0 - kDataInset)));
  };

  // x: frame numbers from the first record's to the last's.
  const std::uint64_t f0 = records.empty() ? 0 : records.front().frame;
  const std::uint64_t f1 = records.empty() ? 0 : std::max(records.back().frame, f0);
  auto xOf = [&](std::uint64_t f) {
    if (f1 == f0) return (px0 + px1) / 2;
    return px0 + kDataInset + int(std::lround(double(f - f0) / double(f1 - f0) * (px1 - px0 - kDataInset)));
  };

  // Grid and axis labels.
  for (int k = kLo; k <= kHi; ++k) {
    const int y = yOf(std::pow(10.0, k));
    canvas.line(px0, y, px1, y, kGrid);
    canvas.line(px0 - kTickLength, y, px0, y, kInk);
    const std::string label = decadeLabel(k);
    canvas.text(px0 - kTickLength - 3 - textWidth(label), y + kGlyphHeight / 2, label, kInk);
  }
  if (!records.empty()) {
    const std::uint64_t step = niceStep(f1 - f0, kFrameTicksWanted);
    for (std::uint64_t f = (f0 + step - 1) / step * step; f <= f1; f += step) {
      const int x = xOf(f);
      canvas.line(x, py0, x, py1, kGrid);
      canvas.line(x, py0 - kTickLength, x, py0, kInk);
      const std::string label = std::to_string(f);
      canvas.text(std::clamp(x - textWidth(label) / 2, 0, width - textWidth(label) - 1), py0 - kTickLength - 3, label,
                  kInk);
    }
  }

  // The parts, total first so that the parts it contains are drawn over it.
  for (StepPart part : {StepPart::Total, StepPart::Narrow, StepPart::BroadPhase, StepPart::Ground}) {
    const Rgb c = kPartColour[std::size_t(part)];
    for (std::size_t i = 0; i < records.size(); ++i) {
      const int x = xOf(records[i].frame), y = yOf(records[i].micros[part]);
      if (i == 0) {
        canvas.set(x, y, c);
      } else {
        canvas.line(xOf(records[i - 1].frame), yOf(records[i - 1].micros[part]), x, y, c);
      }
    }
  }
  // Rendering, through the rendered frames only.
  std::optional<std::size_t> previous;
  for (std::size_t i = 0; i < renders.size(); ++i) {
    if (!renders[i].rendered) continue;
    const int x = xOf(records[i].frame), y = yOf(renders[i].micros[RenderPart::Total]);
    if (previous) {
      canvas.line(xOf(records[*previous].frame), yOf(renders[*previous].micros[RenderPart::Total]), x, y,
                  kRenderColour);
    } else {
      canvas.set(x, y, kRenderColour);
    }
    previous = i;
  }
  if (!records.empty()) {
    std::vector<double> total;
    total.reserve(records.size());
    for (const FrameRecord& r : records) total.push_back(r.micros[StepPart::Total]);
    canvas.dashedHLine(px0, px1, yOf(percentile(total, 50)), kP50Colour, kDashOn, kDashOff);
    canvas.dashedHLine(px0, px1, yOf(percentile(total, 99)), kP99Colour, kDashOn, kDashOff);
  } else {
    canvas.text((px0 + px1 - textWidth("NO FRAMES")) / 2, (py0 + py1) / 2, "NO FRAMES", kInk);
  }

  // Axes, and the legend and units above the plot.
  canvas.line(px0, py0, px1, py0, kInk);
  canvas.line(px0, py0, px0, py1, kInk);
  canvas.text(px1 - textWidth("FRAME"), py0 - kTickLength - 3 - kGlyphHeight - 3, "FRAME", kInk);
  const int legendTop = height - 1 - 4;
  canvas.text(4, legendTop, "US (LOG)", kInk);
  struct Entry {
    const char* name;
    Rgb colour;
    bool dashed;
  };
  std::vector<Entry> entries = {{"GROUND", kPartColour[0], false}, {"BROAD", kPartColour[1], false},
                                {"NARROW", kPartColour[2], false}, {"TOTAL", kPartColour[3], false},
                                {"P50", kP50Colour, true},         {"P99", kP99Colour, true}};
  if (rendered) entries.push_back({"RENDER", kRenderColour, false});
  int x = px0 + 8;
  constexpr int kSwatch = 16;
  for (const Entry& e : entries) {
    const int y = legendTop - kGlyphHeight / 2;
    if (e.dashed) {
      canvas.dashedHLine(x, x + kSwatch - 1, y, e.colour, kDashOn, kDashOff);
    } else {
      canvas.fill(x, y - 1, x + kSwatch - 1, y + 1, e.colour);
    }
    canvas.text(x + kSwatch + 4, legendTop, e.name, kInk);
    x += kSwatch + 4 + textWidth(e.name) + 14;
  }

  writePng(canvas, path);
}

}  // namespace nestwalk
