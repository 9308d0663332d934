// The methods report's scatter and bar plots (report_plot.h) on the project's canvas (canvas.h):
// pixels y-up, 5x7 font, PNG through osgDB.
#include "nestwalk/report/report_plot.h"

#include "nestwalk/report/number_text.h"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace nestwalk {
namespace {

constexpr Rgb kBackground{255, 255, 255};
constexpr Rgb kInk{0, 0, 0};
constexpr Rgb kGrid{224, 224, 224};
constexpr int kTick = 4;
constexpr int kLeft = 11 * kGlyphAdvance + 12;  // tick labels up to 9 glyphs, the axis title
constexpr int kRight = 24;
constexpr int kTop = 3 * (kGlyphHeight + 6) + 8;    // title, legend
constexpr int kBottom = 2 * (kGlyphHeight + 6) + 10;  // tick labels, axis title
constexpr int kInset = 12;                          // data starts this far inside the axes
constexpr double kMarker = 4.0;

std::string upper(std::string s) {
  for (char& c : s) c = char(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

/// The tick mantissas of a log axis: whole decades, 1-2-5 within less than a decade of data, 1..9
/// within less than half of one.
std::vector<double> mantissas(double decades) {
  if (decades >= 1) return {1};
  if (decades >= 0.5) return {1, 2, 5};
  return {1, 2, 3, 4, 5, 6, 7, 8, 9};
}

/// One axis: where values go in pixels, and its ticks.
struct Axis {
  bool log = false;
  double lo = 0, hi = 1;  // axis units (log10 of the value on a log axis)
  double step = 1;        // linear: between ticks
  std::vector<double> marks = {1};  // log: tick mantissas
  int p0 = 0, p1 = 1;     // pixels of lo and hi

  static Axis fit(const std::vector<double>& values, const PlotAxis& spec, int p0, int p1) {
    Axis a;
    a.log = spec.log;
    a.p0 = p0;
    a.p1 = p1;
    double mn = HUGE_VAL, mx = -HUGE_VAL;
    for (double v : values)
      if (std::isfinite(v) && (!a.log || v > 0)) {
        const double u = a.log ? std::log10(std::max(v, spec.floor)) : v;
        mn = std::min(mn, u);
        mx = std::max(mx, u);
      }
    if (mn > mx) mn = mx = 0;
    if (a.log) {
      // The widest tick values at or below the least value and at or above the largest.
      a.marks = mantissas(mx - mn);
      const double k = std::floor(mn);
      a.lo = k;
      for (double m : a.marks)
        if (k + std::log10(m) <= mn + 1e-12) a.lo = k + std::log10(m);
      a.hi = std::ceil(mx);
      for (auto it = a.marks.rbegin(); it != a.marks.rend(); ++it)
        if (std::floor(mx) + std::log10(*it) >= mx - 1e-12) a.hi = std::floor(mx) + std::log10(*it);
      if (a.hi <= a.lo) a.hi = a.lo + 1;
      return a;
    }
    mn = std::min(mn, 0.0);
    const double span = mx > mn ? mx - mn : std::max(std::abs(mx), 1.0);
    const double decade = std::pow(10.0, std::floor(std::log10(span / 6)));
    a.step = decade;
    for (double m : {1.0, 2.0, 5.0, 10.0})
      if (span / (decade * m) <= 6) {
        a.step = decade * m;
        break;
      }
    a.lo = std::floor(mn / a.step) * a.step;
    a.hi = std::max(a.lo + a.step, std::ceil(mx / a.step) * a.step);
    return a;
  }
  /// The pixel of a value; values off the axis (and <= 0 on a log axis) are clamped to its ends.
  int pixel(double v) const {
    const double u = log ? (v > 0 ? std::log10(v) : lo) : v;
    const double f = std::isfinite(u) ? std::clamp((u - lo) / (hi - lo), 0.0, 1.0) : 0.0;
    return p0 + kInset + int(std::lround(f * (p1 - p0 - kInset)));
  }
  /// Tick values and their labels.
  std::vector<std::pair<double, std::string>> ticks() const {
    std::vector<std::pair<double, std::string>> out;
    if (log) {
      for (int k = int(std::floor(lo)); k <= int(std::ceil(hi)); ++k)
        for (double m : marks) {
          const double u = k + std::log10(m);
          if (u < lo - 1e-9 || u > hi + 1e-9) continue;
          const double v = m * std::pow(10.0, k);
          out.emplace_back(v, k < -6 ? fixedText(m, 0) + "E" + std::to_string(k) : fixedText(v, std::max(0, -k)));
        }
      return out;
    }
    const int decimals = std::max(0, int(std::ceil(-std::log10(step) - 1e-9)));
    for (double u = lo; u <= hi + 1e-9 * step; u += step)
      out.emplace_back(u, fixedText(std::abs(u) < 1e-9 * step ? 0.0 : u, decimals));
    return out;
  }
};

/// Rectangles already drawn on (markers, labels), so that labels do not cover each other.
struct Occupied {
  struct Box {
    int x0, y0, x1, y1;
  };
  std::vector<Box> boxes;
  bool free(const Box& b) const {
    for (const Box& o : boxes)
      if (b.x0 <= o.x1 && o.x0 <= b.x1 && b.y0 <= o.y1 && o.y0 <= b.y1) return false;
    return true;
  }
  /// A place for a label of `w` pixels beside the point (px, py): right of it, else left, moving
  /// down a line at a time (up to the bottom of the canvas) until it covers nothing drawn yet.
  /// Returns the label's left and top.
  std::pair<int, int> place(int px, int py, int w, int canvasWidth) {
    const int line = kGlyphHeight + 3;
    for (int shift = 0; shift < 12; ++shift)
      for (int side : {1, -1}) {
        const int x = side > 0 ? px + 8 : px - 8 - w;
        const int top = py + kGlyphHeight / 2 + (shift % 2 ? -1 : 1) * ((shift + 1) / 2) * line;
        const Box b{x - 1, top - kGlyphHeight - 1, x + w + 1, top + 1};
        if (x >= 0 && x + w < canvasWidth && free(b)) {
          boxes.push_back(b);
          return {x, top};
        }
      }
    return {px + 8, py + kGlyphHeight / 2};
  }
};

/// Title at the top left, then the legend's entries on the line below.
void drawHeader(Canvas& c, const std::string& title, const std::vector<std::pair<std::string, Rgb>>& legend) {
  const int top = c.height() - 1 - 6;
  c.text(kLeft, top, upper(title), kInk);
  int x = kLeft;
  const int legendTop = top - kGlyphHeight - 8;
  for (const auto& [name, colour] : legend) {
    if (name.empty()) continue;
    c.fill(x, legendTop - kGlyphHeight + 1, x + 11, legendTop - 1, colour);
    c.text(x + 16, legendTop, upper(name), kInk);
    x += 16 + textWidth(upper(name)) + 18;
  }
}

/// Grid lines, ticks and tick labels of both axes (of x only with xTicks), the axis lines and titles.
void drawAxes(Canvas& c, const Axis& ax, const Axis& ay, const std::string& xTitle, const std::string& yTitle,
              bool xTicks = true) {
  for (const auto& [v, label] : xTicks ? ax.ticks() : std::vector<std::pair<double, std::string>>{}) {
    const int x = ax.pixel(v);
    c.line(x, ay.p0, x, ay.p1, kGrid);
    c.line(x, ay.p0 - kTick, x, ay.p0, kInk);
    c.text(x - textWidth(label) / 2, ay.p0 - kTick - 3, label, kInk);
  }
  for (const auto& [v, label] : ay.ticks()) {
    const int y = ay.pixel(v);
    c.line(ax.p0, y, ax.p1, y, kGrid);
    c.line(ax.p0 - kTick, y, ax.p0, y, kInk);
    c.text(ax.p0 - kTick - 3 - textWidth(label), y + kGlyphHeight / 2, label, kInk);
  }
  c.line(ax.p0, ay.p0, ax.p1, ay.p0, kInk);
  c.line(ax.p0, ay.p0, ax.p0, ay.p1, kInk);
  const std::string xt = upper(xTitle) + (ax.log ? " (LOG)" : ""), yt = upper(yTitle) + (ay.log ? " (LOG)" : "");
  c.text(ax.p1 - textWidth(xt), ay.p0 - kTick - 3 - kGlyphHeight - 6, xt, kInk);
  c.text(4, ay.p1 + kGlyphHeight + 6, yt, kInk);
}

}  // namespace

void writeScatterPlot(const std::string& path, const std::string& title, const PlotAxis& x, const PlotAxis& y,
                      const std::vector<PlotSeries>& series, int width, int height) {
  Canvas c(width, height, kBackground);
  std::vector<double> xs, ys;
  std::vector<std::pair<std::string, Rgb>> legend;
  for (const PlotSeries& s : series) {
    legend.emplace_back(s.name, s.colour);
    for (const PlotPoint& p : s.points) {
      xs.push_back(p.x);
      ys.push_back(p.y);
    }
  }
  const Axis ax = Axis::fit(xs, x, kLeft, width - 1 - kRight);
  const Axis ay = Axis::fit(ys, y, kBottom, height - 1 - kTop);
  drawAxes(c, ax, ay, x.title, y.title);
  Occupied occupied;
  for (const PlotSeries& s : series) {
    for (std::size_t i = 1; s.connect && i < s.points.size(); ++i)
      c.line(ax.pixel(s.points[i - 1].x), ay.pixel(s.points[i - 1].y), ax.pixel(s.points[i].x),
             ay.pixel(s.points[i].y), s.colour);
    for (const PlotPoint& p : s.points) {
      const int px = ax.pixel(p.x), py = ay.pixel(p.y), r = int(kMarker);
      if (!s.markers) continue;
      c.disc(px, py, kMarker, s.colour);
      occupied.boxes.push_back({px - r, py - r, px + r, py + r});
    }
  }
  for (const PlotSeries& s : series)
    for (const PlotPoint& p : s.points) {
      if (p.label.empty()) continue;
      const std::string label = upper(p.label);
      const auto [lx, top] = occupied.place(ax.pixel(p.x), ay.pixel(p.y), textWidth(label), width);
      c.text(lx, top, label, kInk);
    }
  drawHeader(c, title, legend);
  writePng(c, path);
}

void writeBarPlot(const std::string& path, const std::string& title,
                  const std::vector<std::pair<std::string, Rgb>>& series, const PlotAxis& y,
                  const std::vector<PlotBarGroup>& groups, int width, int height) {
  Canvas c(width, height, kBackground);
  std::vector<double> values;
  for (const PlotBarGroup& g : groups) values.insert(values.end(), g.values.begin(), g.values.end());
  const Axis ay = Axis::fit(values, y, kBottom, height - 1 - kTop);
  Axis ax;  // only the axis line: groups are placed by index
  ax.p0 = kLeft;
  ax.p1 = width - 1 - kRight;
  drawAxes(c, ax, ay, "", y.title, false);
  const int slot = (ax.p1 - ax.p0 - kInset) / std::max<int>(1, int(groups.size()));
  const int bars = std::max<int>(1, int(series.size()));
  const int bar = std::max(3, (slot * 3 / 4) / bars);
  for (std::size_t i = 0; i < groups.size(); ++i) {
    const PlotBarGroup& g = groups[i];
    const int left = ax.p0 + kInset + int(i) * slot + (slot - bar * bars) / 2;
    const std::string label = upper(g.label);
    c.text(left + bar * bars / 2 - textWidth(label) / 2, ay.p0 - kTick - 3, label, kInk);
    for (std::size_t k = 0; k < g.values.size() && k < series.size(); ++k) {
      const double v = g.values[k];
      if (!std::isfinite(v)) continue;
      const int x0 = left + int(k) * bar, top = ay.pixel(v);
      c.fill(x0 + 1, ay.p0 + 1, x0 + bar - 2, top, series[k].second);
      const std::string text = fixedText(v, std::abs(v) < 10 ? 2 : std::abs(v) < 100 ? 1 : 0);
      c.text(x0 + bar / 2 - textWidth(text) / 2, top + kGlyphHeight + 3, text, kInk);
    }
  }
  drawHeader(c, title, series);
  writePng(c, path);
}

}  // namespace nestwalk
