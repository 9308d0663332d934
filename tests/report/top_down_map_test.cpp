// The top-down map of a run (engine/report/top_down_map.h), read back with osgDB's own PNG reader:
// a synthetic scene at UTM magnitudes (a plane falling to the south-east with a pit and a hole,
// a rotated container and a pole) and a run over it; the image's size and north-up frame, the
// hillshade against the plane's own Lambert shade, the hole, the path, blocked frames, the blocking
// unit's outline, expectations and footprints are checked at pixels computed from the construction;
// the legend column's swatches and text, and its scale bar (segments of a 1-2-5 length of metres);
// a map coarser than the terrain's cells drawn from its pyramid's level (a sloped plane at 70 N).
#include "nestwalk/report/top_down_map.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/terrain/terrain_import.h"
#include "nestwalk/terrain/terrain_pyramid.h"
#include "tests/report/report_fixtures.h"

#include <gtest/gtest.h>
#include <osg/Image>
#include <osgDB/ReadFile>

#include <cmath>
#include <memory>
#include <numbers>

namespace nestwalk {
namespace {

using testing::TempDir;

struct Rgb {
  int r, g, b;
  bool operator==(const Rgb&) const = default;
};
std::ostream& operator<<(std::ostream& os, const Rgb& c) { return os << "(" << c.r << ", " << c.g << ", " << c.b << ")"; }

// The colours top_down_map.h documents.
constexpr Rgb kHoleGrey{128, 128, 128};
constexpr Rgb kWalk{40, 90, 255}, kFly{0, 215, 255};
constexpr Rgb kRed{230, 0, 0}, kMet{0, 190, 0};
constexpr Rgb kContainer{150, 65, 25}, kPole{255, 215, 0};
constexpr Rgb kLowTint{96, 140, 96}, kHighTint{236, 214, 170};

// The terrain: 121 x 101 samples 2 m apart, sample (0, 0) at a UTM position; heights
// 200 - 0.5 c - 0.25 r (exact in float: a plane falling east and south), a paraboloid pit 10 m
// deep and 16 m across in radius about sample (45, 65), a 5 x 5 hole of nodata at columns 60-64,
// rows 40-44.
constexpr int kCols = 121, kRows = 101;
constexpr double kCell = 2.0, kOriginX = 550000.5, kOriginY = 4650100.5;
constexpr int kPitCol = 45, kPitRow = 65;
constexpr double kPitRadius = 8, kPitDepth = 10;  // radius in samples
constexpr float kNoData = -9999;
constexpr int kHoleCol = 60, kHoleRow = 40, kHoleSize = 5;

double planeAt(double col, double row) { return 200 - 0.5 * col - 0.25 * row; }
double planeAtMap(double x, double y) { return planeAt((x - kOriginX) / kCell, (kOriginY - y) / kCell); }
Eigen::Vector2d samplePoint(double col, double row) { return {kOriginX + col * kCell, kOriginY - row * kCell}; }

std::vector<float> terrainSamples() {
  std::vector<float> h;
  for (int r = 0; r < kRows; ++r)
    for (int c = 0; c < kCols; ++c) {
      const double d2 = (c - kPitCol) * (c - kPitCol) + (r - kPitRow) * (r - kPitRow);
      const double pit = d2 < kPitRadius * kPitRadius ? kPitDepth * (1 - d2 / (kPitRadius * kPitRadius)) : 0;
      const bool hole = c >= kHoleCol && c < kHoleCol + kHoleSize && r >= kHoleRow && r < kHoleRow + kHoleSize;
      h.push_back(hole ? kNoData : float(planeAt(c, r) - pit));
    }
  return h;
}

// Equipment: a container turned 30° anticlockwise (seen from above) and a thin pole, each its own
// collision unit.
const Eigen::Vector2d kContainerCentre{550100, 4649996};
constexpr double kContainerTurn = 30 * std::numbers::pi / 180;
const Eigen::Vector3d kContainerHalf{3, 1.2, 1.3};
const Eigen::Vector2d kPoleCentre{550160, 4649980};
Eigen::Vector2d containerAxisU() { return {std::cos(kContainerTurn), std::sin(kContainerTurn)}; }
Eigen::Vector2d containerAxisV() { return {-std::sin(kContainerTurn), std::cos(kContainerTurn)}; }
Eigen::Vector2d containerPoint(double u, double v) { return kContainerCentre + u * containerAxisU() + v * containerAxisV(); }

Scene testScene() {
  Scene scene;
  std::vector<float> samples = terrainSamples();
  scene.terrain = std::make_shared<const terrain::Heightfield>(kCols, kRows, std::move(samples), kOriginX, kOriginY,
                                                               kCell, kCell, kNoData);
  scene.origin = Eigen::Vector3d(550120, 4650000, 0);
  auto add = [&](const std::string& name, const std::string& kind, const Obb<double>& mapBox) {
    EquipmentSpec spec;
    spec.name = name;
    spec.kind = kind;
    scene.spec.equipment.push_back(spec);
    Obb<double> local = mapBox;
    local.center -= scene.origin;
    SceneInstance instance;
    instance.spec = std::uint32_t(scene.instances.size());
    instance.volume = NestedVolume<double>::fromObb(local);
    instance.unit = std::uint32_t(scene.units.size());
    scene.instances.push_back(instance);
    CollisionUnit unit;
    unit.name = name;
    unit.kind = kind;
    unit.volume = instance.volume;
    unit.instances = {instance.spec};
    scene.units.push_back(unit);
  };
  Obb<double> container;
  container.center = Eigen::Vector3d(kContainerCentre.x(), kContainerCentre.y(), 150);
  container.axes.col(0) << containerAxisU(), 0;
  container.axes.col(1) << containerAxisV(), 0;
  container.halfExtents = kContainerHalf;
  add("yard/container", "container", container);
  Obb<double> pole;
  pole.center = Eigen::Vector3d(kPoleCentre.x(), kPoleCentre.y(), 160);
  pole.halfExtents = Eigen::Vector3d(0.05, 0.05, 2);
  add("pole1", "pole", pole);
  return scene;
}

// The run: 161 frames walking east along y = 4649990 from x = 550060 to 550140 (0.5 m a frame),
// frames 80-84 blocked by the container, then 41 frames flying north to y = 4650010.
constexpr double kWalkY = 4649990, kWalkX0 = 550060;
constexpr int kWalkFrames = 161, kFlyFrames = 41;
constexpr int kFirstBlocked = 80, kLastBlocked = 84;

std::vector<FrameRecord> testRecords() {
  std::vector<FrameRecord> records;
  for (int i = 0; i < kWalkFrames + kFlyFrames; ++i) {
    FrameRecord r;
    r.frame = std::uint64_t(i + 1);
    r.flying = i >= kWalkFrames;
    r.eye = r.flying ? Eigen::Vector3d(kWalkX0 + 0.5 * (kWalkFrames - 1), kWalkY + 0.5 * (i - kWalkFrames), 170)
                     : Eigen::Vector3d(kWalkX0 + 0.5 * i, kWalkY, 160);
    if (i >= kFirstBlocked && i <= kLastBlocked) {
      r.blocked = true;
      r.blockedBy = "yard/container";
    }
    records.push_back(r);
  }
  return records;
}

std::vector<ExpectationResult> testExpectations() {
  ExpectationResult met, failed;
  met.met = true;
  met.eye = Eigen::Vector3d(550080, kWalkY, 160);
  failed.met = false;
  failed.eye = Eigen::Vector3d(550140, 4650005, 170);
  return {met, failed};
}

osg::ref_ptr<osg::Image> readBack(const std::string& path) {
  osg::ref_ptr<osg::Image> img = osgDB::readImageFile(path);
  if (!img) ADD_FAILURE() << "osgDB cannot read " << path;
  return img;
}

Rgb pixel(const osg::Image& img, const Eigen::Vector2i& p) {
  const unsigned char* d = img.data(unsigned(p.x()), unsigned(p.y()));
  return {d[0], d[1], d[2]};
}

/// The map written once for the tests that look at its pixels (maxSize 800, default margin).
class TopDownMapImage : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<TempDir>();
    const Scene scene = testScene();
    options_.maxSize = 800;
    writeTopDownMap(*dir_ / "map.png", scene, testRecords(), testExpectations(), options_);
    frame_ = topDownFrame(scene, testRecords(), testExpectations(), options_);
    image_ = readBack(*dir_ / "map.png");
  }
  static void TearDownTestSuite() {
    image_ = nullptr;
    dir_.reset();
  }
  /// The colour at a map point.
  Rgb at(const Eigen::Vector2d& map) const {
    const Eigen::Vector2i p = frame_.pixelOf(map);
    EXPECT_TRUE(frame_.inside(p)) << "map point " << map.transpose() << " is off the image";
    return frame_.inside(p) ? pixel(*image_, p) : Rgb{-1, -1, -1};
  }
  void SetUp() override { ASSERT_NE(image_, nullptr); }

