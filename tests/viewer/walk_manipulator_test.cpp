// The walker as a camera manipulator (engine/viewer/walk_manipulator.h), driven by events injected
// through OSG's own event queue with chosen times, on the bundled scene: distances against speed x
// time, the eye against the terrain query, the heading against the mouse deltas, the stop at the
// bench-2 mast against a static-overlap search, and a recorded walk (walk_recording.h) played back
// by the script player: same contacts, positions within 1 mm.
#include "nestwalk/core/angles.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/viewer/walk_manipulator.h"
#include "nestwalk/viewer/walk_recording.h"
#include "nestwalk/walker/flythrough.h"
#include "nestwalk/walker/script_file.h"

#include "tests/common/test_data.h"

#include <osgGA/EventQueue>
#include <osgGA/GUIActionAdapter>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;

// What a window would do for the manipulator; it asks for nothing the tests need.
struct NoWindow : osgGA::GUIActionAdapter {
  void requestRedraw() override {}
  void requestContinuousUpdate(bool) override {}
  void requestWarpPointer(float, float) override {}
};

// The bundled patrol's start, facing the bench-2 mast about 40 m ahead.
struct PatrolStart {
  Eigen::Vector3d at;
  double heading = 0;
  std::string blocker;  // the unit group its first expectation names
};

PatrolStart patrolStart() {
  const Script s = readScript(test::bundledScript("bench_patrol.txt").string());
  PatrolStart p;
  for (const ScriptCommand& c : s.commands) {
    if (c.op == ScriptOp::Start) {
      p.at = c.v;
      p.heading = c.heading;
    }
    if (c.op == ScriptOp::ExpectBlocked && p.blocker.empty()) p.blocker = c.name;
  }
  return p;
}

class WalkByHand : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!fs::exists(test::bundledSceneFile())) return;
    scene_ = new Scene(loadScene(test::bundledSceneFile().string()));
  }
  static void TearDownTestSuite() {
    delete scene_;
    scene_ = nullptr;
  }
  void SetUp() override {
    if (!scene_) GTEST_SKIP() << test::bundledSceneFile() << " is absent: build the bundled_scene target";
    world_ = std::make_unique<CollisionWorld>(CollisionWorld::fromScene(*scene_, scene_->spec.method));
    options_.viewer = scene_->spec.viewer;
    walker_ = std::make_unique<Walker>(*scene_->terrain, *world_, scene_->origin, options_);
    start_ = patrolStart();
    ASSERT_EQ(walker_->place(start_.at, false, start_.heading, false, 0), "");
    manipulator_ = new WalkManipulator(*walker_);
    queue_ = new osgGA::EventQueue(osgGA::GUIEventAdapter::Y_INCREASING_UPWARDS);
  }
  // Hands every queued event to the manipulator, in order.
  void deliver() {
    osgGA::EventQueue::Events events;
    queue_->takeEvents(events);
    for (auto& e : events)
      if (auto* ea = e->asGUIEventAdapter()) manipulator_->handle(*ea, window_);
  }
  // Frames every 1/30 s from `from` to `to` seconds (inclusive), delivered as they come.
  void framesUntil(double from, double to) {
    for (double t = from; t <= to + 1e-9; t += 1.0 / 30.0) {
      queue_->frame(t);
      deliver();
    }
  }
  double horizontalFromStart() const { return (walker_->state().feet - start_.at).head<2>().norm(); }

  static Scene* scene_;
  std::unique_ptr<CollisionWorld> world_;
  WalkerOptions options_;
  std::unique_ptr<Walker> walker_;
  PatrolStart start_;
  osg::ref_ptr<WalkManipulator> manipulator_;
  osg::ref_ptr<osgGA::EventQueue> queue_;
  NoWindow window_;
};
Scene* WalkByHand::scene_ = nullptr;

