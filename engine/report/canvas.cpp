// The report pictures' pixel canvas and its 5x7 bitmap font (see canvas.h).
#include "nestwalk/report/canvas.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/core/output_file.h"

#include <osg/GL>
#include <osgDB/WriteFile>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace nestwalk {
namespace {

// The glyphs: rows top to bottom, bit 4 the leftmost column.
struct Glyph {
  char ch;
  std::uint8_t rows[kGlyphHeight];
};
constexpr Glyph kFont[] = {
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}}, {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}}, {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}}, {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}}, {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}}, {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}}, {'-', {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}},
    {'(', {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}}, {')', {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}},
    {'/', {0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00}}, {':', {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00}},
    {'A', {0x0E, 0x11, 0x11, 0x11, 0x1F, 0x11, 0x11}}, {'B', {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}},
    {'C', {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}}, {'D', {0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C}},
    {'E', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}}, {'F', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}},
    {'G', {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}}, {'H', {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
    {'I', {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}}, {'J', {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}},
    {'K', {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}}, {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}},
    {'M', {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}}, {'N', {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}},
    {'O', {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}}, {'P', {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}},
    {'Q', {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D}}, {'R', {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}},
    {'S', {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}}, {'T', {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
    {'U', {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}}, {'V', {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}},
    {'W', {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}}, {'X', {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11}},
    {'Y', {0x11, 0x11, 0x11, 0x0A, 0x04, 0x04, 0x04}}, {'Z', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F}},
};

const Glyph* glyphOf(char ch) {
  for (const Glyph& g : kFont)
    if (g.ch == ch) return &g;
  return nullptr;
}

}  // namespace

int textWidth(const std::string& text) { return text.empty() ? 0 : int(text.size()) * kGlyphAdvance - 1; }

Canvas::Canvas(int width, int height, Rgb background) : image_(new osg::Image) {
  image_->allocateImage(width, height, 1, GL_RGB, GL_UNSIGNED_BYTE);
  image_->setInternalTextureFormat(GL_RGB);
  fill(0, 0, width - 1, height - 1, background);
}

void Canvas::set(int x, int y, Rgb c) {
  if (x < 0 || y < 0 || x >= width() || y >= height()) return;
  unsigned char* p = image_->data(unsigned(x), unsigned(y));
  p[0] = c.r;
  p[1] = c.g;
  p[2] = c.b;
}

void Canvas::line(int x0, int y0, int x1, int y1, Rgb c) { thickLine(x0, y0, x1, y1, 0, c); }

void Canvas::thickLine(int x0, int y0, int x1, int y1, int radius, Rgb c) {
  const int dx = std::abs(x1 - x0), sx = x0 < x1 ? 1 : -1;
  const int dy = -std::abs(y1 - y0), sy = y0 < y1 ? 1 : -1;
  int err = dx + dy;
  for (;;) {
    fill(x0 - radius, y0 - radius, x0 + radius, y0 + radius, c);
    if (x0 == x1 && y0 == y1) return;
    const int e2 = 2 * err;
    if (e2 >= dy) {
      err += dy;
      x0 += sx;
    }
    if (e2 <= dx) {
      err += dx;
      y0 += sy;
    }
  }
}

void Canvas::dashedHLine(int x0, int x1, int y, Rgb c, int on, int off) {
  for (int x = x0; x <= x1; ++x)
    if ((x - x0) % (on + off) < on) set(x, y, c);
}

void Canvas::fill(int x0, int y0, int x1, int y1, Rgb c) {
  x0 = std::max(x0, 0), y0 = std::max(y0, 0);
  x1 = std::min(x1, width() - 1), y1 = std::min(y1, height() - 1);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) set(x, y, c);
}

void Canvas::disc(int cx, int cy, double radius, Rgb c) {
  const int reach = int(std::ceil(radius));
  for (int dy = -reach; dy <= reach; ++dy)
    for (int dx = -reach; dx <= reach; ++dx)
      if (std::hypot(double(dx), double(dy)) <= radius) set(cx + dx, cy + dy, c);
}

void Canvas::ring(int cx, int cy, double radius, Rgb c) {
  const int reach = int(std::ceil(radius + 0.5));
  for (int dy = -reach; dy <= reach; ++dy)
    for (int dx = -reach; dx <= reach; ++dx)
      if (std::abs(std::hypot(double(dx), double(dy)) - radius) <= 0.5) set(cx + dx, cy + dy, c);
}

void Canvas::fillPolygon(const std::vector<Eigen::Vector2d>& vertices, Rgb c) {
  if (vertices.size() < 3) return;
  double yMin = vertices[0].y(), yMax = yMin;
  for (const Eigen::Vector2d& v : vertices) {
    yMin = std::min(yMin, v.y());
    yMax = std::max(yMax, v.y());
  }
  const int rowFirst = std::max(0, int(std::ceil(yMin - 0.5)));
  const int rowLast = std::min(height() - 1, int(std::floor(yMax - 0.5)));
  std::vector<double> crossings;
  for (int row = rowFirst; row <= rowLast; ++row) {
    const double y = row + 0.5;
    crossings.clear();
    for (std::size_t i = 0; i < vertices.size(); ++i) {
      const Eigen::Vector2d& a = vertices[i];
      const Eigen::Vector2d& b = vertices[(i + 1) % vertices.size()];
      if ((a.y() <= y) == (b.y() <= y)) continue;  // the edge does not cross this row (half-open rule)
      crossings.push_back(a.x() + (y - a.y()) / (b.y() - a.y()) * (b.x() - a.x()));
    }
    std::sort(crossings.begin(), crossings.end());
    for (std::size_t k = 0; k + 1 < crossings.size(); k += 2) {
      const int first = int(std::ceil(crossings[k] - 0.5)), last = int(std::floor(crossings[k + 1] - 0.5));
      for (int x = std::max(first, 0); x <= std::min(last, width() - 1); ++x) set(x, row, c);
    }
  }
}

void Canvas::text(int x, int top, const std::string& s, Rgb c) {
  for (char ch : s) {
    if (const Glyph* g = glyphOf(ch))
      for (int r = 0; r < kGlyphHeight; ++r)
        for (int col = 0; col < kGlyphWidth; ++col)
          if (g->rows[r] & (0x10 >> col)) set(x + col, top - r, c);
    x += kGlyphAdvance;
  }
}

void writePng(Canvas& canvas, const std::string& path) {
  OutputFile file(path, ".png");
  if (!osgDB::writeImageFile(canvas.image(), file.tempPath()))
    throw InputError(path + ": cannot write the PNG (is OpenSceneGraph's png plugin installed? does the folder exist?)");
  file.commit();
}

}  // namespace nestwalk
