// Keys and mouse made into walker steps (engine/viewer/walk_controls.h), against hand-computed
// moves and step counts.
#include "nestwalk/viewer/walk_controls.h"

#include <gtest/gtest.h>

#include <cmath>

namespace nestwalk {
namespace {

constexpr double kDt = 1.0 / 60.0;

TEST(WalkControls, RealTimeBecomesWholeStepsAndTheRestCarriesOver) {
  WalkControls c(1.4, kDt);
  EXPECT_EQ(c.stepsFor(0.2), 12);
  // 2.5 steps, then 2.5 more: 2, then 3 (the half carried over).
  EXPECT_EQ(c.stepsFor(2.5 * kDt), 2);
  EXPECT_EQ(c.stepsFor(2.5 * kDt), 3);
  EXPECT_EQ(c.stepsFor(0.0), 0);
  // A 5 s frame takes kMaxStepsPerFrame steps and drops the rest.
  EXPECT_EQ(c.stepsFor(5.0), kMaxStepsPerFrame);
  EXPECT_EQ(c.stepsFor(0.4 * kDt), 0);
}

TEST(WalkControls, ForwardFollowsTheHeadingAtTheSpeed) {
  WalkControls c(1.4, kDt);
  c.setView(90, 0);  // east
  c.press(WalkKey::Forward);
  StepInput in = c.input(false);
  EXPECT_DOUBLE_EQ(in.move.x(), 1.4 * kDt);
  EXPECT_EQ(in.move.y(), 0.0);
  EXPECT_EQ(in.headingDeg, 90.0);
  c.press(WalkKey::Run);
  EXPECT_DOUBLE_EQ(c.input(false).move.norm(), 1.4 * kRunFactor * kDt);
  c.release(WalkKey::Run);
  // Forward and right at heading 0: north-east, no faster than straight.
  c.setView(0, 0);
  c.press(WalkKey::Right);
  in = c.input(false);
  EXPECT_NEAR(in.move.x(), 1.4 * kDt / std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(in.move.y(), 1.4 * kDt / std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(in.move.norm(), 1.4 * kDt, 1e-15);
  // Opposite keys cancel.
  c.press(WalkKey::Left);
  c.press(WalkKey::Back);
  EXPECT_EQ(c.input(false).move.norm(), 0.0);
  EXPECT_EQ(c.speed(), 0.0);
}

TEST(WalkControls, UpAndDownOnlyInFlight) {
  WalkControls c(2.0, kDt);
  c.press(WalkKey::Up);
  EXPECT_EQ(c.input(false).move.norm(), 0.0);
  EXPECT_DOUBLE_EQ(c.input(true).move.z(), 2.0 * kDt);
  c.press(WalkKey::Forward);  // heading 0: north and up, scaled to the speed together
  const StepInput in = c.input(true);
  EXPECT_NEAR(in.move.y(), 2.0 * kDt / std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(in.move.z(), 2.0 * kDt / std::sqrt(2.0), 1e-15);
}

TEST(WalkControls, MouseTurnsByDegreesPerPixelAndPitchIsClamped) {
  WalkControls c(1.4, kDt);
  c.setView(350, 0);
  c.look(100, 0);  // right: clockwise, through north
  EXPECT_NEAR(c.headingDeg(), 350 + 100 * kDegreesPerPixel - 360, 1e-12);
  c.look(0, 25);  // up
  EXPECT_NEAR(c.pitchDeg(), 25 * kDegreesPerPixel, 1e-12);
  c.look(0, 10000);
  EXPECT_EQ(c.pitchDeg(), kMaxPitchDeg);
  c.look(0, -20000);
  EXPECT_EQ(c.pitchDeg(), -kMaxPitchDeg);
}

}  // namespace
}  // namespace nestwalk