TEST_F(WalkByHand, HoldingWWalksSpeedTimesTimeWithinOneStep) {
  const double speed = options_.viewer.speed;
  queue_->frame(0.0);
  queue_->keyPress('w', 0.0);
  deliver();
  framesUntil(1.0 / 30.0, 2.0);
  queue_->keyRelease('w', 2.0);
  deliver();
  framesUntil(2.0 + 1.0 / 30.0, 2.5);  // standing still
  EXPECT_NEAR(horizontalFromStart(), speed * 2.0, speed * options_.dt);
  EXPECT_FALSE(walker_->state().blocked);
  // Along the heading, and the eye exactly eye_height above the terrain under it.
  const Eigen::Vector3d d = walker_->state().feet - start_.at;
  const double h = radians(start_.heading);
  EXPECT_NEAR(d.x() * std::cos(h) - d.y() * std::sin(h), 0.0, 1e-7);
  const Eigen::Vector3d eye = walker_->eye();
  const std::optional<double> ground = scene_->terrain->groundHeight(eye.x(), eye.y());
  ASSERT_TRUE(ground.has_value());
  EXPECT_NEAR(eye.z() - *ground, options_.viewer.eyeHeight, 1e-9);
  // Shift runs kRunFactor times faster.
  const Eigen::Vector3d before = walker_->state().feet;
  queue_->frame(3.0);
  queue_->keyPress(osgGA::GUIEventAdapter::KEY_Shift_L, 3.0);
  queue_->keyPress('W', 3.0);  // Shift gives the capital
  deliver();
  framesUntil(3.0 + 1.0 / 30.0, 4.0);
  EXPECT_NEAR((walker_->state().feet - before).head<2>().norm(), speed * kRunFactor * 1.0, speed * kRunFactor * options_.dt);
}

TEST_F(WalkByHand, MouseDragTurnsTheHeadingByDegreesPerPixel) {
  queue_->frame(0.0);
  queue_->mouseButtonPress(100, 100, 1, 0.0);
  queue_->mouseMotion(150, 100, 0.01);  // 50 px right
  queue_->mouseMotion(150, 120, 0.02);  // 20 px up
  queue_->mouseButtonRelease(150, 120, 1, 0.03);
  queue_->frame(0.05);
  deliver();
  EXPECT_NEAR(turnBetween(start_.heading, walker_->state().headingDeg), 50 * kDegreesPerPixel, 1e-9);
  EXPECT_NEAR(walker_->state().pitchDeg, 20 * kDegreesPerPixel, 1e-9);
  // The camera looks where the walker looks: its inverse matrix maps the view direction to -z.
  const osg::Matrixd view = manipulator_->getInverseMatrix();
  const double hd = radians(walker_->state().headingDeg), p = radians(walker_->state().pitchDeg);
  const osg::Vec3d eye(walker_->eye().x(), walker_->eye().y(), walker_->eye().z());
  const osg::Vec3d ahead = eye + osg::Vec3d(std::sin(hd) * std::cos(p), std::cos(hd) * std::cos(p), std::sin(p));
  const osg::Vec3d inEye = ahead * view;
  EXPECT_NEAR(inEye.x(), 0.0, 1e-6);
  EXPECT_NEAR(inEye.y(), 0.0, 1e-6);
  EXPECT_NEAR(inEye.z(), -1.0, 1e-6);
}