  static inline std::unique_ptr<TempDir> dir_;
  static inline TopDownMapOptions options_;
  static inline TopDownFrame frame_;
  static inline osg::ref_ptr<osg::Image> image_;
};

TEST_F(TopDownMapImage, SizeFollowsThePathExtentAndMargin) {
  // Eyes span x 550060..550140 and y 4649990..4650010; with 40 m of margin each side the area is
  // 160 m x 100 m, wide enough to fill the 800 pixels less the legend column.
  ASSERT_GT(frame_.legendWidth, 100);  // "expectation failed" alone is ~110 pixels at 12 px
  ASSERT_LT(frame_.legendWidth, 300);
  const int mapColumns = 800 - frame_.legendWidth;
  EXPECT_EQ(frame_.width, mapColumns);
  EXPECT_DOUBLE_EQ(frame_.metresPerPixel, 160.0 / mapColumns);
  EXPECT_EQ(frame_.height, int(std::ceil(100.0 * mapColumns / 160.0)));
  EXPECT_EQ(image_->s(), 800);
  EXPECT_EQ(image_->t(), frame_.height);
  // The area is centred: its edges lie within a pixel of the map's.
  const double m = frame_.metresPerPixel;
  EXPECT_NEAR(frame_.west, 550020, 1e-6);
  EXPECT_NEAR(frame_.west + frame_.width * m, 550180, 1e-6);
  EXPECT_GT(frame_.south, 4649950 - m);
  EXPECT_LE(frame_.south, 4649950);
  EXPECT_NEAR(frame_.south + 0.5 * frame_.height * m, 4650000, 1e-6);
  EXPECT_EQ(dir_->entries(), std::vector<std::string>{"map.png"});
}

