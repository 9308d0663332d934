// The frame-time plot (engine/report/frame_record.h), read back with osgDB's own PNG reader: size,
// drawn pixels inside the plot, each documented colour present where it belongs.
#include "nestwalk/report/frame_time_plot.h"

#include "nestwalk/core/input_error.h"
#include "tests/report/report_fixtures.h"

#include <gtest/gtest.h>
#include <osg/Image>
#include <osgDB/ReadFile>

#include <algorithm>
#include <array>
#include <limits>

namespace nestwalk {
namespace {

using testing::sampleRecords;
using testing::TempDir;

struct Rgb {
  int r, g, b;
  bool operator==(const Rgb&) const = default;
};

// The colours frame_record.h documents.
constexpr Rgb kBackground{255, 255, 255};
constexpr std::array<Rgb, 4> kParts = {Rgb{44, 160, 44}, Rgb{31, 119, 180}, Rgb{255, 127, 14}, Rgb{214, 39, 40}};
constexpr Rgb kP50{148, 103, 189}, kP99{140, 86, 75};

/// Where the pixels of one colour lie (y up, as osg::Image rows).
struct Spread {
  std::size_t count = 0;
  int minX = std::numeric_limits<int>::max(), maxX = -1, minY = std::numeric_limits<int>::max(), maxY = -1;
  double sumY = 0;
  double meanY() const { return count ? sumY / double(count) : 0; }
};

Rgb pixel(const osg::Image& img, int x, int y) {
  const unsigned char* p = img.data(unsigned(x), unsigned(y));
  return {p[0], p[1], p[2]};
}

Spread spreadOf(const osg::Image& img, Rgb c) {
  Spread s;
  for (int y = 0; y < img.t(); ++y)
    for (int x = 0; x < img.s(); ++x)
      if (pixel(img, x, y) == c) {
        ++s.count;
        s.minX = std::min(s.minX, x);
        s.maxX = std::max(s.maxX, x);
        s.minY = std::min(s.minY, y);
        s.maxY = std::max(s.maxY, y);
        s.sumY += y;
      }
  return s;
}

osg::ref_ptr<osg::Image> readBack(const std::string& path) {
  osg::ref_ptr<osg::Image> img = osgDB::readImageFile(path);
  if (!img) ADD_FAILURE() << "osgDB cannot read " << path;
  return img;
}

TEST(FrameTimePlot, ReadsBackWithEveryPartDrawn) {
  TempDir dir;
  const std::vector<FrameRecord> records = sampleRecords(600);
  const std::string path = dir / "frame_times.png";
  writeFrameTimePlot(path, records, {}, 1200, 500);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"frame_times.png"});
  const osg::ref_ptr<osg::Image> img = readBack(path);
  ASSERT_TRUE(img);
  ASSERT_EQ(img->s(), 1200);
  ASSERT_EQ(img->t(), 500);
  ASSERT_EQ(img->getPixelFormat(), GLenum(GL_RGB));
  ASSERT_EQ(img->getDataType(), GLenum(GL_UNSIGNED_BYTE));

  // The inner 80 % x 70 % of the image is inside any reasonable plot area: it must be drawn on.
  std::size_t drawn = 0, inner = 0;
  for (int y = img->t() * 15 / 100; y < img->t() * 85 / 100; ++y)
    for (int x = img->s() * 10 / 100; x < img->s() * 90 / 100; ++x, ++inner)
      drawn += !(pixel(*img, x, y) == kBackground);
  EXPECT_GT(drawn, inner / 50) << "almost nothing drawn in the plot area";

  // Each part's line runs across the plot, at heights in the order of the parts' magnitudes
  // (ground 0.1 µs < broad 1 µs < narrow 5 µs < total 10 µs on a monotone scale).
  std::array<Spread, 4> s;
  for (std::size_t k = 0; k < 4; ++k) {
    s[k] = spreadOf(*img, kParts[k]);
    EXPECT_GT(s[k].count, 600u) << "part " << k;
    EXPECT_GT(s[k].maxX - s[k].minX, img->s() * 3 / 4) << "part " << k;
  }
  for (std::size_t k = 1; k < 4; ++k) EXPECT_GT(s[k].meanY(), s[k - 1].meanY()) << "part " << k;

