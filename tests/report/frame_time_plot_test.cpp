// The frame-time plot (engine/report/frame_time_plot.h), read back with osgDB's own PNG reader. The
// plot area is found in the image (its black axis lines); where a time must lie is computed here
// from the documented rule (log10 over the decades enclosing every time when they are 3 or more;
// frames linear from the first record's to the last's), and each series' colour is looked for
// there. The tick marks at the decades, the labels' ink, the p50 and p99 rows (nearest-rank
// percentiles computed here), the legend, the size, the errors and the absence of temporary files.
#include "nestwalk/report/frame_time_plot.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/plot/plot_frame.h"
#include "tests/common/png_readback.h"
#include "tests/report/report_fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace nestwalk {
namespace {

using testing::Colour;
using testing::FoundAxes;
using testing::pixelAt;
using testing::sampleRecords;
using testing::TempDir;

// The colours frame_time_plot.h documents.
constexpr std::array<Colour, 4> kParts = {Colour{44, 160, 44}, Colour{31, 119, 180}, Colour{255, 127, 14},
                                          Colour{214, 39, 40}};
constexpr Colour kP50{148, 103, 189}, kP99{140, 86, 75}, kRender{227, 119, 194};

// A series' line is 2 pixels wide through the computed point; the pixel of exactly its colour lies
// within a pixel of it, and the neighbouring frames' values move it by under a pixel: 2 pixels.
constexpr int kSeriesSearch = 2;
// The percentile lines lie on the pixel row of the computed height; rounding of the height across a
// row boundary may move them by one.
constexpr int kRowSlack = 1;

/// The y axis's ends by the rule: the decades enclosing every positive time (raised to 0.001 µs).
struct Decades {
  int lo = 0, hi = 0;
  double loValue() const { return std::pow(10.0, lo); }
  double hiValue() const { return std::pow(10.0, hi); }
};
Decades decadesOf(const std::vector<FrameRecord>& records, const std::vector<RenderRecord>& renders = {}) {
  double mn = std::numeric_limits<double>::infinity(), mx = 0;
  auto cover = [&](double us) {
    if (us > 0) mn = std::min(mn, std::max(us, kFrameTimeFloorMicros)), mx = std::max(mx, us);
  };
  for (const FrameRecord& r : records)
    for (double us : r.micros) cover(us);
  for (const RenderRecord& r : renders)
    if (r.rendered) cover(r.micros[RenderPart::Total]);
  return {int(std::floor(std::log10(mn))), int(std::ceil(std::log10(mx)))};
}

/// Nearest-rank percentile: the smallest value with at least p % of the values at or below it.
double nearestRank(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  const std::size_t rank = std::size_t(std::ceil(p / 100 * double(v.size())));
  return v[std::max<std::size_t>(rank, 1) - 1];
}

/// The row holding most pixels of colour c inside the plot area.
int rowOf(const osg::Image& img, const FoundAxes& a, Colour c) {
  int bestRow = -1, best = 0;
  for (int y = a.xAxisRow; y <= a.lastRow; ++y) {
    int n = 0;
    for (int x = a.yAxisColumn; x <= a.lastColumn; ++x) n += pixelAt(img, x, y) == c;
    if (n > best) best = n, bestRow = y;
  }
  return bestRow;
}

class FrameTimePlotImage : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<TempDir>();
    writeFrameTimePlot(*dir_ / "frame_times.png", sampleRecords(kFrames), {}, 1200, 500);
    image_ = testing::readPng(*dir_ / "frame_times.png");
    if (image_) axes_ = testing::findAxes(*image_, kPlotDataInset);
  }
  static void TearDownTestSuite() {
    image_ = nullptr;
    dir_.reset();
  }
  void SetUp() override { ASSERT_NE(image_, nullptr); }

  static constexpr std::size_t kFrames = 600;
  static inline std::unique_ptr<TempDir> dir_;
  static inline osg::ref_ptr<osg::Image> image_;
  static inline FoundAxes axes_;
};

TEST_F(FrameTimePlotImage, SizeFormatAndNoTemporaryFile) {
  EXPECT_EQ(image_->s(), 1200);
  EXPECT_EQ(image_->t(), 500);
  EXPECT_EQ(image_->getPixelFormat(), GLenum(GL_RGB));
  EXPECT_EQ(image_->getDataType(), GLenum(GL_UNSIGNED_BYTE));
  EXPECT_EQ(dir_->entries(), std::vector<std::string>{"frame_times.png"});
  // The axes span most of the image: the plot is not squeezed by its margins.
  EXPECT_GT(axes_.lastColumn - axes_.yAxisColumn, 1200 * 3 / 4);
  EXPECT_GT(axes_.lastRow - axes_.xAxisRow, 500 / 2);
  EXPECT_EQ(axes_.firstColumn, axes_.yAxisColumn);  // the axes meet at the corner
  EXPECT_EQ(axes_.firstRow, axes_.xAxisRow);
}

