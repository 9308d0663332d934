// The small RGB pixel canvas the report pictures (frame-time plot, top-down map) are drawn on: an
// osg::Image with points, lines, rectangles, discs, rings, filled polygons and text in a 5x7
// bitmap font, written as PNG through osgDB's image writer (its png plugin).
//
// Pixels are addressed y-up, as in osg::Image: row 0 is the bottom row (the PNG plugin flips rows
// on writing and reading, so a reader through osgDB sees the same rows). Pixel (x, y) covers the
// square [x, x + 1) x [y, y + 1) of the continuous pixel plane, its centre is (x + 0.5, y + 0.5).
// Drawing outside the canvas is clipped silently.
#pragma once

#include <osg/Image>
#include <osg/ref_ptr>

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace nestwalk {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb&) const = default;
};

// The bitmap font: every glyph is 5 x 7 pixels and the pen advances 6 pixels per character. It
// holds the digits, the capital letters A-Z and ". - ( ) / :"; any other character (a space,
// lower case) draws as a blank.
inline constexpr int kGlyphWidth = 5, kGlyphHeight = 7, kGlyphAdvance = 6;

/// Width in pixels of `text` in the bitmap font (no trailing gap; 0 for an empty text).
int textWidth(const std::string& text);

class Canvas {
 public:
  /// A width x height RGB image filled with `background`.
  Canvas(int width, int height, Rgb background);

  int width() const { return image_->s(); }
  int height() const { return image_->t(); }
  osg::Image& image() { return *image_; }

  void set(int x, int y, Rgb c);

  /// Bresenham's line, both ends included.
  void line(int x0, int y0, int x1, int y1, Rgb c);
  /// Bresenham's line drawn with a square brush of (2 radius + 1)^2 pixels.
  void thickLine(int x0, int y0, int x1, int y1, int radius, Rgb c);
  /// Horizontal dashes from x0 to x1 on row y: `on` pixels drawn, `off` skipped, starting at x0.
  void dashedHLine(int x0, int x1, int y, Rgb c, int on, int off);
  /// The rectangle [x0, x1] x [y0, y1], both corners included.
  void fill(int x0, int y0, int x1, int y1, Rgb c);
  /// Every pixel whose centre lies within `radius` of the centre of pixel (cx, cy).
  void disc(int cx, int cy, double radius, Rgb c);
  /// Every pixel whose centre lies within half a pixel of the circle of `radius` about the
  /// centre of pixel (cx, cy).
  void ring(int cx, int cy, double radius, Rgb c);
  /// Every pixel whose centre lies inside the closed polygon (continuous pixel coordinates, any
  /// orientation; the even-odd rule decides for self-intersecting ones).
  void fillPolygon(const std::vector<Eigen::Vector2d>& vertices, Rgb c);
  /// Text with its top-left corner at (x, top); y-up, so rows go down from `top`.
  void text(int x, int top, const std::string& s, Rgb c);

 private:
  osg::ref_ptr<osg::Image> image_;
};

/// Writes the canvas as PNG to `path` through an OutputFile (output_file.h): a temporary name in
/// the same folder, renamed when complete. Throws InputError naming `path` when it cannot be
/// written.
void writePng(Canvas& canvas, const std::string& path);

}  // namespace nestwalk
