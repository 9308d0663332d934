// OpenSceneGraph AnimationPath files (engine/walker/script.h) against OSG itself: the camera
// orientation against osg::Matrixd::lookAt, the written file against osg::AnimationPath::read and
// osgGA::AnimationPathManipulator, and the script made from a file osg::AnimationPath::write wrote.
#include "nestwalk/core/angles.h"
#include "nestwalk/walker/animation_path.h"
#include "nestwalk/walker/script_file.h"

#include "nestwalk/core/input_error.h"
#include "tests/common/temp_folder.h"

#include <gtest/gtest.h>
#include <osg/AnimationPath>
#include <osg/Matrixd>
#include <osg/Quat>
#include <osgGA/AnimationPathManipulator>

#include <unistd.h>

#include <cmath>
#include <numbers>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;

// Quaternion and direction agreement: a few ulps of the trigonometry behind both sides.
constexpr double kRotationTol = 1e-12;
// Angles read back from a quaternion: atan2 of components good to ~1e-16 gives ~1e-13 degrees;
// near the vertical the heading comes from the right vector, as well conditioned.
constexpr double kAngleTolDeg = 1e-9;

using TempDir = test::TempFolder;

/// The direction of heading H (clockwise from +y) and pitch P (up) in the z-up map frame.
osg::Vec3d direction(double h, double p) {
  return osg::Vec3d(std::sin(radians(h)) * std::cos(radians(p)), std::cos(radians(h)) * std::cos(radians(p)),
                    std::sin(radians(p)));
}

/// OSG's own camera rotation for that view: lookAt gives the view matrix, its inverse the
/// camera's world matrix, whose rotation is what an AnimationPath control point holds.
osg::Quat osgCameraRotation(const osg::Vec3d& eye, double h, double p) {
  const osg::Matrixd view = osg::Matrixd::lookAt(eye, eye + direction(h, p), osg::Vec3d(0, 0, 1));
  return osg::Matrixd::inverse(view).getRotate();
}

double angleDiff(double a, double b) {
  double d = std::fmod(a - b, 360.0);
  if (d > 180) d -= 360;
  if (d < -180) d += 360;
  return std::abs(d);
}

TEST(AnimationPath, CameraQuaternionMatchesOsgLookAt) {
  for (double h = -180; h <= 540; h += 15)
    for (double p = -89; p <= 89; p += 8.9) {
      const Eigen::Vector4d q = cameraQuaternion(h, p);
      const osg::Quat o = osgCameraRotation(osg::Vec3d(500000, 4400000, 300), h, p);
      const double dot = q.x() * o.x() + q.y() * o.y() + q.z() * o.z() + q.w() * o.w();
      EXPECT_NEAR(std::abs(dot), 1.0, kRotationTol) << "heading " << h << " pitch " << p;
      EXPECT_NEAR(q.norm(), 1.0, kRotationTol);
      // And OSG turns its camera's -Z with our quaternion onto the view direction, +Y upwards.
      const osg::Quat oq(q.x(), q.y(), q.z(), q.w());
      const osg::Vec3d f = oq * osg::Vec3d(0, 0, -1), want = direction(h, p);
      EXPECT_NEAR((f - want).length(), 0.0, kRotationTol) << "heading " << h << " pitch " << p;
      const osg::Vec3d up = oq * osg::Vec3d(0, 1, 0), right = oq * osg::Vec3d(1, 0, 0);
      EXPECT_GT(up.z(), 0.0);
      EXPECT_NEAR(right.z(), 0.0, kRotationTol);  // no roll
    }
}

TEST(AnimationPath, StraightUpAndDownAreTheLimitOfTheSlopes) {
  for (double h : {0.0, 37.0, 90.0, 200.0, 359.0})
    for (double p : {90.0, -90.0}) {
      const Eigen::Vector4d q = cameraQuaternion(h, p);
      const osg::Quat o = osgCameraRotation(osg::Vec3d(0, 0, 0), h, std::copysign(89.9999, p));
      const double dot = q.x() * o.x() + q.y() * o.y() + q.z() * o.z() + q.w() * o.w();
      EXPECT_NEAR(std::abs(dot), 1.0, 1e-9) << "heading " << h << " pitch " << p;
      double hh = 0, pp = 0;
      headingPitchFromQuaternion(q, hh, pp);
      EXPECT_NEAR(pp, p, kAngleTolDeg);
      EXPECT_LT(angleDiff(hh, h), kAngleTolDeg) << "heading " << h << " pitch " << p << " got " << hh;
    }
}

