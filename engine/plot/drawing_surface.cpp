// The report pictures' drawing surface over cairo (drawing_surface.h): y-up pixel coordinates turned
// into cairo's y-down device space point by point (text is set upright in device space at the
// converted anchor), the UI font loaded once from its file through FreeType and cairo-ft.
#include "nestwalk/plot/drawing_surface.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/core/output_file.h"
#include "nestwalk/core/ui_font.h"

#include <cairo-ft.h>
#include <cairo.h>
#include <ft2build.h>
#include FT_FREETYPE_H

#include <algorithm>
#include <cmath>
#include <mutex>
#include <numbers>
#include <stdexcept>

namespace nestwalk {
namespace {

// The halo under text (TextStyle::halo): a stroke this wide around the glyphs' outlines, pixels.
constexpr double kHaloWidth = 3.0;

/// The UI font as a cairo font face, loaded on first use and kept for the process (with its FreeType
/// library and face; the face is released with the font face, which never happens).
cairo_font_face_t* uiFontFace() {
  static std::mutex mutex;
  static cairo_font_face_t* face = nullptr;
  std::lock_guard lock(mutex);
  if (face) return face;
  const std::string path = uiFontPath();  // throws InputError when the file is absent
  FT_Library library = nullptr;
  if (FT_Init_FreeType(&library) != 0) throw InputError(path + ": cannot start FreeType to read the font");
  FT_Face ftFace = nullptr;
  if (FT_New_Face(library, path.c_str(), 0, &ftFace) != 0) {
    FT_Done_FreeType(library);
    throw InputError(path + ": FreeType cannot read the font file");
  }
  cairo_font_face_t* created = cairo_ft_font_face_create_for_ft_face(ftFace, 0);
  static const cairo_user_data_key_t kFaceKey{};
  if (cairo_font_face_status(created) != CAIRO_STATUS_SUCCESS ||
      cairo_font_face_set_user_data(created, &kFaceKey, ftFace, [](void* f) { FT_Done_Face(static_cast<FT_Face>(f)); }) !=
          CAIRO_STATUS_SUCCESS) {
    cairo_font_face_destroy(created);
    FT_Done_Face(ftFace);
    FT_Done_FreeType(library);
    throw InputError(path + ": cairo cannot use the font");
  }
  face = created;
  return face;
}

/// Greyscale antialiasing, slight hinting, unhinted metrics: a text measures the same with and
/// without a surface, and at every position.
cairo_font_options_t* fontOptions() {
  static cairo_font_options_t* options = [] {
    cairo_font_options_t* o = cairo_font_options_create();
    cairo_font_options_set_antialias(o, CAIRO_ANTIALIAS_GRAY);
    cairo_font_options_set_hint_style(o, CAIRO_HINT_STYLE_SLIGHT);
    cairo_font_options_set_hint_metrics(o, CAIRO_HINT_METRICS_OFF);
    return o;
  }();
  return options;
}

/// The UI font at `size` pixels per em, unrotated (the caller destroys it).
cairo_scaled_font_t* scaledFont(double size) {
  cairo_matrix_t fontMatrix, identity;
  cairo_matrix_init_scale(&fontMatrix, size, size);
  cairo_matrix_init_identity(&identity);
  return cairo_scaled_font_create(uiFontFace(), &fontMatrix, &identity, fontOptions());
}

/// A text's layout at one size: advance, the font's ascent and descent, the height of a capital.
struct TextMetrics {
  double advance = 0, ascent = 0, descent = 0, capHeight = 0;
};

TextMetrics measure(const std::string& text, double size) {
  cairo_scaled_font_t* font = scaledFont(size);
  cairo_font_extents_t fe;
  cairo_scaled_font_extents(font, &fe);
  cairo_text_extents_t te, cap;
  cairo_scaled_font_text_extents(font, text.c_str(), &te);
  cairo_scaled_font_text_extents(font, "H", &cap);
  cairo_scaled_font_destroy(font);
  return {te.x_advance, fe.ascent, fe.descent, cap.height};
}

/// The baseline's left end (y up) and the box of a text anchored at `anchor`.
std::pair<Point, TextBox> layout(Point anchor, const TextMetrics& m, const TextStyle& style) {
  double x = anchor.x();
  if (style.h == HAlign::Centre) x -= m.advance / 2;
  if (style.h == HAlign::Right) x -= m.advance;
  double baseline = anchor.y();
  switch (style.v) {
    case VAlign::Top: baseline -= m.ascent; break;
    case VAlign::Middle: baseline -= m.capHeight / 2; break;
    case VAlign::Baseline: break;
    case VAlign::Bottom: baseline += m.descent; break;
  }
  return {{x, baseline}, {x, baseline - m.descent, x + m.advance, baseline + m.ascent}};
}

}  // namespace

DrawingSurface::DrawingSurface(int width, int height, Rgb background) : width_(width), height_(height) {
  if (width < 1 || height < 1)
    throw InputError("a drawing of " + std::to_string(width) + " x " + std::to_string(height) + " pixels is empty");
  surface_ = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
  cr_ = cairo_create(surface_);
  if (cairo_status(cr_) != CAIRO_STATUS_SUCCESS) {
    const std::string why = cairo_status_to_string(cairo_status(cr_));
    cairo_destroy(cr_);
    cairo_surface_destroy(surface_);
    throw InputError("cannot make a drawing of " + std::to_string(width) + " x " + std::to_string(height) +
                     " pixels: " + why);
  }
  cairo_set_antialias(cr_, CAIRO_ANTIALIAS_DEFAULT);
  cairo_set_line_join(cr_, CAIRO_LINE_JOIN_ROUND);
  setColour(background);
  cairo_paint(cr_);
}

DrawingSurface::~DrawingSurface() {
  cairo_destroy(cr_);
  cairo_surface_destroy(surface_);
}

void DrawingSurface::setColour(Rgb c) { cairo_set_source_rgb(cr_, c.r / 255.0, c.g / 255.0, c.b / 255.0); }

void DrawingSurface::path(std::span<const Point> points, bool close) {
  cairo_new_path(cr_);
  for (const Point& p : points) cairo_line_to(cr_, p.x(), deviceY(p.y()));
  if (close) cairo_close_path(cr_);
}

void DrawingSurface::putPixels(int x, int y, int w, int h, std::span<const Rgb> pixels) {
  if (pixels.size() < std::size_t(std::max(w, 0)) * std::size_t(std::max(h, 0)))
    throw std::invalid_argument("DrawingSurface::putPixels: fewer pixels than the block holds");
  cairo_surface_flush(surface_);
  unsigned char* data = cairo_image_surface_get_data(surface_);
  const int stride = cairo_image_surface_get_stride(surface_);
  for (int j = 0; j < h; ++j) {
    const int row = y + j;
    if (row < 0 || row >= height_) continue;
    auto* out = reinterpret_cast<std::uint32_t*>(data + std::size_t(height_ - 1 - row) * std::size_t(stride));
    for (int i = 0; i < w; ++i) {
      const int col = x + i;
      if (col < 0 || col >= width_) continue;
      const Rgb c = pixels[std::size_t(j) * std::size_t(w) + std::size_t(i)];
      out[col] = 0xFF000000u | std::uint32_t(c.r) << 16 | std::uint32_t(c.g) << 8 | std::uint32_t(c.b);
    }
  }
  cairo_surface_mark_dirty(surface_);
}

Rgb DrawingSurface::pixel(int x, int y) const {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return {};
  cairo_surface_flush(surface_);
  const unsigned char* data = cairo_image_surface_get_data(surface_);
  const std::uint32_t v = reinterpret_cast<const std::uint32_t*>(
      data + std::size_t(height_ - 1 - y) * std::size_t(cairo_image_surface_get_stride(surface_)))[x];
  return {std::uint8_t(v >> 16), std::uint8_t(v >> 8), std::uint8_t(v)};
}

void DrawingSurface::fillRect(double x0, double y0, double x1, double y1, Rgb c) {
  cairo_new_path(cr_);
  cairo_rectangle(cr_, std::min(x0, x1), deviceY(std::max(y0, y1)), std::abs(x1 - x0), std::abs(y1 - y0));
  setColour(c);
  cairo_fill(cr_);
}

void DrawingSurface::line(Point a, Point b, double width, Rgb c, Dash dash, bool squareEnds) {
  const Point points[] = {a, b};
  path(points, false);
  cairo_set_line_width(cr_, width);
  cairo_set_line_cap(cr_, squareEnds ? CAIRO_LINE_CAP_SQUARE : CAIRO_LINE_CAP_BUTT);
  if (dash.on > 0 && dash.off > 0) {
    const double pattern[] = {dash.on, dash.off};
    cairo_set_dash(cr_, pattern, 2, 0);
  }
  setColour(c);
  cairo_stroke(cr_);
  cairo_set_dash(cr_, nullptr, 0, 0);
}

void DrawingSurface::polyline(std::span<const Point> points, double width, Rgb c) {
  if (points.empty()) return;
  path(points, false);
  if (points.size() == 1) cairo_line_to(cr_, points[0].x(), deviceY(points[0].y()));  // a dot
  cairo_set_line_width(cr_, width);
  cairo_set_line_cap(cr_, CAIRO_LINE_CAP_ROUND);
  setColour(c);
  cairo_stroke(cr_);
}

void DrawingSurface::fillPolygon(std::span<const Point> vertices, Rgb c) {
  if (vertices.size() < 3) return;
  path(vertices, true);
  cairo_set_fill_rule(cr_, CAIRO_FILL_RULE_WINDING);
  setColour(c);
  cairo_fill(cr_);
}

void DrawingSurface::strokePolygon(std::span<const Point> vertices, double width, Rgb c) {
  if (vertices.size() < 2) return;
  path(vertices, true);
  cairo_set_line_width(cr_, width);
  setColour(c);
  cairo_stroke(cr_);
}

void DrawingSurface::disc(Point centre, double radius, Rgb c) {
  cairo_new_path(cr_);
  cairo_arc(cr_, centre.x(), deviceY(centre.y()), radius, 0, 2 * std::numbers::pi);
  setColour(c);
  cairo_fill(cr_);
}

void DrawingSurface::circle(Point centre, double radius, double width, Rgb c) {
  cairo_new_path(cr_);
  cairo_arc(cr_, centre.x(), deviceY(centre.y()), radius, 0, 2 * std::numbers::pi);
  cairo_close_path(cr_);
  cairo_set_line_width(cr_, width);
  setColour(c);
  cairo_stroke(cr_);
}

void DrawingSurface::clip(double x0, double y0, double x1, double y1) {
  cairo_reset_clip(cr_);
  cairo_new_path(cr_);
  cairo_rectangle(cr_, std::min(x0, x1), deviceY(std::max(y0, y1)), std::abs(x1 - x0), std::abs(y1 - y0));
  cairo_clip(cr_);
}

void DrawingSurface::resetClip() { cairo_reset_clip(cr_); }

TextBox DrawingSurface::textBox(Point anchor, const std::string& text, const TextStyle& style) {
  return layout(anchor, measure(text, style.size), style).second;
}

double DrawingSurface::textWidth(const std::string& text, double size) { return measure(text, size).advance; }

DrawingSurface::FontMetrics DrawingSurface::fontMetrics(double size) {
  const TextMetrics m = measure("", size);
  return {m.ascent, m.descent, m.capHeight};
}

TextBox DrawingSurface::text(Point anchor, const std::string& text, const TextStyle& style) {
  const auto [origin, box] = layout(anchor, measure(text, style.size), style);
  if (text.empty()) return box;
  cairo_set_font_face(cr_, uiFontFace());
  cairo_set_font_options(cr_, fontOptions());
  cairo_set_font_size(cr_, style.size);
  cairo_new_path(cr_);
  cairo_move_to(cr_, origin.x(), deviceY(origin.y()));
  if (style.halo) {
    cairo_text_path(cr_, text.c_str());
    cairo_set_line_width(cr_, kHaloWidth);
    setColour(style.haloColour);
    cairo_stroke_preserve(cr_);
    setColour(style.colour);
    cairo_fill(cr_);
  } else {
    setColour(style.colour);
    cairo_show_text(cr_, text.c_str());
  }
  return box;
}

void DrawingSurface::writePng(const std::string& path) {
  cairo_surface_flush(surface_);
  OutputFile file(path, ".png");
  const cairo_status_t status = cairo_surface_write_to_png(surface_, file.tempPath().c_str());
  if (status != CAIRO_STATUS_SUCCESS)
    throw InputError(path + ": cannot write the PNG (" + cairo_status_to_string(status) + "; does the folder exist?)");
  file.commit();
}

}  // namespace nestwalk