TEST_F(TopDownMapImage, FrameIsNorthUpWithSquarePixels) {
  const double m = frame_.metresPerPixel;
  const Eigen::Vector2d centre = frame_.pixelCentre(123, 45);
  EXPECT_NEAR(centre.x(), frame_.west + 123.5 * m, 1e-6);
  EXPECT_NEAR(centre.y(), frame_.south + 45.5 * m, 1e-6);
  EXPECT_EQ(frame_.pixelOf(centre), Eigen::Vector2i(123, 45));
  EXPECT_EQ(frame_.pixelOf(centre + Eigen::Vector2d(0, 10 * m)), Eigen::Vector2i(123, 55));  // north: rows up
  EXPECT_EQ(frame_.pixelOf(centre + Eigen::Vector2d(10 * m, 0)), Eigen::Vector2i(133, 45));  // east: columns right
  // The legend column is white paper right of the map (here its left padding), a black line
  // between them.
  EXPECT_EQ(pixel(*image_, {frame_.width + 3, frame_.height / 2}), (Rgb{255, 255, 255}));
  EXPECT_EQ(pixel(*image_, {frame_.width, frame_.height / 2}), (Rgb{0, 0, 0}));
}

TEST_F(TopDownMapImage, HillshadeIsTheLambertShadeOfThePlane) {
  // The plane z = 200 - 0.5 c - 0.25 r with c = (x - x0) / 2, r = (y0 - y) / 2: dz/dx = -0.25,
  // dz/dy = +0.125. Sun: azimuth 315°, altitude 45°.
  const Eigen::Vector3d normal = Eigen::Vector3d(0.25, -0.125, 1).normalized();
  const double alt = std::numbers::pi / 4, az = 7 * std::numbers::pi / 4;
  const Eigen::Vector3d sun(std::cos(alt) * std::sin(az), std::cos(alt) * std::cos(az), std::sin(alt));
  const double shade = std::max(0.0, normal.dot(sun));
  // Height range: the highest sample is (0, 0) at 200, the lowest the plane's far corner
  // (120, 100) at 115 (the pit's bottom is at 151.25).
  const double lowest = planeAt(120, 100), highest = planeAt(0, 0);
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(550150.3, 4650030.7), Eigen::Vector2d(550120.3, 4650040.7),
                                   Eigen::Vector2d(550170.0, 4649965.0)}) {
    const Eigen::Vector2d centre = frame_.pixelCentre(frame_.pixelOf(p).x(), frame_.pixelOf(p).y());
    const double f = (planeAtMap(centre.x(), centre.y()) - lowest) / (highest - lowest);
    const double light = 0.35 + 0.65 * shade;
    const Rgb expected{int(std::lround((kLowTint.r + f * (kHighTint.r - kLowTint.r)) * light)),
                       int(std::lround((kLowTint.g + f * (kHighTint.g - kLowTint.g)) * light)),
                       int(std::lround((kLowTint.b + f * (kHighTint.b - kLowTint.b)) * light))};
    const Rgb got = at(p);
    EXPECT_NEAR(got.r, expected.r, 1) << "at " << p.transpose();
    EXPECT_NEAR(got.g, expected.g, 1) << "at " << p.transpose();
    EXPECT_NEAR(got.b, expected.b, 1) << "at " << p.transpose();
  }
}

