// The methods report's scatter and bar plots (engine/plot/charts.h), read back with osgDB's
// own PNG reader. The plot area is found in the image (its black axis lines); the axes' ends are
// worked out here from the axis rule (axis.h) for data chosen so that the answer is plain, and each
// marker and bar is looked for where its value must lie. Labels, legend swatches, the size, the
// errors and the absence of temporary files.
#include "nestwalk/plot/charts.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/plot/plot_frame.h"
#include "tests/common/png_readback.h"
#include "tests/common/temp_folder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace nestwalk {
namespace {

using testing::Colour;
using testing::FoundAxes;
using testing::logFraction;
using testing::pixelAt;
using TempDir = test::TempFolder;

constexpr Rgb kRed{214, 39, 40}, kBlue{31, 119, 180}, kOrange{255, 127, 14};
constexpr Colour kRedC{214, 39, 40}, kBlueC{31, 119, 180}, kOrangeC{255, 127, 14};
// A marker is a disc of radius 4.5 about the value's point: the pixel holding the point is
// covered entirely; computing the point here and there may put it a pixel apart.
constexpr int kMarkerSearch = 1;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Pixels of colour c above the plot area (the legend's swatches).
int aboveThePlot(const osg::Image& img, const FoundAxes& a, Colour c) {
  int n = 0;
  for (int y = a.lastRow + 1; y < img.t(); ++y)
    for (int x = 0; x < img.s(); ++x) n += pixelAt(img, x, y) == c;
  return n;
}

TEST(ScatterPlot, MarkersLieWhereTheLogAxesPutThem) {
  TempDir dir;
  // x from 1 to 100 and y from 10 to 1000: two decades each, whose ends are 1-2-5 values, so each
  // axis runs from the least value to the largest (with ticks at 1, 2, 5, 10, ...).
  const PlotSeries a{"series a", kRed, {{1, 10, ""}, {10, 100, ""}, {100, 1000, ""}}, true};
  const PlotSeries b{"nested+mesh", kBlue, {{3, 200, "nested+mesh"}}};
  const std::string path = dir / "scatter.png";
  writeScatterPlot(path, "time against error", {"time", true, 0, "µs"}, {"error", true, 0, "mm"}, {a, b}, 900, 600);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"scatter.png"});
  const osg::ref_ptr<osg::Image> img = testing::readPng(path);
  ASSERT_TRUE(img);
  EXPECT_EQ(img->s(), 900);
  EXPECT_EQ(img->t(), 600);
  const FoundAxes ax = testing::findAxes(*img, kPlotDataInset);
  ASSERT_GT(ax.lastColumn - ax.yAxisColumn, 600);
  ASSERT_GT(ax.lastRow - ax.xAxisRow, 350);
  auto pixelOf = [&](double x, double y) {
    return std::pair{int(ax.x(logFraction(x, 1, 100))), int(ax.y(logFraction(y, 10, 1000)))};
  };
  for (const PlotPoint& p : a.points) {
    const auto [px, py] = pixelOf(p.x, p.y);
    EXPECT_TRUE(testing::colourNear(*img, px, py, kRedC, kMarkerSearch)) << p.x << ", " << p.y;
  }
  const auto [bx, by] = pixelOf(3, 200);
  EXPECT_TRUE(testing::colourNear(*img, bx, by, kBlueC, kMarkerSearch));
  // Ticks (black, left of the y axis) at the decades of y: 10 at the bottom, 100, 1000 at the top.
  for (double y : {10.0, 100.0, 1000.0})
    EXPECT_EQ(pixelAt(*img, ax.yAxisColumn - 2, int(ax.y(logFraction(y, 10, 1000)))), testing::kBlack) << y;
  // The series line joins a's points: halfway (in log) between the first two, red.
  const auto [mx, my] = pixelOf(std::sqrt(10.0), std::sqrt(1000.0));
  EXPECT_TRUE(testing::colourNear(*img, mx, my, kRedC, 1));
  // The label right of b's marker, the ticks' labels under the x axis and left of the y axis.
  EXPECT_GT(testing::inkIn(*img, bx + 6, by - 6, bx + 90, by + 6), 60);
  EXPECT_GT(testing::inkIn(*img, ax.yAxisColumn, ax.xAxisRow - 20, ax.lastColumn, ax.xAxisRow - 4), 150);
  EXPECT_GT(testing::inkIn(*img, 0, ax.xAxisRow, ax.yAxisColumn - 5, ax.lastRow), 150);
  // The legend: both series' swatches above the plot, and the title.
  EXPECT_GT(aboveThePlot(*img, ax, kRedC), 10);
  EXPECT_GT(aboveThePlot(*img, ax, kBlueC), 10);
  EXPECT_GT(testing::inkIn(*img, 0, ax.lastRow + 1, img->s() - 1, img->t() - 1), 500);
}