TEST(AnimationPath, HeadingPitchFromOsgRotation) {
  for (double h = 0; h < 360; h += 7.5)
    for (double p = -85; p <= 85; p += 17) {
      const osg::Quat o = osgCameraRotation(osg::Vec3d(1, 2, 3), h, p);
      for (double sign : {1.0, -1.0}) {  // q and -q are the same rotation
        double hh = 0, pp = 0;
        headingPitchFromQuaternion(sign * Eigen::Vector4d(o.x(), o.y(), o.z(), o.w()), hh, pp);
        EXPECT_NEAR(pp, p, kAngleTolDeg);
        EXPECT_LT(angleDiff(hh, h), kAngleTolDeg);
        EXPECT_GE(hh, 0.0);
        EXPECT_LT(hh, 360.0);
      }
    }
  // Not unit length (a hand-edited file): only the rotation counts.
  const osg::Quat o = osgCameraRotation(osg::Vec3d(0, 0, 0), 123, -20);
  double hh = 0, pp = 0;
  headingPitchFromQuaternion(2.5 * Eigen::Vector4d(o.x(), o.y(), o.z(), o.w()), hh, pp);
  EXPECT_NEAR(hh, 123.0, kAngleTolDeg);
  EXPECT_NEAR(pp, -20.0, kAngleTolDeg);
}

std::vector<CameraSample> utmSamples() {
  std::vector<CameraSample> s;
  for (int i = 0; i < 50; ++i) {
    CameraSample c;
    c.time = i / 60.0;
    c.eye = Eigen::Vector3d(500123.4567 + 0.0123 * i, 4400987.6543 - 0.731 * i, 312.25 + 0.01 * i);
    c.headingDeg = std::fmod(10.0 + 7.3 * i, 360.0);
    c.pitchDeg = -30.0 + 1.1 * i;
    s.push_back(c);
  }
  return s;
}

TEST(AnimationPath, WrittenFileReadsBackThroughOsg) {
  TempDir dir;
  const std::vector<CameraSample> samples = utmSamples();
  const std::string file = (dir / "camera.path").string();
  writeAnimationPath(file, samples);
  // Only the file itself is left in the folder (the temporary was renamed).
  std::size_t entries = 0;
  for (const auto& e : fs::directory_iterator(dir.path())) {
    ++entries;
    EXPECT_EQ(e.path().filename(), "camera.path");
  }
  EXPECT_EQ(entries, 1u);

  osg::ref_ptr<osg::AnimationPath> path = new osg::AnimationPath;
  std::ifstream in(file);
  path->read(in);
  const auto& map = path->getTimeControlPointMap();
  ASSERT_EQ(map.size(), samples.size());
  std::size_t i = 0;
  for (const auto& [time, cp] : map) {
    const CameraSample& s = samples[i++];
    EXPECT_EQ(time, s.time);  // shortest round-trip text: exact
    EXPECT_EQ(cp.getPosition().x(), s.eye.x());
    EXPECT_EQ(cp.getPosition().y(), s.eye.y());
    EXPECT_EQ(cp.getPosition().z(), s.eye.z());
    const osg::Quat o = osgCameraRotation(cp.getPosition(), s.headingDeg, s.pitchDeg);
    const double dot = cp.getRotation().x() * o.x() + cp.getRotation().y() * o.y() + cp.getRotation().z() * o.z() +
                       cp.getRotation().w() * o.w();
    EXPECT_NEAR(std::abs(dot), 1.0, kRotationTol) << "sample " << i - 1;
    // The control point's matrix is the camera's world matrix: eye there, looking along the view.
    osg::Matrixd m;
    cp.getMatrix(m);
    EXPECT_EQ(m.getTrans(), cp.getPosition());
    const osg::Vec3d forward = m.getRotate() * osg::Vec3d(0, 0, -1);
    EXPECT_NEAR((forward - direction(s.headingDeg, s.pitchDeg)).length(), 0.0, kRotationTol);
  }

  // osgviewer's replay manipulator reads the same file to the same path.
  osg::ref_ptr<osgGA::AnimationPathManipulator> manip = new osgGA::AnimationPathManipulator(file);
  ASSERT_TRUE(manip->valid());
  EXPECT_EQ(manip->getAnimationPath()->getTimeControlPointMap().size(), samples.size());
  EXPECT_EQ(manip->getAnimationPath()->getFirstTime(), samples.front().time);
  EXPECT_EQ(manip->getAnimationPath()->getLastTime(), samples.back().time);
}