TEST_F(TopDownMapImage, PitWallFacingTheSunIsBrighterThanTheOneFacingAway) {
  // The pit's south-east wall rises to the south-east, so it faces the north-west sun.
  const Eigen::Vector2d pit = samplePoint(kPitCol, kPitRow);
  auto brightness = [&](const Eigen::Vector2d& p) {
    const Rgb c = at(p);
    return c.r + c.g + c.b;
  };
  EXPECT_GT(brightness(pit + Eigen::Vector2d(7, -7)), brightness(pit + Eigen::Vector2d(-7, 7)) + 60);
}

TEST_F(TopDownMapImage, HoleIsFlatGrey) {
  EXPECT_EQ(at(samplePoint(kHoleCol + 2, kHoleRow + 2)), kHoleGrey);
  EXPECT_EQ(at(samplePoint(kHoleCol + 0.3, kHoleRow + 3.6)), kHoleGrey);
}

TEST_F(TopDownMapImage, PathIsDrawnInItsModeColour) {
  const std::vector<FrameRecord> records = testRecords();
  for (int i : {20, 30, 60, 130}) EXPECT_EQ(at(records[std::size_t(i)].eye.head<2>()), kWalk) << "frame " << i;
  for (int i : {kWalkFrames + 8, kWalkFrames + 15}) EXPECT_EQ(at(records[std::size_t(i)].eye.head<2>()), kFly) << "frame " << i;
}

TEST_F(TopDownMapImage, BlockedFramesAndTheirBlockerAreRed) {
  const std::vector<FrameRecord> records = testRecords();
  for (int i = kFirstBlocked; i <= kLastBlocked; ++i) EXPECT_EQ(at(records[std::size_t(i)].eye.head<2>()), kRed);
  // The container's footprint is outlined in red: points on its long edges.
  EXPECT_EQ(at(containerPoint(0.5, kContainerHalf.y())), kRed);
  EXPECT_EQ(at(containerPoint(-0.5, -kContainerHalf.y())), kRed);
}

