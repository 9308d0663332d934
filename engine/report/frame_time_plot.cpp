// The frame-time plot (frame_time_plot.h): µs per step for each timed part against the frame
// number, on the drawing surface (drawing_surface.h) with the shared axes and header
// (plot_frame.h), written as PNG.
#include "nestwalk/report/frame_time_plot.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/core/statistics.h"
#include "nestwalk/plot/axis.h"
#include "nestwalk/plot/drawing_surface.h"
#include "nestwalk/plot/plot_frame.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace nestwalk {
namespace {

// Colours (frame_time_plot.h names them).
constexpr Rgb kPartColour[kStepParts] = {
    {44, 160, 44},   // ground: green
    {31, 119, 180},  // broad: blue
    {255, 127, 14},  // narrow: orange
    {214, 39, 40},   // total: red
};
constexpr Rgb kRenderColour{227, 119, 194};  // rendering (run --render): pink, rendered frames only
constexpr Rgb kP50Colour{148, 103, 189};     // p50 of total: purple, dashed
constexpr Rgb kP99Colour{140, 86, 75};       // p99 of total: brown, dashed

constexpr double kPercentileWidth = 1;  // pixels
constexpr double kPixelsPerXTick = 110;   // about one frame tick per this many pixels of the x axis
constexpr double kPixelsPerYTick = 40;
constexpr double kRightRoom = 4;   // between the plot area and the image's padding, pixels
constexpr double kHeaderGap = 8;   // between the header and the plot area, pixels
constexpr double kLeastPlotHeight = 60;  // below this the legend is left out, pixels
constexpr const char* kTitle = "walker step time per frame";

}  // namespace

void writeFrameTimePlot(const std::string& path, const std::vector<FrameRecord>& records,
                        std::span<const RenderRecord> renders, int width, int height) {
  if (width < kMinFrameTimePlotWidth || height < kMinFrameTimePlotHeight)
    throw InputError(path + ": frame-time plot of " + std::to_string(width) + " x " + std::to_string(height) +
                     " pixels is too small (at least " + std::to_string(kMinFrameTimePlotWidth) + " x " +
                     std::to_string(kMinFrameTimePlotHeight) + ")");
  DrawingSurface s(width, height, kPlotPaper);

  // The axes over the data.
  std::vector<double> times, frames;
  bool rendered = false;
  for (const FrameRecord& r : records) {
    frames.push_back(double(r.frame));
    for (double us : r.micros) times.push_back(us);
  }
  for (const RenderRecord& r : renders)
    if (r.rendered) {
      rendered = true;
      times.push_back(r.micros[RenderPart::Total]);
    }
  const int yTicks = std::max(3, int(height / kPixelsPerYTick));
  const Axis ay = Axis::fit(times, {.scale = AxisScale::Log10, .logFloor = kFrameTimeFloorMicros,
                                    .maxTicks = std::min(yTicks, 10), .unit = "µs"});
  if (frames.size() == 1) frames = {frames[0] - 1, frames[0] + 1};  // a single record in the middle
  const Axis ax = Axis::fit(frames, {.tight = true, .maxTicks = std::max(3, int(width / kPixelsPerXTick)), .minStep = 1});

  // Layout: the header at the top, the frame axis title under the tick labels.
  std::vector<LegendEntry> legend = {{"ground", kPartColour[0], Swatch::Line},
                                     {"broad phase", kPartColour[1], Swatch::Line},
                                     {"narrow phase", kPartColour[2], Swatch::Line},
                                     {"step total", kPartColour[3], Swatch::Line},
                                     {"p50 of total", kP50Colour, Swatch::DashedLine, kPercentileWidth},
                                     {"p99 of total", kP99Colour, Swatch::DashedLine, kPercentileWidth}};
  if (rendered) legend.push_back({"render", kRenderColour, Swatch::Line});
  const DrawingSurface::FontMetrics font = DrawingSurface::fontMetrics(kTickFontSize);
  const double titleRow = font.ascent + font.descent;
  const double bottom = kPlotPadding + titleRow + xTickMargin();
  // The legend is left out where it would leave the plot too low (small images).
  PlotHeader header(kTitle, legend, kPlotPadding, width - kPlotPadding);
  if (height - kPlotPadding - header.height() - kHeaderGap - bottom < kLeastPlotHeight)
    header = PlotHeader(kTitle, {}, kPlotPadding, width - kPlotPadding);
  const PlotArea area = PlotArea::inside(kPlotPadding + yTickMargin(ay), bottom, width - kPlotPadding - kRightRoom,
                                         height - kPlotPadding - header.height() - kHeaderGap);

  drawAxes(s, area, &ax, ay);
  s.text({area.right, kPlotPadding}, "frame", {.size = kTickFontSize, .colour = kPlotInk, .h = HAlign::Right, .v = VAlign::Bottom});
  header.draw(s, height - kPlotPadding);

  // The series, clipped to the plot area; total first so that the parts it contains lie over it.
  s.clip(area.left, area.bottom - kFrameTimeLineWidth, area.right + kFrameTimeLineWidth, area.top + kFrameTimeLineWidth);
  std::vector<Point> points;
  for (StepPart part : {StepPart::Total, StepPart::Narrow, StepPart::BroadPhase, StepPart::Ground}) {
    points.clear();
    for (const FrameRecord& r : records) points.push_back({area.x(ax, double(r.frame)), area.y(ay, r.micros[part])});
    s.polyline(points, kFrameTimeLineWidth, kPartColour[std::size_t(part)]);
  }
  points.clear();
  for (std::size_t i = 0; i < renders.size() && i < records.size(); ++i)
    if (renders[i].rendered)
      points.push_back({area.x(ax, double(records[i].frame)), area.y(ay, renders[i].micros[RenderPart::Total])});
  s.polyline(points, kFrameTimeLineWidth, kRenderColour);
  s.resetClip();

  if (!records.empty()) {
    std::vector<double> total;
    total.reserve(records.size());
    for (const FrameRecord& r : records) total.push_back(r.micros[StepPart::Total]);
    for (const auto& [p, colour] : {std::pair{50.0, kP50Colour}, std::pair{99.0, kP99Colour}}) {
      const double y = std::floor(area.y(ay, percentile(total, p))) + 0.5;  // a pixel row: crisp
      s.line({area.left, y}, {area.right, y}, kPercentileWidth, colour, kPlotDash);
    }
  } else {
    s.text({(area.left + area.right) / 2, (area.bottom + area.top) / 2}, "no frames",
           {.size = kTitleFontSize, .colour = kPlotInk, .h = HAlign::Centre, .v = VAlign::Middle});
  }
  drawAxisLines(s, area);
  s.writePng(path);
}

}  // namespace nestwalk