TEST(AnimationPath, WriteReplacesAndFailsNamingTheFile) {
  TempDir dir;
  const std::string file = (dir / "camera.path").string();
  writeAnimationPath(file, utmSamples());
  writeAnimationPath(file, {CameraSample{}});
  osg::ref_ptr<osg::AnimationPath> path = new osg::AnimationPath;
  std::ifstream in(file);
  path->read(in);
  EXPECT_EQ(path->getTimeControlPointMap().size(), 1u);

  const std::string bad = (dir / "no-such-folder" / "camera.path").string();
  try {
    writeAnimationPath(bad, utmSamples());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
  }
}

TEST(AnimationPath, ScriptFromOsgWrittenPath) {
  // A recording as osgviewer makes it: OSG's own writer, OSG's own camera rotations.
  struct Point {
    double t;
    osg::Vec3d eye;
    double h, p;
  };
  const std::vector<Point> pts = {
      {0.0, {500100.0, 4400200.0, 320.0}, 30.0, -10.0},
      {2.0, {500110.0, 4400210.0, 321.0}, 45.0, -5.0},
      {3.5, {500110.0, 4400210.0005, 321.0}, 90.0, 0.0},  // 0.5 mm: the same place, a wait
      {4.0, {500100.0, 4400200.0, 318.0}, 225.0, 12.5},
  };
  osg::ref_ptr<osg::AnimationPath> path = new osg::AnimationPath;
  for (const Point& p : pts)
    path->insert(p.t, osg::AnimationPath::ControlPoint(p.eye, osgCameraRotation(p.eye, p.h, p.p)));
  std::ostringstream text;
  path->write(text);

  const Script s = scriptFromAnimationPath(text.str(), "rec.path");
  EXPECT_EQ(s.path, "rec.path");
  // mode, start, look; then speed, heading, look, goto / heading, look, wait / speed, heading, look, goto.
  ASSERT_EQ(s.commands.size(), 3u + 4u + 3u + 4u);
  const auto& c = s.commands;
  // OSG writes 15 significant digits: 1e-8 m at these magnitudes.
  constexpr double kWrittenTol = 1e-7;
  constexpr double kWrittenAngleTolDeg = 1e-6;

  EXPECT_EQ(c[0].op, ScriptOp::Mode);
  EXPECT_TRUE(c[0].fly);
  EXPECT_EQ(c[1].op, ScriptOp::Start);
  EXPECT_EQ(c[1].line, 1);
  EXPECT_TRUE(c[1].hasZ);
  EXPECT_TRUE(c[1].hasHeading);
  EXPECT_NEAR((c[1].v - Eigen::Vector3d(500100, 4400200, 320)).norm(), 0, kWrittenTol);
  EXPECT_LT(angleDiff(c[1].heading, 30.0), kWrittenAngleTolDeg);
  EXPECT_EQ(c[2].op, ScriptOp::Look);
  EXPECT_NEAR(c[2].v.x(), -10.0, kWrittenAngleTolDeg);

  const double d1 = (pts[1].eye - pts[0].eye).length();
  EXPECT_EQ(c[3].op, ScriptOp::Speed);
  EXPECT_EQ(c[3].line, 2);
  EXPECT_NEAR(c[3].v.x(), d1 / 2.0, kWrittenTol);
  EXPECT_EQ(c[4].op, ScriptOp::Heading);
  EXPECT_LT(angleDiff(c[4].v.x(), 45.0), kWrittenAngleTolDeg);
  EXPECT_EQ(c[5].op, ScriptOp::Look);
  EXPECT_NEAR(c[5].v.x(), -5.0, kWrittenAngleTolDeg);
  EXPECT_EQ(c[6].op, ScriptOp::Goto);
  EXPECT_TRUE(c[6].hasZ);
  EXPECT_NEAR((c[6].v - Eigen::Vector3d(500110, 4400210, 321)).norm(), 0, kWrittenTol);

  EXPECT_EQ(c[7].op, ScriptOp::Heading);
  EXPECT_LT(angleDiff(c[7].v.x(), 90.0), kWrittenAngleTolDeg);
  EXPECT_EQ(c[8].op, ScriptOp::Look);
  EXPECT_NEAR(c[8].v.x(), 0.0, kWrittenAngleTolDeg);
  EXPECT_EQ(c[9].op, ScriptOp::Wait);
  EXPECT_NEAR(c[9].v.x(), 1.5, 1e-12);
  EXPECT_EQ(c[9].line, 3);

  const double d3 = (pts[3].eye - pts[2].eye).length();
  EXPECT_EQ(c[10].op, ScriptOp::Speed);
  EXPECT_NEAR(c[10].v.x(), d3 / 0.5, kWrittenTol);
  EXPECT_LT(angleDiff(c[11].v.x(), 225.0), kWrittenAngleTolDeg);
  EXPECT_NEAR(c[12].v.x(), 12.5, kWrittenAngleTolDeg);
  EXPECT_EQ(c[13].op, ScriptOp::Goto);
  EXPECT_NEAR((c[13].v - Eigen::Vector3d(500100, 4400200, 318)).norm(), 0, kWrittenTol);
}