TEST_F(TopDownMapImage, FootprintsAreTheInnerBoxesInTheirKindColour) {
  EXPECT_EQ(at(kContainerCentre), kContainer);
  EXPECT_EQ(at(containerPoint(1.5, 0)), kContainer);
  // Inside the container's axis-aligned box but 1.2 m outside its turned box: terrain.
  const Eigen::Vector2d outside = containerPoint(1.5, -2.4);
  const Eigen::Vector2d offset = outside - kContainerCentre;
  ASSERT_LT(std::abs(offset.x()), kContainerHalf.x() * std::cos(kContainerTurn) + kContainerHalf.y() * std::sin(kContainerTurn));
  ASSERT_LT(std::abs(offset.y()), kContainerHalf.x() * std::sin(kContainerTurn) + kContainerHalf.y() * std::cos(kContainerTurn));
  EXPECT_NE(at(outside), kContainer);
  EXPECT_NE(at(outside), kRed);
  // The pole is narrower than a pixel: drawn as a small disc of its colour.
  EXPECT_EQ(at(kPoleCentre), kPole);
}

TEST_F(TopDownMapImage, ExpectationsAreGreenWhenMetAndRedWhenFailed) {
  const std::vector<ExpectationResult> expectations = testExpectations();
  EXPECT_EQ(at(expectations[0].eye.head<2>()), kMet);
  EXPECT_EQ(at(expectations[1].eye.head<2>()), kRed);
}

TEST_F(TopDownMapImage, LegendColumnShowsTheRunsMarksAndTheKinds) {
  // Every mark of the run and both kinds have a swatch of their colour in the column.
  for (const Rgb c : {kWalk, kFly, kRed, kMet, kContainer, kPole}) {
    int n = 0;
    for (int y = 0; y < image_->t(); ++y)
      for (int x = frame_.width + 1; x < image_->s(); ++x) n += pixel(*image_, {x, y}) == c;
    EXPECT_GT(n, 3) << c;
  }
  // Text: the labels right of the swatches, in the column's upper half.
  int ink = 0;
  for (int y = image_->t() / 2; y < image_->t(); ++y)
    for (int x = frame_.width + 30; x < image_->s(); ++x) ink += !(pixel(*image_, {x, y}) == Rgb{255, 255, 255});
  EXPECT_GT(ink, 7 * 40);  // seven entries
}

TEST_F(TopDownMapImage, ScaleBarIsAWholeNumberOfOneTwoFiveSegments) {
  // The bar's outline is the longest black run in the column's bottom rows; its middle row is
  // black and white segments of one 1-2-5 length each, at most 5 of them, and the whole bar is a
  // 1-2-5 length too.
  int bestRow = -1, bestFirst = -1, best = 0;
  for (int y = 0; y < 60; ++y)
    for (int x = frame_.width + 2, run = 0; x < image_->s(); ++x) {
      run = pixel(*image_, {x, y}) == Rgb{0, 0, 0} ? run + 1 : 0;
      if (run > best) best = run, bestRow = y, bestFirst = x - run + 1;
    }
  ASSERT_GT(best, 20) << "no scale bar";
  EXPECT_LE(best, frame_.legendWidth - 2 * 8);  // within the column's padding
  const int middle = bestRow + 3;
  int segments = 0;
  bool black = false;
  for (int x = bestFirst + 1; x < bestFirst + best - 1; ++x) {
    const Rgb c = pixel(*image_, {x, middle});
    if (c == Rgb{0, 0, 0} && !black) ++segments, black = true;
    if (c == Rgb{255, 255, 255} && black) ++segments, black = false;
  }
  ASSERT_GE(segments, 2);
  ASSERT_LE(segments, 5);
  // The bar's ends are rounded to whole pixels: a pixel of slack over its length.
  auto oneTwoFive = [&](double metres, double pixels) {
    const double mantissa = metres / std::pow(10.0, std::floor(std::log10(metres)));
    const double slack = 1.0 / pixels;  // relative
    for (double m : {1.0, 2.0, 5.0, 10.0})
      if (std::abs(mantissa - m) < m * slack) return true;
    return false;
  };
  const double barMetres = best * frame_.metresPerPixel;
  EXPECT_TRUE(oneTwoFive(barMetres, best)) << "a bar of " << barMetres << " m";
  EXPECT_TRUE(oneTwoFive(barMetres / segments, double(best) / segments)) << segments << " segments of " << barMetres / segments << " m";
  // Labels under the bar.
  int ink = 0;
  for (int y = 0; y < bestRow; ++y)
    for (int x = bestFirst; x < bestFirst + best; ++x) ink += !(pixel(*image_, {x, y}) == Rgb{255, 255, 255});
  EXPECT_GT(ink, 30);
}

