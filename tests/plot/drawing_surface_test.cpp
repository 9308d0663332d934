// The report pictures' drawing surface (engine/plot/drawing_surface.h): the UI font is DejaVu
// Sans from its file and draws what the bitmap font could not ("µ", "+", lower case); shapes are
// antialiased yet exact in colour where they cover a pixel entirely; coordinates are y up; the
// PNG is written through a temporary file and read back by osgDB with the same rows; a missing
// folder is an InputError naming the path.
#include "nestwalk/plot/drawing_surface.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/core/ui_font.h"
#include "tests/common/png_readback.h"
#include "tests/common/temp_folder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace nestwalk {
namespace {

using testing::Colour;
using TempDir = test::TempFolder;

constexpr Rgb kPaper{255, 255, 255}, kInk{0, 0, 0};
constexpr double kSize = 24;  // large text, so that glyph shapes are many pixels

/// Pixels that are not paper inside a text's box.
int inkOf(const std::string& text, HAlign h = HAlign::Left) {
  DrawingSurface s(200, 60, kPaper);
  const TextBox box = s.text({100, 30}, text, {.size = kSize, .colour = kInk, .h = h, .v = VAlign::Middle});
  int n = 0;
  for (int y = int(box.bottom) - 1; y <= int(box.top) + 1; ++y)
    for (int x = int(box.left) - 1; x <= int(box.right) + 1; ++x) n += !(s.pixel(x, y) == kPaper);
  return n;
}

TEST(UiFont, IsDejaVuSansFromItsFile) {
  EXPECT_STREQ(kUiFontPath, "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf");
  ASSERT_TRUE(std::filesystem::is_regular_file(kUiFontPath)) << "install fonts-dejavu-core (tools/setup-deps.sh)";
  EXPECT_EQ(uiFontPath(), kUiFontPath);
}

TEST(DrawingSurface, TextHasTheGlyphsTheBitmapFontLacked) {
  // Each of these has ink of its own: a blank would draw nothing.
  for (const char* glyph : {"µ", "+", "a", "s", "×", "°"}) EXPECT_GT(inkOf(glyph), 20) << glyph;
  // "µs" is more than "s", "nested+mesh" more than "nested mesh", lower case differs from upper.
  EXPECT_GT(inkOf("µs"), inkOf("s") + 20);
  EXPECT_GT(inkOf("nested+mesh"), inkOf("nested mesh") + 20);
  EXPECT_NE(inkOf("frame"), inkOf("FRAME"));
  // Widths are the font's advances: "+" is wider than a space, "µs" wider than "s".
  EXPECT_GT(DrawingSurface::textWidth("nested+mesh", 12), DrawingSurface::textWidth("nested mesh", 12));
  EXPECT_GT(DrawingSurface::textWidth("µs", 12), DrawingSurface::textWidth("s", 12));
  EXPECT_NEAR(DrawingSurface::textWidth("ab", 24), 2 * DrawingSurface::textWidth("ab", 12), 0.01);
}

TEST(DrawingSurface, TextIsAntialiasedAndAnchored) {
  DrawingSurface s(200, 60, kPaper);
  const TextBox box = s.text({100, 30}, "Wave", {.size = kSize, .colour = kInk, .h = HAlign::Centre, .v = VAlign::Middle});
  EXPECT_NEAR((box.left + box.right) / 2, 100, 1e-9);
  EXPECT_NEAR(box.width(), DrawingSurface::textWidth("Wave", kSize), 1e-9);
  const DrawingSurface::FontMetrics m = DrawingSurface::fontMetrics(kSize);
  EXPECT_NEAR(box.height(), m.ascent + m.descent, 1e-9);
  EXPECT_GT(m.capHeight, 0.6 * kSize);  // DejaVu's capitals are 0.73 em
  EXPECT_LT(m.capHeight, 0.8 * kSize);
  int grey = 0, black = 0;
  for (int y = 0; y < s.height(); ++y)
    for (int x = 0; x < s.width(); ++x) {
      const Rgb c = s.pixel(x, y);
      black += c == kInk;
      grey += !(c == kInk) && !(c == kPaper);
    }
  EXPECT_GT(black, 20);
  EXPECT_GT(grey, 20) << "no antialiased edge pixels";
  // Middle: the capitals centred on y = 30 (no descender in "Wave"): ink within half a capital
  // (and a pixel of antialiasing) of it, none beyond.
  int inside = 0, outside = 0;
  for (int y = 0; y < s.height(); ++y)
    for (int x = 0; x < s.width(); ++x)
      if (!(s.pixel(x, y) == kPaper)) (std::abs(y + 0.5 - 30) <= m.capHeight / 2 + 1 ? inside : outside) += 1;
  EXPECT_GT(inside, 100);
  EXPECT_EQ(outside, 0);
}

TEST(DrawingSurface, ShapesAreExactWhereTheyCoverWholePixelsAndYIsUp) {
  DrawingSurface s(40, 30, kPaper);
  constexpr Rgb kFill{30, 40, 130}, kLine{40, 90, 255};
  s.fillRect(2, 3, 10, 8, kFill);               // whole pixels (2..9, 3..7), bottom left
  s.line({0, 20.5}, {40, 20.5}, 1, kLine);      // row 20, on pixel centres: crisp
  s.line({12, 0}, {40, 18}, 1, kInk);           // a diagonal: antialiased
  EXPECT_EQ(s.pixel(2, 3), kFill);
  EXPECT_EQ(s.pixel(9, 7), kFill);
  EXPECT_EQ(s.pixel(10, 7), kPaper);
  EXPECT_EQ(s.pixel(9, 8), kPaper);
  EXPECT_EQ(s.pixel(30, 20), kLine);
  EXPECT_EQ(s.pixel(30, 19), kPaper);
  EXPECT_EQ(s.pixel(30, 21), kPaper);
  int partial = 0;
  for (int x = 0; x < 40; ++x)
    for (int y = 0; y < 30; ++y) {
      const Rgb c = s.pixel(x, y);
      partial += !(c == kPaper) && !(c == kInk) && !(c == kFill) && !(c == kLine);
    }
  EXPECT_GT(partial, 20);
  // A disc covers the pixel holding its centre entirely.
  s.disc({20.3, 10.7}, 3, kFill);
  EXPECT_EQ(s.pixel(20, 10), kFill);
  // Pixels put as a block, rows bottom to top.
  const Rgb block[] = {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}, {10, 11, 12}};
  s.putPixels(38, 28, 2, 2, block);
  EXPECT_EQ(s.pixel(38, 28), (Rgb{1, 2, 3}));
  EXPECT_EQ(s.pixel(39, 28), (Rgb{4, 5, 6}));
  EXPECT_EQ(s.pixel(38, 29), (Rgb{7, 8, 9}));
}