TEST_F(WalkByHand, WalkingIntoTheMastStopsHalfAMillimetreShortOfIt) {
  queue_->frame(0.0);
  queue_->keyPress('w', 0.0);
  deliver();
  framesUntil(1.0 / 30.0, 40.0);  // 56 m asked; the mast is about 40 m ahead
  const WalkerState& s = walker_->state();
  ASSERT_TRUE(s.blocked);
  ASSERT_GE(s.blockedUnit, 0);
  const std::string& unit = world_->name(std::size_t(s.blockedUnit));
  EXPECT_EQ(unit.rfind(start_.blocker, 0), 0u) << unit;
  EXPECT_EQ(manipulator_->pose().blockedBy, unit);
  // How far the body could still go along the heading before its volumes overlap the mast's:
  // bisection on the static test, independent of the swept one that stopped it.
  const auto [sn, cs] = sinCosDegrees(s.headingDeg);
  const Eigen::Vector3d dir(sn, cs, 0);
  auto overlaps = [&](double t) {
    CollisionCounters c;
    return world_->overlapping(walker_->bodyVolume(s.feet + t * dir, s.bodyYawDeg), c) >= 0;
  };
  ASSERT_FALSE(overlaps(0.0));
  ASSERT_TRUE(overlaps(0.01));
  double lo = 0, hi = 0.01;
  for (int i = 0; i < 60; ++i) (overlaps(0.5 * (lo + hi)) ? hi : lo) = 0.5 * (lo + hi);
  EXPECT_NEAR(hi, kStopDistance, 0.1e-3) << "gap " << hi * 1e3 << " mm";
}

TEST_F(WalkByHand, ARecordedWalkReplaysWithTheSameContactsAndPositions) {
  WalkRecording recording(*walker_, test::bundledSceneFile().string(), "nested");
  manipulator_->onStep([&](const StepInput& in, const StepReport&) { recording.add(in, *walker_); });
  double t = 0;
  queue_->frame(t);
  queue_->keyPress('w', t);
  deliver();
  framesUntil(t + 1.0 / 30.0, 35.0);  // into the mast, pressing on for a few seconds
  ASSERT_TRUE(walker_->state().blocked);
  queue_->keyRelease('w', 35.0);
  // Turn right by dragging, in small moves over half a second, then walk on and stand.
  queue_->mouseButtonPress(400, 300, 1, 35.0);
  for (int i = 1; i <= 15; ++i) queue_->mouseMotion(400 + 30 * i, 300 - i, 35.0 + i / 30.0);
  queue_->mouseButtonRelease(850, 285, 1, 35.5);
  deliver();
  framesUntil(35.0 + 1.0 / 30.0, 36.0);
  queue_->keyPress('w', 36.0);
  queue_->keyPress('d', 37.0);
  deliver();
  framesUntil(36.0 + 1.0 / 30.0, 39.0);
  queue_->keyRelease('w', 39.0);
  queue_->keyRelease('d', 39.0);
  deliver();
  framesUntil(39.0 + 1.0 / 30.0, 40.0);
  ASSERT_FALSE(recording.contacts().empty());

  const Script script = parseScript(recording.scriptText(), "recorded.txt");
  const CollisionWorld replayWorld = CollisionWorld::fromScene(*scene_, scene_->spec.method);
  const FlythroughResult replay = runFlythrough(*scene_, replayWorld, script, options_);
  for (const ExpectationResult& e : replay.expectations) EXPECT_TRUE(e.met) << e.text << ": " << e.detail;
  // The contacts, in order: where each run of blocked steps begins.
  std::vector<const FrameRecord*> blocks;
  for (std::size_t i = 0; i < replay.records.size(); ++i)
    if (replay.records[i].blocked && (i == 0 || !replay.records[i - 1].blocked)) blocks.push_back(&replay.records[i]);
  ASSERT_EQ(blocks.size(), recording.contacts().size()) << recording.scriptText();
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    EXPECT_EQ(blocks[i]->blockedBy, recording.contacts()[i].blocker);
    const Eigen::Vector3d handEye = recording.contacts()[i].feet + Eigen::Vector3d(0, 0, options_.viewer.eyeHeight);
    EXPECT_LE((blocks[i]->eye - handEye).norm(), 1e-3) << "contact " << i;
  }
  EXPECT_LE((replay.records.back().eye - walker_->eye()).norm(), 1e-3);
  EXPECT_NEAR(turnBetween(replay.records.back().headingDeg, walker_->state().headingDeg), 0.0, 1e-9);
}

}  // namespace
}  // namespace nestwalk