TEST(ScatterPlot, LinearAxesReachZero) {
  TempDir dir;
  // x from -5 to 15 and y from 0 (the axis reaches 0) to 8: any limit from 5 to 10 ticks gives x a
  // step of 5 and ends -5 and 15; y ends at 0 and 8 with a step of 1 or 2.
  const PlotSeries s{"points", kOrange, {{-5, 2, "a"}, {15, 8, "b"}, {5, 5, ""}}};
  writeScatterPlot(dir / "linear.png", "linear", {"x"}, {"y"}, {s});
  const osg::ref_ptr<osg::Image> img = testing::readPng(dir / "linear.png");
  ASSERT_TRUE(img);
  const FoundAxes ax = testing::findAxes(*img, kPlotDataInset);
  for (const PlotPoint& p : s.points) {
    const int px = int(ax.x((p.x + 5) / 20)), py = int(ax.y(p.y / 8));
    EXPECT_TRUE(testing::colourNear(*img, px, py, kOrangeC, kMarkerSearch)) << p.x << ", " << p.y;
  }
}

TEST(BarPlot, BarsRiseFromTheLogAxisFloorToTheirValues) {
  TempDir dir;
  // Values from 2 to 400 span decades 0 .. 3: the axis runs over whole decades, 1 to 1000.
  const std::vector<std::pair<std::string, Rgb>> series = {{"p50", kBlue}, {"mean", kOrange}, {"p99", kRed}};
  const std::vector<PlotBarGroup> groups = {{"nested", {2, 30, 400}}, {"nested+mesh", {5, kNaN, 50}}};
  const std::string path = dir / "bars.png";
  writeBarPlot(path, "µs per frame", series, {"time per frame", true, 0, "µs"}, groups, 900, 500);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"bars.png"});
  const osg::ref_ptr<osg::Image> img = testing::readPng(path);
  ASSERT_TRUE(img);
  EXPECT_EQ(img->s(), 900);
  EXPECT_EQ(img->t(), 500);
  const FoundAxes ax = testing::findAxes(*img, kPlotDataInset);
  ASSERT_GT(ax.lastRow - ax.xAxisRow, 250);

  // Each series' bars, left to right, as runs of its colour just above the x axis.
  const int row = ax.xAxisRow + 3;
  auto runsOf = [&](Colour c) {
    std::vector<std::pair<int, int>> runs;
    for (int x = ax.yAxisColumn + 1; x <= ax.lastColumn; ++x)
      if (pixelAt(*img, x, row) == c) {
        if (runs.empty() || runs.back().second != x - 1) runs.push_back({x, x});
        runs.back().second = x;
      }
    return runs;
  };
  const Colour colours[] = {kBlueC, kOrangeC, kRedC};
  std::vector<int> groupCentres(groups.size(), 0);
  for (std::size_t k = 0; k < series.size(); ++k) {
    const auto runs = runsOf(colours[k]);
    std::vector<double> expected;
    for (const PlotBarGroup& g : groups)
      if (std::isfinite(g.values[k])) expected.push_back(g.values[k]);
    ASSERT_EQ(runs.size(), expected.size()) << "series " << k;  // the NaN has no bar
    for (std::size_t i = 0; i < runs.size(); ++i) {
      const int centre = (runs[i].first + runs[i].second) / 2;
      int top = row;
      while (pixelAt(*img, centre, top + 1) == colours[k]) ++top;
      // The bar's top edge lies at the value; the last row covered entirely is the one below it.
      const double edge = ax.y(logFraction(expected[i], 1, 1000));
      EXPECT_GE(top, int(std::floor(edge)) - 1) << "series " << k << " bar " << i << " of " << expected[i];
      EXPECT_LE(top, int(std::floor(edge))) << "series " << k << " bar " << i << " of " << expected[i];
      // Its value printed above it.
      EXPECT_GT(testing::inkIn(*img, runs[i].first - 4, top + 2, runs[i].second + 4, top + 18), 15) << expected[i];
    }
  }
  // Groups' labels under the axis, left group left of the right one.
  const auto blue = runsOf(kBlueC);
  for (const auto& run : blue)
    EXPECT_GT(testing::inkIn(*img, run.first - 20, ax.xAxisRow - 22, run.second + 60, ax.xAxisRow - 4), 30);
  EXPECT_LT(blue[0].second, blue[1].first);
  for (Colour c : colours) EXPECT_GT(aboveThePlot(*img, ax, c), 20) << c;
}

TEST(ReportPlots, UnwritablePathNamesTheFile) {
  TempDir dir;
  const std::string missing = dir / "no/plot.png";
  try {
    writeScatterPlot(missing, "t", {"x", true}, {"y", true}, {{"s", kRed, {{1, 1, ""}}}});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  try {
    writeBarPlot(missing, "t", {{"s", kRed}}, {"y", true}, {{"g", {1}}});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  EXPECT_TRUE(dir.entries().empty());
}

}  // namespace
}  // namespace nestwalk
