// Angles (core/angles.h) at their edges: the wraps never leave their ranges, the exact sine and
// cosine at multiples of 90 degrees, headings of the compass directions.
#include "nestwalk/core/angles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace nestwalk {
namespace {

TEST(Angles, Wrap360StaysInItsRangeAtTheEdges) {
  EXPECT_EQ(wrapDegrees360(0.0), 0.0);
  EXPECT_EQ(wrapDegrees360(360.0), 0.0);
  EXPECT_EQ(wrapDegrees360(-360.0), 0.0);
  EXPECT_EQ(wrapDegrees360(-90.0), 270.0);
  EXPECT_EQ(wrapDegrees360(725.0), 5.0);
  EXPECT_EQ(wrapDegrees360(359.5), 359.5);
  // fmod(-tiny, 360) + 360 rounds to 360 in double: the wrap must give 0, never 360.
  for (double tiny : {-1e-15, -1e-300, -std::numeric_limits<double>::denorm_min(), -0.0}) {
    const double w = wrapDegrees360(tiny);
    EXPECT_GE(w, 0.0) << tiny;
    EXPECT_LT(w, 360.0) << tiny;
  }
  EXPECT_LT(wrapDegrees360(std::nextafter(360.0, 0.0)), 360.0);
  EXPECT_TRUE(std::isnan(wrapDegrees360(std::numeric_limits<double>::infinity())));
  EXPECT_TRUE(std::isnan(wrapDegrees360(std::nan(""))));
}

TEST(Angles, Wrap180IsHalfOpenAtMinus180) {
  EXPECT_EQ(wrapDegrees180(180.0), 180.0);
  EXPECT_EQ(wrapDegrees180(-180.0), 180.0);
  EXPECT_EQ(wrapDegrees180(540.0), 180.0);
  EXPECT_EQ(wrapDegrees180(270.0), -90.0);
  EXPECT_EQ(wrapDegrees180(-190.0), 170.0);
  EXPECT_EQ(wrapDegrees180(0.0), 0.0);
  for (double a = -1000.0; a <= 1000.0; a += 0.37) {
    const double w = wrapDegrees180(a);
    EXPECT_GT(w, -180.0) << a;
    EXPECT_LE(w, 180.0) << a;
    EXPECT_NEAR(std::remainder(w - a, 360.0), 0.0, 1e-9) << a;
  }
}

TEST(Angles, TurnBetweenTakesTheShortWay) {
  EXPECT_EQ(turnBetween(350.0, 10.0), 20.0);
  EXPECT_EQ(turnBetween(10.0, 350.0), -20.0);
  EXPECT_EQ(turnBetween(0.0, 180.0), 180.0);
  EXPECT_EQ(turnBetween(90.0, 270.0), 180.0);  // half a turn is clockwise
}

TEST(Angles, HeadingsOfCompassDirections) {
  EXPECT_EQ(headingOf(0.0, 1.0), 0.0);    // north
  EXPECT_EQ(headingOf(1.0, 0.0), 90.0);   // east
  EXPECT_EQ(headingOf(0.0, -1.0), 180.0); // south
  EXPECT_EQ(headingOf(-1.0, 0.0), 270.0); // west
  EXPECT_EQ(headingOf(0.0, 0.0), 0.0);
  EXPECT_NEAR(headingOf(1.0, 1.0), 45.0, 1e-12);
  const double nearlyNorth = headingOf(-1e-300, 1.0);  // just west of north: wraps below 360
  EXPECT_GE(nearlyNorth, 0.0);
  EXPECT_LT(nearlyNorth, 360.0);
}

TEST(Angles, SinCosExactAtRightAnglesAndAccurateElsewhere) {
  const std::pair<double, double> quarter[] = {{0, 1}, {1, 0}, {0, -1}, {-1, 0}};
  for (int k = -8; k <= 8; ++k) {
    const auto [s, c] = sinCosDegrees(90.0 * k);
    EXPECT_EQ(s, quarter[((k % 4) + 4) % 4].first) << k;
    EXPECT_EQ(c, quarter[((k % 4) + 4) % 4].second) << k;
  }
  for (double a = -720.0; a <= 720.0; a += 7.3) {
    const auto [s, c] = sinCosDegrees(a);
    // Against long double, with the angle reduced exactly first.
    const long double r = static_cast<long double>(std::fmod(a, 360.0)) * std::numbers::pi_v<long double> / 180.0L;
    EXPECT_NEAR(s, double(std::sin(r)), 1e-15) << a;
    EXPECT_NEAR(c, double(std::cos(r)), 1e-15) << a;
  }
  EXPECT_EQ(radians(180.0), std::numbers::pi);
  EXPECT_EQ(degrees(std::numbers::pi), 180.0);
}

}  // namespace
}  // namespace nestwalk
