// The frame-time plot: µs per step for each timed part against the frame number, drawn into an
// osg::Image and written as PNG by osgDB's image writer plugin. Colours, scale and layout are
// documented in frame_record.h. Pixels are addressed y-up (row 0 is the bottom row, as in
// osg::Image; the PNG plugin flips rows on writing and reading).
#include "engine/report/frame_record.h"

#include "engine/core/input_error.h"
#include "engine/report/output_file.h"

#include <osg/GL>
#include <osg/Image>
#include <osgDB/WriteFile>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

namespace nestwalk {
namespace {

struct Rgb {
  std::uint8_t r, g, b;
};

// Colours (the legend and frame_record.h name them).
constexpr Rgb kBackground{255, 255, 255};
constexpr Rgb kInk{0, 0, 0};          // axes, ticks, text
constexpr Rgb kGrid{224, 224, 224};   // decade and frame grid lines
constexpr Rgb kPartColour[kStepParts] = {
    {44, 160, 44},   // ground: green
    {31, 119, 180},  // broad: blue
    {255, 127, 14},  // narrow: orange
    {214, 39, 40},   // total: red
};
constexpr Rgb kP50Colour{148, 103, 189};  // p50 of total: purple, dashed
constexpr Rgb kP99Colour{140, 86, 75};    // p99 of total: brown, dashed

// Layout, pixels. The left margin holds y labels up to 7 glyphs ("0.00001"), the top margin the
// legend, the bottom margin the frame labels.
constexpr int kGlyphW = 5, kGlyphH = 7, kGlyphAdvance = 6;
constexpr int kLeftMargin = 8 * kGlyphAdvance + 8;
constexpr int kRightMargin = 16;
constexpr int kTopMargin = 2 * kGlyphH + 12;
constexpr int kBottomMargin = 2 * kGlyphH + 14;  // tick labels, then "FRAME" below them
constexpr int kTickLength = 4;
constexpr int kDataInset = 3;  // data starts this far inside the axes, so the axes never hide it
constexpr int kDashOn = 6, kDashOff = 4;  // percentile lines
constexpr int kMinWidth = kLeftMargin + kRightMargin + 100;
constexpr int kMinHeight = kTopMargin + kBottomMargin + 60;
// Below this the log axis stops (a part that took 0 µs, e.g. with timing off, sits on the floor).
constexpr double kFloorMicros = 1e-3;
constexpr int kFrameTicksWanted = 8;

// A 5x7 bitmap font for the labels: rows top to bottom, bit 4 the leftmost column. Glyphs not
// here draw as blanks.
struct Glyph {
  char ch;
  std::uint8_t rows[kGlyphH];
};
constexpr Glyph kFont[] = {
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}}, {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}}, {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}}, {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}}, {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}}, {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}}, {'-', {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}},
    {'(', {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}}, {')', {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}},
    {'A', {0x0E, 0x11, 0x11, 0x11, 0x1F, 0x11, 0x11}}, {'B', {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}},
    {'D', {0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C}}, {'E', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}},
    {'F', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}}, {'G', {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}},
    {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}}, {'M', {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}},
    {'N', {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}}, {'O', {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}},
    {'P', {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}}, {'R', {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}},
    {'S', {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}}, {'T', {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
    {'U', {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}}, {'W', {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}},
};

class Canvas {
 public:
  Canvas(int w, int h) : image_(new osg::Image) {
    image_->allocateImage(w, h, 1, GL_RGB, GL_UNSIGNED_BYTE);
    image_->setInternalTextureFormat(GL_RGB);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) set(x, y, kBackground);
  }
  int width() const { return image_->s(); }
  int height() const { return image_->t(); }
  osg::Image& image() { return *image_; }

  void set(int x, int y, Rgb c) {
    if (x < 0 || y < 0 || x >= width() || y >= height()) return;
    unsigned char* p = image_->data(unsigned(x), unsigned(y));
    p[0] = c.r;
    p[1] = c.g;
    p[2] = c.b;
  }

  /// Bresenham's line, both ends included.
  void line(int x0, int y0, int x1, int y1, Rgb c) {
    const int dx = std::abs(x1 - x0), sx = x0 < x1 ? 1 : -1;
    const int dy = -std::abs(y1 - y0), sy = y0 < y1 ? 1 : -1;
    int err = dx + dy;
    for (;;) {
      set(x0, y0, c);
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

  void dashedHLine(int x0, int x1, int y, Rgb c) {
    for (int x = x0; x <= x1; ++x)
      if ((x - x0) % (kDashOn + kDashOff) < kDashOn) set(x, y, c);
  }

  void fill(int x0, int y0, int x1, int y1, Rgb c) {
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) set(x, y, c);
  }

  /// Text with its top-left corner at (x, top); y-up, so rows go down from `top`.
  void text(int x, int top, const std::string& s, Rgb c) {
    for (char ch : s) {
      for (const Glyph& g : kFont) {
        if (g.ch != ch) continue;
        for (int r = 0; r < kGlyphH; ++r)
          for (int col = 0; col < kGlyphW; ++col)
            if (g.rows[r] & (0x10 >> col)) set(x + col, top - r, c);
      }
      x += kGlyphAdvance;
    }
  }

 private:
  osg::ref_ptr<osg::Image> image_;
};

int textWidth(const std::string& s) { return int(s.size()) * kGlyphAdvance - 1; }

/// Label of the decade 10^k: plain decimals from 0.00001 to 1000000, "1E-9" style beyond.
std::string decadeLabel(int k) {
  if (k >= 0 && k <= 6) return "1" + std::string(std::size_t(k), '0');
  if (k < 0 && k >= -5) return "0." + std::string(std::size_t(-k - 1), '0') + "1";
  return "1E" + std::to_string(k);
}

/// A 1-2-5 step giving about `wanted` intervals over `span`.
std::uint64_t niceStep(std::uint64_t span, int wanted) {
  std::uint64_t step = 1;
  for (;;) {
    for (std::uint64_t m : {1ull, 2ull, 5ull})
      if (span / (step * m) <= std::uint64_t(wanted)) return step * m;
    step *= 10;
  }
}

}  // namespace