TEST(TopDownMap, WholeTerrainFrameCoversTheSamples) {
  TopDownMapOptions options;
  options.maxSize = 600;
  options.wholeTerrain = true;
  const Scene scene = testScene();
  // No run: the legend lists the two kinds only ("container", ~60 pixels).
  const TopDownFrame frame = topDownFrame(scene, {}, {}, options);
  ASSERT_GT(frame.legendWidth, 60);
  ASSERT_LT(frame.legendWidth, 200);
  // Samples span 240 m x 200 m, the width limits.
  const int mapColumns = 600 - frame.legendWidth;
  EXPECT_EQ(frame.width, mapColumns);
  EXPECT_DOUBLE_EQ(frame.metresPerPixel, 240.0 / mapColumns);
  EXPECT_EQ(frame.height, int(std::ceil(200.0 * mapColumns / 240.0)));
  EXPECT_NEAR(frame.west, kOriginX, 1e-6);
  EXPECT_NEAR(frame.south + 0.5 * frame.height * frame.metresPerPixel, kOriginY - 100, 1e-6);

  TempDir dir;
  writeTopDownMap(dir / "whole.png", scene, {}, {}, options);
  const osg::ref_ptr<osg::Image> img = readBack(dir / "whole.png");
  ASSERT_TRUE(img);
  EXPECT_EQ(img->s(), 600);
  EXPECT_EQ(img->t(), frame.height);
  // The run does not move the frame with wholeTerrain.
  const TopDownFrame withRun = topDownFrame(scene, testRecords(), testExpectations(), options);
  EXPECT_NEAR(withRun.west + 0.5 * withRun.width * withRun.metresPerPixel, kOriginX + 120, 1e-6);
}

/// The expected colour of a map pixel: the tint at height fraction f, lit by the Lambert shade of
/// the plane with slopes dz/dx, dz/dy under the documented sun.
Rgb planeColour(double f, double dzdx, double dzdy) {
  const Eigen::Vector3d normal = Eigen::Vector3d(-dzdx, -dzdy, 1).normalized();
  const double alt = std::numbers::pi / 4, az = 7 * std::numbers::pi / 4;
  const Eigen::Vector3d sun(std::cos(alt) * std::sin(az), std::cos(alt) * std::cos(az), std::sin(alt));
  const double light = 0.35 + 0.65 * std::max(0.0, normal.dot(sun));
  return {int(std::lround((kLowTint.r + f * (kHighTint.r - kLowTint.r)) * light)),
          int(std::lround((kLowTint.g + f * (kHighTint.g - kLowTint.g)) * light)),
          int(std::lround((kLowTint.b + f * (kHighTint.b - kLowTint.b)) * light))};
}