TEST(DrawingSurface, PngReadsBackWithTheSameRows) {
  TempDir dir;
  DrawingSurface s(30, 20, kPaper);
  s.fillRect(0, 0, 5, 4, Rgb{200, 10, 10});  // bottom left
  s.fillRect(25, 16, 30, 20, Rgb{10, 10, 200});  // top right
  const std::string path = dir / "surface.png";
  s.writePng(path);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"surface.png"});
  const osg::ref_ptr<osg::Image> img = testing::readPng(path);
  ASSERT_TRUE(img);
  EXPECT_EQ(img->s(), 30);
  EXPECT_EQ(img->t(), 20);
  EXPECT_EQ(img->getPixelFormat(), GLenum(GL_RGB));
  EXPECT_EQ(testing::pixelAt(*img, 0, 0), (Colour{200, 10, 10}));
  EXPECT_EQ(testing::pixelAt(*img, 29, 19), (Colour{10, 10, 200}));
  EXPECT_EQ(testing::pixelAt(*img, 15, 10), testing::kWhite);
}

TEST(DrawingSurface, UnwritablePathNamesTheFileAndLeavesNothing) {
  TempDir dir;
  DrawingSurface s(10, 10, kPaper);
  const std::string missing = dir / "no/such/folder.png";
  try {
    s.writePng(missing);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  EXPECT_TRUE(dir.entries().empty());
  EXPECT_THROW(DrawingSurface(0, 10, kPaper), InputError);
}

}  // namespace
}  // namespace nestwalk
