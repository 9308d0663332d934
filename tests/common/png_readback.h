// Shared by the report's picture tests: PNGs read back through osgDB's own png plugin (rows y up,
// row 0 the bottom one, as drawing_surface.h draws them), pixel colours, and a plot's axes found
// in the image itself (the longest runs of black pixels), so that a test computes where a value
// must lie from the axis rule alone.
#pragma once

#include <gtest/gtest.h>
#include <osg/Image>
#include <osgDB/ReadFile>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <string>

namespace nestwalk::testing {

struct Colour {
  int r = 0, g = 0, b = 0;
  bool operator==(const Colour&) const = default;
};
inline std::ostream& operator<<(std::ostream& os, const Colour& c) {
  return os << "(" << c.r << ", " << c.g << ", " << c.b << ")";
}
inline constexpr Colour kWhite{255, 255, 255}, kBlack{0, 0, 0};

inline osg::ref_ptr<osg::Image> readPng(const std::string& path) {
  osg::ref_ptr<osg::Image> img = osgDB::readImageFile(path);
  if (!img) ADD_FAILURE() << "osgDB cannot read " << path;
  return img;
}

/// The colour of pixel (x, y), y up; (-1, -1, -1) outside the image.
inline Colour pixelAt(const osg::Image& img, int x, int y) {
  if (x < 0 || y < 0 || x >= img.s() || y >= img.t()) return {-1, -1, -1};
  const unsigned char* p = img.data(unsigned(x), unsigned(y));
  return {p[0], p[1], p[2]};
}

/// Pixels in [x0, x1] x [y0, y1] (clipped to the image) that are not `background`.
inline int inkIn(const osg::Image& img, int x0, int y0, int x1, int y1, Colour background = kWhite) {
  int n = 0;
  for (int y = std::max(0, y0); y <= std::min(img.t() - 1, y1); ++y)
    for (int x = std::max(0, x0); x <= std::min(img.s() - 1, x1); ++x) n += !(pixelAt(img, x, y) == background);
  return n;
}

/// Whether a pixel of colour `c` lies within `radius` pixels (a square) of pixel (x, y).
inline bool colourNear(const osg::Image& img, int x, int y, Colour c, int radius) {
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx)
      if (pixelAt(img, x + dx, y + dy) == c) return true;
  return false;
}

/// A plot's axes as found in the image: the x axis is the longest horizontal run of black pixels,
/// the y axis the longest vertical one. The plot area's edges lie on the centres of these pixels:
/// left = yAxisColumn + 0.5, bottom = xAxisRow + 0.5, right = the x axis's last column + 0.5,
/// top = the y axis's last row + 0.5; values map from `inset` pixels inside the axis lines
/// (plot_frame.h's kPlotDataInset) to the right and top edges.
struct FoundAxes {
  int xAxisRow = -1, firstColumn = -1, lastColumn = -1;
  int yAxisColumn = -1, firstRow = -1, lastRow = -1;
  double inset = 0;
  double left() const { return yAxisColumn + 0.5; }
  double bottom() const { return xAxisRow + 0.5; }
  double right() const { return lastColumn + 0.5; }
  double top() const { return lastRow + 0.5; }
  /// Where a value at `fraction` of an axis lies, continuous pixel coordinates.
  double x(double fraction) const { return left() + inset + fraction * (right() - left() - inset); }
  double y(double fraction) const { return bottom() + inset + fraction * (top() - bottom() - inset); }
};

inline FoundAxes findAxes(const osg::Image& img, double inset) {
  FoundAxes a;
  a.inset = inset;
  int best = 0;
  for (int y = 0; y < img.t(); ++y)
    for (int x = 0, run = 0; x < img.s(); ++x) {
      run = pixelAt(img, x, y) == kBlack ? run + 1 : 0;
      if (run > best) best = run, a.xAxisRow = y, a.lastColumn = x, a.firstColumn = x - run + 1;
    }
  best = 0;
  for (int x = 0; x < img.s(); ++x)
    for (int y = 0, run = 0; y < img.t(); ++y) {
      run = pixelAt(img, x, y) == kBlack ? run + 1 : 0;
      if (run > best) best = run, a.yAxisColumn = x, a.lastRow = y, a.firstRow = y - run + 1;
    }
  return a;
}

/// log10 fraction of v on a log axis from lo to hi.
inline double logFraction(double v, double lo, double hi) {
  return (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo));
}

}  // namespace nestwalk::testing