TEST_F(FrameTimePlotImage, EachPartLiesWhereTheLogAxisPutsItsTime) {
  const std::vector<FrameRecord> records = sampleRecords(kFrames);
  const Decades d = decadesOf(records);
  // The sample's times run from 0.1 µs (ground) to ~55 µs (a spiky total): decades -1 .. 2, three
  // of them, so the axis runs over whole decades.
  ASSERT_EQ(d.lo, -1);
  ASSERT_EQ(d.hi, 2);
  const double f0 = double(records.front().frame), f1 = double(records.back().frame);
  // Frames away from the spikes (every 37th), so that the line is level around them.
  for (std::size_t i : {100u, 250u, 400u, 520u})
    for (std::size_t k = 0; k < 4; ++k) {
      const double us = records[i].micros[kAllStepParts[k]];
      const double x = axes_.x((double(records[i].frame) - f0) / (f1 - f0));
      const double y = axes_.y(testing::logFraction(us, d.loValue(), d.hiValue()));
      EXPECT_TRUE(testing::colourNear(*image_, int(x), int(y), kParts[k], kSeriesSearch))
          << "part " << k << " at frame " << records[i].frame << " (" << us << " µs) not near pixel " << int(x) << ", "
          << int(y);
    }
}

TEST_F(FrameTimePlotImage, DecadesHaveTicksAndLabels) {
  const Decades d = decadesOf(sampleRecords(kFrames));
  for (int k = d.lo; k <= d.hi; ++k) {
    const int y = int(axes_.y(double(k - d.lo) / double(d.hi - d.lo)));
    // A black tick mark left of the y axis...
    EXPECT_EQ(pixelAt(*image_, axes_.yAxisColumn - 2, y), testing::kBlack) << "decade " << k;
    // ... and its label ("0.1 µs" .. "100 µs") left of the tick.
    EXPECT_GT(testing::inkIn(*image_, axes_.yAxisColumn - 60, y - 5, axes_.yAxisColumn - 6, y + 5), 15)
        << "decade " << k;
  }
  // Frame labels under the x axis, the axis title at its right end.
  EXPECT_GT(testing::inkIn(*image_, axes_.yAxisColumn, 0, axes_.lastColumn, axes_.xAxisRow - 5), 100);
}

TEST_F(FrameTimePlotImage, PercentileLinesAreDashedOnTheirRows) {
  const std::vector<FrameRecord> records = sampleRecords(kFrames);
  const Decades d = decadesOf(records);
  std::vector<double> total;
  for (const FrameRecord& r : records) total.push_back(r.micros[StepPart::Total]);
  for (const auto& [p, colour] : {std::pair{50.0, kP50}, std::pair{99.0, kP99}}) {
    const int expected = int(axes_.y(testing::logFraction(nearestRank(total, p), d.loValue(), d.hiValue())));
    const int row = rowOf(*image_, axes_, colour);
    EXPECT_NEAR(row, expected, kRowSlack) << "p" << p;
    // Dashed: along the row the colour starts again and again.
    int runs = 0;
    bool in = false;
    for (int x = axes_.yAxisColumn; x <= axes_.lastColumn; ++x) {
      const bool hit = pixelAt(*image_, x, row) == colour;
      runs += hit && !in;
      in = hit;
    }
    EXPECT_GT(runs, 50) << "p" << p;
  }
}

TEST_F(FrameTimePlotImage, TitleAndLegendAboveThePlot) {
  // Every series' swatch in the legend, above the plot area.
  for (Colour c : {kParts[0], kParts[1], kParts[2], kParts[3], kP50, kP99}) {
    int n = 0;
    for (int y = axes_.lastRow + 2; y < image_->t(); ++y)
      for (int x = 0; x < image_->s(); ++x) n += pixelAt(*image_, x, y) == c;
    EXPECT_GT(n, 4) << c;
  }
  // No render entry without rendered frames.
  int render = 0;
  for (int y = 0; y < image_->t(); ++y)
    for (int x = 0; x < image_->s(); ++x) render += pixelAt(*image_, x, y) == kRender;
  EXPECT_EQ(render, 0);
  // Text in the header (title and names).
  EXPECT_GT(testing::inkIn(*image_, 0, axes_.lastRow + 2, image_->s() - 1, image_->t() - 1), 800);
}