  // p50 and p99 of the total: dashed horizontal lines (one row each in the plot, plus the legend's
  // swatch), the p99 one above the p50 one, both within the total's range.
  const Spread p50 = spreadOf(*img, kP50), p99 = spreadOf(*img, kP99);
  ASSERT_GT(p50.count, 300u);
  ASSERT_GT(p99.count, 300u);
  auto plotRowOf = [&](Rgb c) {  // the row holding most of the colour's pixels
    std::vector<int> perRow(std::size_t(img->t()), 0);
    for (int y = 0; y < img->t(); ++y)
      for (int x = 0; x < img->s(); ++x) perRow[std::size_t(y)] += pixel(*img, x, y) == c;
    return int(std::max_element(perRow.begin(), perRow.end()) - perRow.begin());
  };
  const int y50 = plotRowOf(kP50), y99 = plotRowOf(kP99);
  EXPECT_GT(y99, y50);
  EXPECT_GE(y50, s[3].minY);
  EXPECT_LE(y99, s[3].maxY);
  // Dashed: along the p50 row the colour alternates with other pixels.
  int runs = 0;
  bool in = false;
  for (int x = 0; x < img->s(); ++x) {
    const bool hit = pixel(*img, x, y50) == kP50;
    runs += hit && !in;
    in = hit;
  }
  EXPECT_GT(runs, 50);
}

TEST(FrameTimePlot, RenderTimesAboveTheStepsWhenFramesWereRendered) {
  TempDir dir;
  constexpr Rgb kRender{227, 119, 194};
  std::vector<FrameRecord> records = sampleRecords(600);
  writeFrameTimePlot(dir / "rendered.png", records, testing::sampleRenders(600), 1200, 500);  // every third frame, ~30 ms
  const osg::ref_ptr<osg::Image> img = readBack(dir / "rendered.png");
  ASSERT_TRUE(img);
  const Spread render = spreadOf(*img, kRender), total = spreadOf(*img, kParts[3]);
  EXPECT_GT(render.count, 600u);
  EXPECT_GT(render.maxX - render.minX, img->s() * 3 / 4);
  EXPECT_GT(render.meanY(), total.meanY() + 100) << "render times (ms) lie far above the step totals (us)";
  writeFrameTimePlot(dir / "plain.png", records, {}, 1200, 500);
  const osg::ref_ptr<osg::Image> plain = readBack(dir / "plain.png");
  ASSERT_TRUE(plain);
  EXPECT_EQ(spreadOf(*plain, kRender).count, 0u);
}

TEST(FrameTimePlot, OtherSizesAndEmptyRun) {
  TempDir dir;
  writeFrameTimePlot(dir / "small.png", sampleRecords(5), {}, 400, 200);
  osg::ref_ptr<osg::Image> img = readBack(dir / "small.png");
  ASSERT_TRUE(img);
  EXPECT_EQ(img->s(), 400);
  EXPECT_EQ(img->t(), 200);
  EXPECT_GT(spreadOf(*img, kParts[3]).count, 0u);

  writeFrameTimePlot(dir / "empty.png", {}, {}, 600, 300);
  img = readBack(dir / "empty.png");
  ASSERT_TRUE(img);
  EXPECT_EQ(img->s(), 600);
  std::size_t drawn = 0;
  for (int y = 0; y < img->t(); ++y)
    for (int x = 0; x < img->s(); ++x) drawn += !(pixel(*img, x, y) == kBackground);
  EXPECT_GT(drawn, 0u);  // axes and legend

  // Timing off (all zero) draws the lines on the floor instead of failing.
  std::vector<FrameRecord> zero = sampleRecords(20);
  for (FrameRecord& r : zero) r.micros = {};
  EXPECT_NO_THROW(writeFrameTimePlot(dir / "zero.png", zero));
}

TEST(FrameTimePlot, BadSizeOrFolderNamesTheFile) {
  TempDir dir;
  const std::string tiny = dir / "tiny.png";
  try {
    writeFrameTimePlot(tiny, sampleRecords(5), {}, 20, 10);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(tiny), std::string::npos) << e.what();
  }
  const std::string missing = dir / "no/plot.png";
  try {
    writeFrameTimePlot(missing, sampleRecords(5));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  EXPECT_TRUE(dir.entries().empty());
}

}  // namespace
}  // namespace nestwalk