TEST(TopDownMap, AMapCoarserThanTheCellsIsDrawnFromThePyramidsLevel) {
  // A plane z = 300 - 0.05 c - 0.1 r on 1027 x 771 samples of 1 m at 70 N (UTM 33), written as a
  // terrain file with its pyramid; the scene's heightfield is the file's heights moved 3.5 m up
  // (the loader's height shift). The whole-terrain map at 320 pixels has about 4 m pixels: drawn
  // from level 2 (whose last column and row are irregular: the pixels past the last regular ones
  // take the nearest point inside), it is still the plane's colour at every terrain pixel.
  constexpr int cols = 1027, rows = 771;
  constexpr double x0 = 612000.5, y0 = 7769000.5, shift = 3.5;
  auto plane = [](int c, int r) { return 300 - 0.05 * c - 0.1 * r; };
  std::vector<float> heights, moved, flat;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      heights.push_back(float(plane(c, r)));
      moved.push_back(float(double(heights.back()) + shift));
      flat.push_back(250.0f);
    }
  TempDir dir;
  const std::string file = dir / "plane.tif";
  terrain::writeTerrainCog(file, cols, rows, heights, x0, y0, 1.0, 1.0, "EPSG:32633", false);
  Scene scene;
  scene.terrain = std::make_shared<const terrain::Heightfield>(cols, rows, std::move(moved), x0, y0, 1.0, 1.0);
  scene.terrainPyramid = std::make_shared<const terrain::TerrainPyramid>(file);
  scene.terrainHeightShift = shift;
  scene.origin = Eigen::Vector3d(x0 + 512, y0 - 384, 0);
  TopDownMapOptions options;
  options.maxSize = 320;
  options.wholeTerrain = true;
  const TopDownFrame frame = topDownFrame(scene, {}, {}, options);
  ASSERT_GE(frame.metresPerPixel, 4.0) << "the map must be coarse enough for level 2";
  writeTopDownMap(dir / "plane.png", scene, {}, {}, options);
  const osg::ref_ptr<osg::Image> img = readBack(dir / "plane.png");
  ASSERT_TRUE(img);
  const double lowest = plane(cols - 1, rows - 1) + shift, highest = plane(0, 0) + shift;
  std::size_t terrainPixels = 0;
  for (int j = 0; j < frame.height; ++j)
    for (int i = 0; i < frame.width; ++i) {
      const Eigen::Vector2d p = frame.pixelCentre(i, j);
      const double c = (p.x() - x0), r = (y0 - p.y());
      if (c < 0 || r < 0 || c > cols - 1 || r > rows - 1) continue;
      // Horn's rule at a corner of the drawn grid takes one diagonal neighbour pair as the centre's
      // height (both are missing), so a corner sample's shade is not the plane's: skip the pixels
      // within two level cells (8 m) of a corner.
      const bool nearX = c < 8 || c > cols - 1 - 8, nearY = r < 8 || r > rows - 1 - 8;
      if (nearX && nearY) continue;
      ++terrainPixels;
      const Rgb expected = planeColour((300 - 0.05 * c - 0.1 * r + shift - lowest) / (highest - lowest), -0.05, 0.1);
      const Rgb got = pixel(*img, {i, j});
      ASSERT_NEAR(got.r, expected.r, 1) << i << ", " << j;
      ASSERT_NEAR(got.g, expected.g, 1) << i << ", " << j;
      ASSERT_NEAR(got.b, expected.b, 1) << i << ", " << j;
    }
  EXPECT_GT(terrainPixels, 0.9 * frame.width * frame.height * 0.75);

  // What is drawn is the level's samples: with the scene's fine heights flattened (the pyramid
  // still the plane's), the coarse map keeps the plane's shade; a map fine enough to need the
  // fine samples (1,200 pixels: under 2 m each) shows the flat ground's.
  scene.terrain = std::make_shared<const terrain::Heightfield>(cols, rows, std::move(flat), x0, y0, 1.0, 1.0);
  auto centrePixel = [&](const std::string& name, int maxSize) {
    TopDownMapOptions o = options;
    o.maxSize = maxSize;
    writeTopDownMap(dir / name, scene, {}, {}, o);
    const TopDownFrame f = topDownFrame(scene, {}, {}, o);
    return pixel(*readBack(dir / name), f.pixelOf({x0 + 512, y0 - 384}));
  };
  // A flat terrain's tint is the middle of the ramp (its lowest and highest are equal).
  EXPECT_EQ(centrePixel("coarse.png", 320), planeColour(0.5, -0.05, 0.1));
  EXPECT_EQ(centrePixel("fine.png", 1200), planeColour(0.5, 0, 0));
}

TEST(TopDownMap, BadInputsNameTheFile) {
  TempDir dir;
  const Scene scene = testScene();
  const std::string missing = dir / "no/map.png";
  try {
    writeTopDownMap(missing, scene, testRecords(), testExpectations(), {.maxSize = 400});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  const std::string bare = dir / "bare.png";
  try {
    writeTopDownMap(bare, Scene{}, testRecords(), {});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(bare), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("terrain"), std::string::npos) << e.what();
  }
  EXPECT_THROW(writeTopDownMap(dir / "tiny.png", scene, testRecords(), {}, {.maxSize = 10}), InputError);
  EXPECT_TRUE(dir.entries().empty());
}

}  // namespace
}  // namespace nestwalk
