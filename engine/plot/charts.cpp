// The methods report's scatter and bar plots (charts.h) on the drawing surface, with the
// shared axes, title and legend (plot_frame.h).
#include "nestwalk/plot/charts.h"

#include "nestwalk/plot/axis.h"
#include "nestwalk/core/number_text.h"
#include "nestwalk/plot/plot_frame.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace nestwalk {
namespace {

constexpr double kLabelFontSize = 11;     // point labels and bar values, pixels per em
constexpr double kLabelOffset = 4;        // between a marker's rim and its label, pixels
constexpr int kLabelShifts = 12;          // lines up and down a point label may move
constexpr double kPixelsPerTick = 50;     // at most one tick per this many pixels of an axis
constexpr double kRowGap = 6;             // between the header, the y title and the plot, pixels
constexpr double kRightRoom = 16;         // right of the plot area, pixels
constexpr double kBarFill = 0.75;         // share of a group's slot its bars fill

Axis fitAxis(const std::vector<double>& values, const PlotAxis& spec, double pixels) {
  return Axis::fit(values, {.scale = spec.log ? AxisScale::Log10 : AxisScale::Linear,
                            .logFloor = spec.floor,
                            .includeZero = !spec.log,
                            .maxTicks = std::clamp(int(pixels / kPixelsPerTick), 3, 10),
                            .unit = spec.unit});
}

std::string axisTitle(const PlotAxis& spec) { return spec.title + (spec.log ? " (log)" : ""); }

double textRow(double size) {
  const DrawingSurface::FontMetrics m = DrawingSurface::fontMetrics(size);
  return m.ascent + m.descent;
}

/// The plot area of an image: the header above, the y axis's title row, the x tick labels and the
/// x axis's title row below. The y axis is fitted to the area's height (its labels set the left
/// margin), so it is fitted here too.
struct Layout {
  PlotArea area;
  Axis y;
};
Layout layout(int width, int height, const PlotHeader& header, const std::vector<double>& ys, const PlotAxis& ySpec) {
  const double top = height - kPlotPadding - header.height() - kRowGap - textRow(kTickFontSize) - kRowGap;
  const double bottom = kPlotPadding + textRow(kTickFontSize) + xTickMargin();
  const Axis y = fitAxis(ys, ySpec, top - bottom);
  return {PlotArea::inside(kPlotPadding + yTickMargin(y), bottom, width - kRightRoom, top), y};
}

void drawTitles(DrawingSurface& s, const PlotArea& area, const std::string& xTitle, const std::string& yTitle) {
  if (!xTitle.empty())
    s.text({area.right, kPlotPadding}, xTitle, {.size = kTickFontSize, .colour = kPlotInk, .h = HAlign::Right, .v = VAlign::Bottom});
  s.text({kPlotPadding, area.top + kRowGap}, yTitle, {.size = kTickFontSize, .colour = kPlotInk, .v = VAlign::Bottom});
}

/// Boxes already drawn on (markers, labels), so that point labels do not cover each other.
class LabelPlacer {
 public:
  LabelPlacer(int width, int height) : width_(width), height_(height) {}
  void occupy(const TextBox& b) { boxes_.push_back(b); }
  /// Where a label of the point p (a marker of `radius`) goes: right of it, else left, moving a
  /// line up or down at a time; the chosen box is occupied from then on.
  std::pair<Point, TextStyle> place(Point p, double radius, const std::string& text) {
    const double line = textRow(kLabelFontSize);
    TextStyle style{.size = kLabelFontSize, .colour = kPlotInk, .v = VAlign::Middle};
    for (int shift = 0; shift <= 2 * kLabelShifts; ++shift) {
      const double dy = (shift % 2 ? 1 : -1) * ((shift + 1) / 2) * line;
      for (HAlign side : {HAlign::Left, HAlign::Right}) {
        style.h = side;
        const Point anchor{p.x() + (side == HAlign::Left ? 1 : -1) * (radius + kLabelOffset), p.y() + dy};
        const TextBox b = DrawingSurface::textBox(anchor, text, style);
        if (b.left < kPlotPadding || b.right > width_ - kPlotPadding || b.bottom < kPlotPadding || b.top > height_ - kPlotPadding)
          continue;
        if (std::none_of(boxes_.begin(), boxes_.end(), [&](const TextBox& o) { return o.overlaps(b); })) {
          boxes_.push_back(b);
          return {anchor, style};
        }
      }
    }
    style.h = HAlign::Left;
    return {{p.x() + radius + kLabelOffset, p.y()}, style};
  }

 private:
  int width_, height_;
  std::vector<TextBox> boxes_;
};

}  // namespace