TEST(AnimationPath, OurWriterThenOurReader) {
  TempDir dir;
  const std::vector<CameraSample> samples = utmSamples();
  const std::string file = (dir / "camera.path").string();
  writeAnimationPath(file, samples);
  const Script s = readScript(file);
  ASSERT_EQ(s.commands.size(), 3u + 4u * (samples.size() - 1));
  EXPECT_EQ(s.commands[1].v, samples[0].eye);  // exact: shortest round-trip text
  EXPECT_NEAR(s.commands[1].heading, samples[0].headingDeg, kAngleTolDeg);
  EXPECT_NEAR(s.commands[2].v.x(), samples[0].pitchDeg, kAngleTolDeg);
  const ScriptCommand& lastGoto = s.commands.back();
  EXPECT_EQ(lastGoto.op, ScriptOp::Goto);
  EXPECT_EQ(lastGoto.v, samples.back().eye);
  EXPECT_EQ(lastGoto.line, int(samples.size()));
}

std::string pathError(const std::string& text) {
  try {
    scriptFromAnimationPath(text, "rec.path");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(AnimationPath, BadFilesNameTheLine) {
  EXPECT_EQ(pathError("0 1 2 3 0 0 0 1\n1 1 2 3 0 0 1\n"),
            "rec.path:2: expected 8 numbers (time x y z qx qy qz qw), got 7");
  EXPECT_EQ(pathError("0 1 2 3 0 0 0 1 9\n"), "rec.path:1: expected 8 numbers (time x y z qx qy qz qw), got more");
  EXPECT_EQ(pathError("0 1 2 3 0 0 0 1\n\n1 1 2 x 0 0 0 1\n"), "rec.path:3: 'x' is not a number");
  EXPECT_EQ(pathError("0 1 2 nan 0 0 0 1\n"), "rec.path:1: 'nan' is not a finite number");
  EXPECT_EQ(pathError("0 1 2 3 0 0 0 0\n"), "rec.path:1: the rotation quaternion is zero");
  EXPECT_EQ(pathError("1 1 2 3 0 0 0 1\n1 1 2 4 0 0 0 1\n"),
            "rec.path:2: time 1 does not come after the previous control point's 1 (times must increase)");
  EXPECT_EQ(pathError("\n  \n"), "rec.path: no control points (expected lines \"time x y z qx qy qz qw\")");
}

}  // namespace
}  // namespace nestwalk
