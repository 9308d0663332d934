// A plot's furniture, shared by the frame-time plot (frame_time_plot.h) and the methods report's
// plots (charts.h): the plot area, its two axes (light grey grid lines at the ticks, black
// tick marks outside the area with their labels from axis.h, black one-pixel axis lines on the
// left and bottom edges, over the data) and the block above the plot with the title and the
// legend.
//
// Coordinates are the drawing surface's (drawing_surface.h): pixels, y up.
//
// Thread safety: PlotArea and PlotHeader are immutable once made; drawing goes to the caller's
// DrawingSurface (one thread per surface).
#pragma once

#include "nestwalk/plot/axis.h"
#include "nestwalk/plot/drawing_surface.h"

#include <string>
#include <vector>

namespace nestwalk {

// What every plot shares.
inline constexpr Rgb kPlotPaper{255, 255, 255}, kPlotInk{0, 0, 0}, kPlotGrid{224, 224, 224};
inline constexpr double kTickFontSize = 12;    // tick labels, legend, axis titles; pixels per em
inline constexpr double kTitleFontSize = 14;
inline constexpr double kTickLength = 4;       // tick marks, outside the plot area, pixels
inline constexpr double kTickLabelGap = 3;     // between a tick mark and its label, pixels
inline constexpr double kPlotPadding = 8;      // between the image's edges and what is drawn, pixels

/// Values map from this many pixels inside the axis lines, so that data at an axis's lower end
/// (a time of 0, the least value of a log axis) is not hidden under the other axis's line.
inline constexpr double kPlotDataInset = 6;

/// The plot area. Its edges lie on pixel centres, so the one-pixel axis lines drawn on its left and
/// bottom edges are crisp. Values map by Axis::position from left + kPlotDataInset to right and
/// from bottom + kPlotDataInset to top.
struct PlotArea {
  double left = 0, bottom = 0, right = 1, top = 1;

  /// The area inside [left, right] x [bottom, top] whose edges are the nearest pixel centres.
  static PlotArea inside(double left, double bottom, double right, double top);
  double x(const Axis& axis, double v) const { return axis.position(v, left + kPlotDataInset, right); }
  double y(const Axis& axis, double v) const { return axis.position(v, bottom + kPlotDataInset, top); }
};

/// The width the y axis's tick labels need left of the area, tick marks included.
double yTickMargin(const Axis& y);
/// The height a row of x tick labels needs below the area, tick marks included.
double xTickMargin();

/// Grid lines at both axes' ticks, tick marks and their labels. `x` null: no x ticks nor grid (bar
/// charts label their groups themselves). A label that would overlap the one before it is left
/// out; x labels are kept inside the image. Drawn before the data.
void drawAxes(DrawingSurface& surface, const PlotArea& area, const Axis* x, const Axis& y);
/// The two axis lines, black, one pixel, on the area's left and bottom edges; drawn after the data
/// so that a series on an edge does not hide them.
void drawAxisLines(DrawingSurface& surface, const PlotArea& area);

/// How a legend entry shows its series: a line (`width` pixels), a dashed line (6 on, 4 off), a
/// filled box or a disc.
enum class Swatch { Line, DashedLine, Box, Disc };
struct LegendEntry {
  std::string name;
  Rgb colour;
  Swatch swatch = Swatch::Box;
  double width = 2;
};
inline constexpr Dash kPlotDash{6, 4};  // dashed series and their legend swatches

/// The block above a plot: the title on the first line, then the legend's entries (those with a
/// name) left to right from `left`, wrapping onto further lines before `right`.
class PlotHeader {
 public:
  PlotHeader(std::string title, std::vector<LegendEntry> entries, double left, double right);
  /// From the top of the title to the bottom of the last legend line, pixels.
  double height() const;
  /// Draws the block with its top at `top`.
  void draw(DrawingSurface& surface, double top) const;

 private:
  struct Placed {
    LegendEntry entry;
    double x = 0;  // the swatch's left end
    int line = 0;  // legend line, from 0 below the title
  };
  std::string title_;
  double left_;
  std::vector<Placed> placed_;
  int lines_ = 0;
};

}  // namespace nestwalk
