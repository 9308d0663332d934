// The methods report's plots (method_report.h): a scatter plot of labelled points (log or linear
// axes, series optionally joined by lines) and a grouped bar chart, drawn on the drawing surface
// (drawing_surface.h) with the shared axes, title and legend (plot_frame.h) and written as PNG.
// Texts are drawn as given (UTF-8: "µs", "nested+mesh").
//
// Layout, top to bottom: the title, the legend (wrapping), the y axis's title over the plot's top
// left corner, the plot area, the x tick labels and the x axis's title under the right end. Axes
// follow axis.h's rule; white background, black axes and text, light grey grid lines at the ticks.
// Markers are discs of radius 4.5 pixels (kPlotMarkerRadius), series lines 2 pixels wide.
//
// Thread safety: keeps no state; each call draws on its own surface and writes its own file (one
// writer per path at a time, core/output_file.h).
#pragma once

#include "nestwalk/plot/drawing_surface.h"

#include <string>
#include <utility>
#include <vector>

namespace nestwalk {

inline constexpr double kPlotMarkerRadius = 4.5;  // pixels
inline constexpr double kPlotSeriesWidth = 2;     // pixels

struct PlotPoint {
  double x = 0, y = 0;
  std::string label;  // drawn beside the point ("" for none)
};

struct PlotSeries {
  std::string name;     // in the legend ("" for none)
  Rgb colour;
  std::vector<PlotPoint> points;
  bool connect = false;  // a line through the points in their order
  bool markers = true;   // a disc at each point
};

struct PlotAxis {
  std::string title;  // "(log)" is appended on a log axis
  bool log = false;   // log10 (axis.h): values <= 0 sit at the lower end, values below `floor`
                      // at the floor. Linear: from min(0, values)
  double floor = 0;   // log axes: the smallest value shown as itself (0: the smallest positive)
  std::string unit = "";  // appended to the tick labels ("10 µs"); "" for none
};

/// A scatter plot. Point labels go right of their point, else left, else a line further up or
/// down, where they cover no marker nor another label (at worst right of the point). Throws
/// InputError naming `path` when it cannot be written.
void writeScatterPlot(const std::string& path, const std::string& title, const PlotAxis& x, const PlotAxis& y,
                      const std::vector<PlotSeries>& series, int width = 900, int height = 600);

/// A group of bars side by side (one per series), labelled under them.
struct PlotBarGroup {
  std::string label;
  std::vector<double> values;  // one per series (NaN: no bar)
};

/// A bar chart: groups side by side in equal slots along x, each series' bar in its colour
/// (`series`: legend names and colours, in the order of the values), the value printed above each
/// bar (raised a line where it would cover its left neighbour's). On a log axis the bars rise from
/// its lower end. Throws InputError naming `path` when it cannot be written.
void writeBarPlot(const std::string& path, const std::string& title,
                  const std::vector<std::pair<std::string, Rgb>>& series, const PlotAxis& y,
                  const std::vector<PlotBarGroup>& groups, int width = 900, int height = 500);

}  // namespace nestwalk
