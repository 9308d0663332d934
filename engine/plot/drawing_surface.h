// The surface the report's pictures (frame-time plot, top-down map, the methods report's plots) are
// drawn on: a thin layer over a cairo RGB image surface. Lines, polygons, discs and text are
// cairo's, antialiased; text is set in the one UI font (nestwalk/core/ui_font.h, DejaVu Sans read
// from its file through cairo-ft), UTF-8, so "µs", "nested+mesh" and lower case print as written.
// The image is written as an 8-bit RGB PNG by cairo.
//
// Coordinates are pixels, y up, as in osg::Image: (0, 0) is the bottom-left corner of the image and
// (width, height) its top-right one (osgDB's png plugin flips rows on writing and reading, so an
// image read back through osgDB has row 0 at the bottom too). Pixel (i, j) covers the square
// [i, i + 1) x [j, j + 1); its centre is (i + 0.5, j + 0.5). A one-pixel line through pixel
// centres is crisp (it covers whole pixels); anything else is antialiased. A pixel a shape covers
// entirely gets exactly the shape's colour (cairo keeps 8-bit colours exact at full coverage).
// Drawing outside the image is clipped silently.
//
// Not copyable; not thread-safe (one surface per thread; the font is shared, cairo locks it).
// The static text measures (textBox, textWidth, fontMetrics) may be called from any thread: the
// font is loaded once, under a lock.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

struct _cairo;
struct _cairo_surface;

namespace nestwalk {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb&) const = default;
};

/// A point in the surface's y-up pixel coordinates.
using Point = Eigen::Vector2d;

/// Where a text's anchor point lies on it. Horizontally: its left end, centre or right end.
/// Vertically: Top puts the font's ascent line on the anchor (the text hangs below), Middle the
/// middle of a capital letter (labels beside a tick), Baseline the baseline, Bottom the font's
/// descent line (the text stands above).
enum class HAlign { Left, Centre, Right };
enum class VAlign { Top, Middle, Baseline, Bottom };

/// The box a text occupies, y up: its advance across, the font's descent to ascent up. Every text
/// of one size has the same height, so boxes of labels line up.
struct TextBox {
  double left = 0, bottom = 0, right = 0, top = 0;
  double width() const { return right - left; }
  double height() const { return top - bottom; }
  bool overlaps(const TextBox& o) const { return left < o.right && o.left < right && bottom < o.top && o.bottom < top; }
};

struct TextStyle {
  double size = 12;                 // pixels per em
  Rgb colour{0, 0, 0};
  HAlign h = HAlign::Left;
  VAlign v = VAlign::Baseline;
  bool halo = false;                // a 3-pixel-wide outline in haloColour under the text, so that
  Rgb haloColour{255, 255, 255};    // it reads on any background
};

/// Dashes of a line: `on` pixels drawn, `off` skipped, from the line's start; {0, 0} for solid.
struct Dash {
  double on = 0, off = 0;
};

class DrawingSurface {
 public:
  /// A width x height image filled with `background`. Throws InputError for a size below 1 x 1.
  DrawingSurface(int width, int height, Rgb background);
  ~DrawingSurface();
  DrawingSurface(const DrawingSurface&) = delete;
  DrawingSurface& operator=(const DrawingSurface&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }

  /// Sets the pixels of the w x h block whose bottom-left pixel is (x, y) to `pixels`, rows bottom
  /// to top, each row left to right (w * h values; the part outside the image is skipped).
  void putPixels(int x, int y, int w, int h, std::span<const Rgb> pixels);
  /// The colour of pixel (x, y) (black outside the image).
  Rgb pixel(int x, int y) const;

  /// The rectangle [x0, x1] x [y0, y1] filled (crisp where the corners are whole numbers).
  void fillRect(double x0, double y0, double x1, double y1, Rgb c);
  /// A straight line `width` pixels wide with butt ends (square ends, reaching width / 2 beyond
  /// the end points, with `squareEnds`).
  void line(Point a, Point b, double width, Rgb c, Dash dash = {}, bool squareEnds = false);
  /// A line through the points in order, round joins and ends.
  void polyline(std::span<const Point> points, double width, Rgb c);
  /// The polygon's inside (non-zero winding) filled.
  void fillPolygon(std::span<const Point> vertices, Rgb c);
  /// The closed polygon's outline, `width` pixels wide, round joins.
  void strokePolygon(std::span<const Point> vertices, double width, Rgb c);
  /// The disc of `radius` about `centre` filled.
  void disc(Point centre, double radius, Rgb c);
  /// The circle of `radius` about `centre`, `width` pixels wide.
  void circle(Point centre, double radius, double width, Rgb c);

  /// Restricts drawing to the rectangle [x0, x1] x [y0, y1] until resetClip().
  void clip(double x0, double y0, double x1, double y1);
  void resetClip();

  /// Draws UTF-8 `text` anchored at `anchor` and returns its box. Throws InputError when the UI
  /// font cannot be loaded (ui_font.h).
  TextBox text(Point anchor, const std::string& text, const TextStyle& style);
  /// The box text(anchor, text, style) would occupy, without a surface.
  static TextBox textBox(Point anchor, const std::string& text, const TextStyle& style);
  /// The advance of `text` at `size` pixels per em.
  static double textWidth(const std::string& text, double size);
  /// The font's ascent and descent (positive, pixels) and the height of a capital, at `size`.
  struct FontMetrics {
    double ascent = 0, descent = 0, capHeight = 0;
  };
  static FontMetrics fontMetrics(double size);

  /// Writes the image as PNG through an OutputFile (nestwalk/core/output_file.h): a temporary name
  /// beside `path`, renamed when complete. Throws InputError naming `path` when it cannot be
  /// written (no such folder, no permission); no temporary file is left then.
  void writePng(const std::string& path);

 private:
  double deviceY(double y) const { return height_ - y; }
  void path(std::span<const Point> points, bool close);
  void setColour(Rgb c);

  int width_, height_;
  _cairo_surface* surface_ = nullptr;
  _cairo* cr_ = nullptr;
};

/// `c` with every channel halved (outlines of filled shapes).
inline Rgb darker(Rgb c) { return {std::uint8_t(c.r / 2), std::uint8_t(c.g / 2), std::uint8_t(c.b / 2)}; }

}  // namespace nestwalk
