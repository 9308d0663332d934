// The methods report's plots (method_report.h): a scatter plot of labelled points (log or linear
// axes, series optionally joined by lines) and a grouped bar chart, drawn on the project's
// pixel canvas (engine/report/canvas.h) and written as PNG. The bitmap font has capital letters
// only: every text is drawn upper-cased, characters it lacks ('+', lower-case ones) as blanks.
#pragma once

#include "nestwalk/report/canvas.h"

#include <string>
#include <vector>

namespace nestwalk {

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
  std::string title;
  bool log = false;  // log10 over the values (whole decades, or 1-2-5 steps when they span less
                     // than one); values below `floor` (and <= 0) sit on the axis's lower end.
                     // Linear: from min(0, values) with a 1-2-5 step
  double floor = 0;  // log axes: the smallest value shown as itself (0: the smallest positive)
};

/// A scatter plot: `title` and the legend above, the axes' titles beside them. Throws InputError
/// naming `path` when it cannot be written.
void writeScatterPlot(const std::string& path, const std::string& title, const PlotAxis& x, const PlotAxis& y,
                      const std::vector<PlotSeries>& series, int width = 900, int height = 600);

/// A group of bars side by side (one per series), labelled under them.
struct PlotBarGroup {
  std::string label;
  std::vector<double> values;  // one per series (NaN: no bar)
};

/// A bar chart: groups along x, each series' bar in its colour (`series`: legend names and
/// colours), the value printed above each bar. On a log axis the bars rise from its lower end.
void writeBarPlot(const std::string& path, const std::string& title,
                  const std::vector<std::pair<std::string, Rgb>>& series, const PlotAxis& y,
                  const std::vector<PlotBarGroup>& groups, int width = 900, int height = 500);

}  // namespace nestwalk