void writeScatterPlot(const std::string& path, const std::string& title, const PlotAxis& x, const PlotAxis& y,
                      const std::vector<PlotSeries>& series, int width, int height) {
  DrawingSurface s(width, height, kPlotPaper);
  std::vector<double> xs, ys;
  std::vector<LegendEntry> legend;
  for (const PlotSeries& ser : series) {
    legend.push_back({ser.name, ser.colour, ser.markers ? Swatch::Disc : Swatch::Line, kPlotSeriesWidth});
    for (const PlotPoint& p : ser.points) {
      xs.push_back(p.x);
      ys.push_back(p.y);
    }
  }
  const PlotHeader header(title, legend, kPlotPadding, width - kPlotPadding);
  const Layout l = layout(width, height, header, ys, y);
  const PlotArea& area = l.area;
  const Axis ax = fitAxis(xs, x, area.right - area.left);
  drawAxes(s, area, &ax, l.y);
  drawTitles(s, area, axisTitle(x), axisTitle(y));
  header.draw(s, height - kPlotPadding);

  LabelPlacer placer(width, height);
  auto at = [&](const PlotPoint& p) { return Point{area.x(ax, p.x), area.y(l.y, p.y)}; };
  for (const PlotSeries& ser : series) {
    if (ser.connect && ser.points.size() > 1) {
      std::vector<Point> line;
      for (const PlotPoint& p : ser.points) line.push_back(at(p));
      s.polyline(line, kPlotSeriesWidth, ser.colour);
    }
    if (!ser.markers) continue;
    for (const PlotPoint& p : ser.points) {
      const Point c = at(p);
      s.disc(c, kPlotMarkerRadius, ser.colour);
      placer.occupy({c.x() - kPlotMarkerRadius, c.y() - kPlotMarkerRadius, c.x() + kPlotMarkerRadius, c.y() + kPlotMarkerRadius});
    }
  }
  for (const PlotSeries& ser : series)
    for (const PlotPoint& p : ser.points) {
      if (p.label.empty()) continue;
      const auto [anchor, style] = placer.place(at(p), ser.markers ? kPlotMarkerRadius : 0, p.label);
      s.text(anchor, p.label, style);
    }
  drawAxisLines(s, area);
  s.writePng(path);
}

void writeBarPlot(const std::string& path, const std::string& title,
                  const std::vector<std::pair<std::string, Rgb>>& series, const PlotAxis& y,
                  const std::vector<PlotBarGroup>& groups, int width, int height) {
  DrawingSurface s(width, height, kPlotPaper);
  std::vector<double> values;
  for (const PlotBarGroup& g : groups) values.insert(values.end(), g.values.begin(), g.values.end());
  std::vector<LegendEntry> legend;
  for (const auto& [name, colour] : series) legend.push_back({name, colour, Swatch::Box});
  const PlotHeader header(title, legend, kPlotPadding, width - kPlotPadding);
  const Layout l = layout(width, height, header, values, y);
  const PlotArea& area = l.area;
  drawAxes(s, area, nullptr, l.y);
  drawTitles(s, area, "", axisTitle(y));
  header.draw(s, height - kPlotPadding);

  const double slot = (area.right - area.left) / double(std::max<std::size_t>(1, groups.size()));
  const int bars = std::max<int>(1, int(series.size()));
  const double bar = std::max(3.0, std::floor(slot * kBarFill / bars));
  const TextStyle groupStyle{.size = kTickFontSize, .colour = kPlotInk, .h = HAlign::Centre, .v = VAlign::Top};
  TextStyle valueStyle{.size = kLabelFontSize, .colour = kPlotInk, .h = HAlign::Centre, .v = VAlign::Bottom};
  for (std::size_t i = 0; i < groups.size(); ++i) {
    const PlotBarGroup& g = groups[i];
    const double left = std::round(area.left + double(i) * slot + (slot - bar * bars) / 2);
    s.text({left + bar * bars / 2, area.bottom - kTickLength - kTickLabelGap}, g.label, groupStyle);
    std::optional<TextBox> previous;
    for (std::size_t k = 0; k < g.values.size() && k < series.size(); ++k) {
      const double v = g.values[k];
      if (!std::isfinite(v)) continue;
      const double x0 = left + double(k) * bar, top = area.y(l.y, v);
      s.fillRect(x0 + 1, area.bottom + 0.5, x0 + bar - 1, std::max(top, area.bottom + 0.5), series[k].second);
      const std::string text = fixedText(v, std::abs(v) < 10 ? 2 : std::abs(v) < 100 ? 1 : 0);
      Point anchor{x0 + bar / 2, top + 2};
      TextBox box = DrawingSurface::textBox(anchor, text, valueStyle);
      if (previous && box.overlaps(*previous)) {
        anchor.y() = previous->top + 1;
        box = DrawingSurface::textBox(anchor, text, valueStyle);
      }
      s.text(anchor, text, valueStyle);
      previous = box;
    }
  }
  drawAxisLines(s, area);
  s.writePng(path);
}

}  // namespace nestwalk