void writeFrameTimePlot(const std::string& path, const std::vector<FrameRecord>& records, int width, int height) {
  if (width < kMinWidth || height < kMinHeight)
    throw InputError(path + ": frame-time plot of " + std::to_string(width) + " x " + std::to_string(height) +
                     " pixels is too small (at least " + std::to_string(kMinWidth) + " x " +
                     std::to_string(kMinHeight) + ")");
  Canvas canvas(width, height);
  const int px0 = kLeftMargin, px1 = width - 1 - kRightMargin;   // plot area, columns
  const int py0 = kBottomMargin, py1 = height - 1 - kTopMargin;  // plot area, rows (y up)

  // Log10 y axis over whole decades holding every positive time (at least one decade).
  double lo = HUGE_VAL, hi = 0;
  for (const FrameRecord& r : records)
    for (double us : r.micros)
      if (us > 0 && std::isfinite(us)) {
        lo = std::min(lo, std::max(us, kFloorMicros));
        hi = std::max(hi, us);
      }
  int kLo = 0, kHi = 1;
  if (hi > 0) {
    kLo = int(std::floor(std::log10(lo)));
    kHi = std::max(kLo + 1, int(std::ceil(std::log10(hi))));
  }
  auto yOf = [&](double us) {
    const double l = us > 0 && std::isfinite(us) ? std::clamp(std::log10(us), double(kLo), double(kHi)) : double(kLo);
    return py0 + kDataInset + int(std::lround((l - kLo) / (kHi - kLo) * (py1 - py0 - kDataInset)));
  };

  // x: frame numbers from the first record's to the last's.
  const std::uint64_t f0 = records.empty() ? 0 : records.front().frame;
  const std::uint64_t f1 = records.empty() ? 0 : std::max(records.back().frame, f0);
  auto xOf = [&](std::uint64_t f) {
    if (f1 == f0) return (px0 + px1) / 2;
    return px0 + kDataInset + int(std::lround(double(f - f0) / double(f1 - f0) * (px1 - px0 - kDataInset)));
  };

  // Grid and axis labels.
  for (int k = kLo; k <= kHi; ++k) {
    const int y = yOf(std::pow(10.0, k));
    canvas.line(px0, y, px1, y, kGrid);
    canvas.line(px0 - kTickLength, y, px0, y, kInk);
    const std::string label = decadeLabel(k);
    canvas.text(px0 - kTickLength - 3 - textWidth(label), y + kGlyphH / 2, label, kInk);
  }
  if (!records.empty()) {
    const std::uint64_t step = niceStep(f1 - f0, kFrameTicksWanted);
    for (std::uint64_t f = (f0 + step - 1) / step * step; f <= f1; f += step) {
      const int x = xOf(f);
      canvas.line(x, py0, x, py1, kGrid);
      canvas.line(x, py0 - kTickLength, x, py0, kInk);
      const std::string label = std::to_string(f);
      canvas.text(std::clamp(x - textWidth(label) / 2, 0, width - textWidth(label) - 1), py0 - kTickLength - 3, label,
                  kInk);
    }
  }

  // The parts, total first so that the parts it contains are drawn over it.
  for (int part : {3, 2, 1, 0}) {
    const Rgb c = kPartColour[part];
    for (std::size_t i = 0; i < records.size(); ++i) {
      const int x = xOf(records[i].frame), y = yOf(records[i].micros[std::size_t(part)]);
      if (i == 0) {
        canvas.set(x, y, c);
      } else {
        canvas.line(xOf(records[i - 1].frame), yOf(records[i - 1].micros[std::size_t(part)]), x, y, c);
      }
    }
  }
  if (!records.empty()) {
    std::vector<double> total;
    total.reserve(records.size());
    for (const FrameRecord& r : records) total.push_back(r.micros[std::size_t(StepPart::Total)]);
    canvas.dashedHLine(px0, px1, yOf(percentile(total, 50)), kP50Colour);
    canvas.dashedHLine(px0, px1, yOf(percentile(total, 99)), kP99Colour);
  } else {
    canvas.text((px0 + px1 - textWidth("NO FRAMES")) / 2, (py0 + py1) / 2, "NO FRAMES", kInk);
  }

  // Axes, and the legend and units above the plot.
  canvas.line(px0, py0, px1, py0, kInk);
  canvas.line(px0, py0, px0, py1, kInk);
  canvas.text(px1 - textWidth("FRAME"), py0 - kTickLength - 3 - kGlyphH - 3, "FRAME", kInk);
  const int legendTop = height - 1 - 4;
  canvas.text(4, legendTop, "US (LOG)", kInk);
  struct Entry {
    const char* name;
    Rgb colour;
    bool dashed;
  };
  const Entry entries[] = {{"GROUND", kPartColour[0], false}, {"BROAD", kPartColour[1], false},
                           {"NARROW", kPartColour[2], false}, {"TOTAL", kPartColour[3], false},
                           {"P50", kP50Colour, true},         {"P99", kP99Colour, true}};
  int x = px0 + 8;
  constexpr int kSwatch = 16;
  for (const Entry& e : entries) {
    const int y = legendTop - kGlyphH / 2;
    if (e.dashed) {
      canvas.dashedHLine(x, x + kSwatch - 1, y, e.colour);
    } else {
      canvas.fill(x, y - 1, x + kSwatch - 1, y + 1, e.colour);
    }
    canvas.text(x + kSwatch + 4, legendTop, e.name, kInk);
    x += kSwatch + 4 + textWidth(e.name) + 14;
  }

  OutputFile file(path, ".png");
  if (!osgDB::writeImageFile(canvas.image(), file.tempPath()))
    throw InputError(path + ": cannot write the PNG (is OpenSceneGraph's png plugin installed?)");
  file.commit();
}

}  // namespace nestwalk