TEST(FrameTimePlot, RenderTimesLieOnTheirOwnDecades) {
  TempDir dir;
  const std::vector<FrameRecord> records = sampleRecords(600);
  const std::vector<RenderRecord> renders = testing::sampleRenders(600);  // every third frame, ~34 ms
  writeFrameTimePlot(dir / "rendered.png", records, renders, 1200, 500);
  const osg::ref_ptr<osg::Image> img = testing::readPng(dir / "rendered.png");
  ASSERT_TRUE(img);
  const FoundAxes a = testing::findAxes(*img, kPlotDataInset);
  const Decades d = decadesOf(records, renders);
  ASSERT_EQ(d.lo, -1);  // 0.1 µs (ground) .. 40.6 ms (render): 6 decades
  ASSERT_EQ(d.hi, 5);
  const double f0 = double(records.front().frame), f1 = double(records.back().frame);
  for (std::size_t i : {99u, 300u, 501u}) {
    ASSERT_TRUE(renders[i].rendered);
    const double x = a.x((double(records[i].frame) - f0) / (f1 - f0));
    const double y = a.y(testing::logFraction(renders[i].micros[RenderPart::Total], d.loValue(), d.hiValue()));
    EXPECT_TRUE(testing::colourNear(*img, int(x), int(y), kRender, kSeriesSearch)) << "frame " << records[i].frame;
    const double yTotal = a.y(testing::logFraction(records[i].micros[StepPart::Total], d.loValue(), d.hiValue()));
    EXPECT_TRUE(testing::colourNear(*img, int(x), int(yTotal), kParts[3], kSeriesSearch)) << "frame " << records[i].frame;
  }
}

TEST(FrameTimePlot, OtherSizesAndEmptyRun) {
  TempDir dir;
  writeFrameTimePlot(dir / "small.png", sampleRecords(5), {}, 400, 200);
  osg::ref_ptr<osg::Image> img = testing::readPng(dir / "small.png");
  ASSERT_TRUE(img);
  EXPECT_EQ(img->s(), 400);
  EXPECT_EQ(img->t(), 200);
  int total = 0;
  for (int y = 0; y < img->t(); ++y)
    for (int x = 0; x < img->s(); ++x) total += pixelAt(*img, x, y) == kParts[3];
  EXPECT_GT(total, 10);

  // No records: the axes and "no frames" in the middle of the plot area.
  writeFrameTimePlot(dir / "empty.png", {}, {}, 600, 300);
  img = testing::readPng(dir / "empty.png");
  ASSERT_TRUE(img);
  EXPECT_EQ(img->s(), 600);
  const FoundAxes a = testing::findAxes(*img, kPlotDataInset);
  ASSERT_GT(a.lastColumn - a.yAxisColumn, 300);
  const int cx = int((a.left() + a.right()) / 2), cy = int((a.bottom() + a.top()) / 2);
  EXPECT_GT(testing::inkIn(*img, cx - 40, cy - 8, cx + 40, cy + 8), 40);

  // Timing off (all zero): every line lies at the axis's lower end, the ground (drawn last) on top,
  // seen between the dashes of the percentile lines over it (a period of 10 pixels: look 5 to
  // either side).
  std::vector<FrameRecord> zero = sampleRecords(20);
  for (FrameRecord& r : zero) r.micros = {};
  writeFrameTimePlot(dir / "zero.png", zero);
  img = testing::readPng(dir / "zero.png");
  ASSERT_TRUE(img);
  const FoundAxes z = testing::findAxes(*img, kPlotDataInset);
  for (double f : {0.25, 0.5, 0.75})
    EXPECT_TRUE(testing::colourNear(*img, int(z.x(f)), int(z.y(0)), kParts[0], 5)) << "at " << f;
  EXPECT_EQ(dir.entries().size(), 3u);
}

TEST(FrameTimePlot, BadSizeOrFolderNamesTheFile) {
  TempDir dir;
  const std::string tiny = dir / "tiny.png";
  try {
    writeFrameTimePlot(tiny, sampleRecords(5), {}, kMinFrameTimePlotWidth - 1, kMinFrameTimePlotHeight);
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
  // The smallest allowed size still draws.
  EXPECT_NO_THROW(writeFrameTimePlot(dir / "least.png", sampleRecords(5), {}, kMinFrameTimePlotWidth,
                                     kMinFrameTimePlotHeight));
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"least.png"});
}

}  // namespace
}  // namespace nestwalk
