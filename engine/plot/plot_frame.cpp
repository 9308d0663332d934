// A plot's axes, title and legend (plot_frame.h).
#include "nestwalk/plot/plot_frame.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace nestwalk {
namespace {

constexpr double kAxisWidth = 1, kGridWidth = 1;  // pixels
constexpr double kLabelSpacing = 6;   // least gap between two tick labels, pixels
constexpr double kSwatchWidth = 18;   // legend swatch, pixels
constexpr double kSwatchGap = 5;      // swatch to name
constexpr double kEntryGap = 16;      // name to the next swatch
constexpr double kLineGap = 6;        // between the header's lines

/// The nearest pixel centre (n + 0.5) at or above / at or below v.
double centreAtOrAbove(double v) { return std::ceil(v - 0.5) + 0.5; }
double centreAtOrBelow(double v) { return std::floor(v - 0.5) + 0.5; }

/// The height of a line of text: the font's ascent plus descent.
double lineHeight(double size) {
  const DrawingSurface::FontMetrics m = DrawingSurface::fontMetrics(size);
  return m.ascent + m.descent;
}

void drawSwatch(DrawingSurface& s, const LegendEntry& e, double x, double middle) {
  const double y = std::floor(middle) + 0.5;  // a pixel centre: one-pixel lines stay crisp
  switch (e.swatch) {
    case Swatch::Line: s.line({x, y}, {x + kSwatchWidth, y}, e.width, e.colour); break;
    case Swatch::DashedLine: s.line({x, y}, {x + kSwatchWidth, y}, e.width, e.colour, kPlotDash); break;
    case Swatch::Box: s.fillRect(x + 2, std::floor(middle) - 4, x + kSwatchWidth - 2, std::floor(middle) + 5, e.colour); break;
    case Swatch::Disc: s.disc({x + kSwatchWidth / 2, middle}, 4, e.colour); break;
  }
}

}  // namespace

PlotArea PlotArea::inside(double left, double bottom, double right, double top) {
  PlotArea a{centreAtOrAbove(left), centreAtOrAbove(bottom), centreAtOrBelow(right), centreAtOrBelow(top)};
  a.right = std::max(a.right, a.left + kPlotDataInset + 1);
  a.top = std::max(a.top, a.bottom + kPlotDataInset + 1);
  return a;
}

double yTickMargin(const Axis& y) {
  double widest = 0;
  for (const AxisTick& t : y.ticks()) widest = std::max(widest, DrawingSurface::textWidth(t.label, kTickFontSize));
  return kTickLength + kTickLabelGap + widest;
}

double xTickMargin() { return kTickLength + kTickLabelGap + lineHeight(kTickFontSize); }

void drawAxes(DrawingSurface& s, const PlotArea& area, const Axis* x, const Axis& y) {
  const TextStyle label{.size = kTickFontSize, .colour = kPlotInk};
  // Grid lines first, under everything, at pixel centres so that they are crisp.
  if (x)
    for (const AxisTick& t : x->ticks()) {
      const double px = std::floor(area.x(*x, t.value)) + 0.5;
      s.line({px, area.bottom}, {px, area.top}, kGridWidth, kPlotGrid);
    }
  for (const AxisTick& t : y.ticks()) {
    const double py = std::floor(area.y(y, t.value)) + 0.5;
    s.line({area.left, py}, {area.right, py}, kGridWidth, kPlotGrid);
  }
  // Ticks and labels.
  if (x) {
    std::optional<TextBox> previous;
    for (const AxisTick& t : x->ticks()) {
      const double px = std::floor(area.x(*x, t.value)) + 0.5;
      s.line({px, area.bottom}, {px, area.bottom - kTickLength}, kAxisWidth, kPlotInk);
      TextStyle st = label;
      st.h = HAlign::Centre;
      st.v = VAlign::Top;
      Point anchor{px, area.bottom - kTickLength - kTickLabelGap};
      TextBox box = DrawingSurface::textBox(anchor, t.label, st);
      const double shift = std::max(0.0, kPlotPadding - box.left) - std::max(0.0, box.right - (s.width() - kPlotPadding));
      anchor.x() += shift;
      box.left += shift, box.right += shift;
      if (previous && box.left < previous->right + kLabelSpacing) continue;
      s.text(anchor, t.label, st);
      previous = box;
    }
  }
  std::optional<TextBox> previous;
  for (const AxisTick& t : y.ticks()) {
    const double py = std::floor(area.y(y, t.value)) + 0.5;
    s.line({area.left, py}, {area.left - kTickLength, py}, kAxisWidth, kPlotInk);
    TextStyle st = label;
    st.h = HAlign::Right;
    st.v = VAlign::Middle;
    const Point anchor{area.left - kTickLength - kTickLabelGap, py};
    const TextBox box = DrawingSurface::textBox(anchor, t.label, st);
    if (previous && box.bottom < previous->top + kLabelSpacing / 3 && previous->bottom < box.top) continue;
    s.text(anchor, t.label, st);
    previous = box;
  }
}

void drawAxisLines(DrawingSurface& s, const PlotArea& area) {
  // Square ends, so that the corner pixel and the end pixels are covered entirely.
  s.line({area.left, area.bottom}, {area.right, area.bottom}, kAxisWidth, kPlotInk, {}, true);
  s.line({area.left, area.bottom}, {area.left, area.top}, kAxisWidth, kPlotInk, {}, true);
}

PlotHeader::PlotHeader(std::string title, std::vector<LegendEntry> entries, double left, double right)
    : title_(std::move(title)), left_(left) {
  double x = left;
  for (LegendEntry& e : entries) {
    if (e.name.empty()) continue;
    const double w = kSwatchWidth + kSwatchGap + DrawingSurface::textWidth(e.name, kTickFontSize);
    if (x > left && x + w > right) {
      x = left;
      ++lines_;
    }
    placed_.push_back({std::move(e), x, lines_});
    x += w + kEntryGap;
  }
  if (!placed_.empty()) ++lines_;
}

double PlotHeader::height() const {
  return lineHeight(kTitleFontSize) + lines_ * (kLineGap + lineHeight(kTickFontSize));
}

void PlotHeader::draw(DrawingSurface& s, double top) const {
  s.text({left_, top}, title_, {.size = kTitleFontSize, .colour = kPlotInk, .v = VAlign::Top});
  const DrawingSurface::FontMetrics m = DrawingSurface::fontMetrics(kTickFontSize);
  const double first = top - lineHeight(kTitleFontSize) - kLineGap, step = kLineGap + lineHeight(kTickFontSize);
  for (const Placed& p : placed_) {
    // The swatch and the name's capitals share their middle.
    const double middle = first - p.line * step - m.ascent + m.capHeight / 2;
    drawSwatch(s, p.entry, p.x, middle);
    s.text({p.x + kSwatchWidth + kSwatchGap, middle}, p.entry.name,
           {.size = kTickFontSize, .colour = kPlotInk, .v = VAlign::Middle});
  }
}

}  // namespace nestwalk
