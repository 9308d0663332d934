// OpenSceneGraph AnimationPath files (osg::AnimationPath::read/write, what osgviewer records with
// 'z' and replays with -p): one control point per line, "time px py pz qx qy qz qw", the
// quaternion being the camera's rotation in the world (AnimationPathManipulator uses the control
// point's matrix, rotate then translate, as the camera's world matrix; the view matrix is its
// inverse). An OSG camera looks down its local -Z with +Y up and +X to the right.
//
// Heading H (degrees clockwise from north = map +y; x east, z up) and pitch P (positive up) give
//   forward = (sin H cos P, cos H cos P, sin P),  right = (cos H, -sin H, 0),
// which is the rotation Rz(-H) * Rx(90 + P): Rx(90) turns the camera's -Z onto north and its +Y
// onto up; Rx(P) pitches about east; Rz(-H) turns clockwise seen from above.
#include "nestwalk/walker/animation_path.h"

#include "nestwalk/core/angles.h"
#include "nestwalk/core/input_error.h"
#include "nestwalk/core/number_text.h"
#include "nestwalk/core/output_file.h"

#include <Eigen/Geometry>

#include <cctype>
#include <charconv>
#include <cmath>
#include <string_view>
#include <system_error>

namespace nestwalk {
namespace {

// Control points closer than this (metres) are the same place: the camera only turned or
// waited there. 1 mm is far below any walking step (speed × dt is centimetres at least) and far
// above the rounding of map coordinates written with 15 significant digits (1e-8 m at 1e7 m).
constexpr double kSamePointDistance = 1e-3;

// A view this close to vertical (|horizontal part of the forward vector|, unitless) has no
// meaningful heading from the forward vector; the heading is read from the camera's right vector
// instead. 1e-9 is about 2e-7 degrees from vertical.
constexpr double kVerticalViewEpsilon = 1e-9;

// A quaternion shorter than this is no rotation (the file is broken); real ones are unit length
// to the 15 digits osg writes.
constexpr double kMinQuaternionNorm = 1e-6;

/// Shortest text that reads back to exactly `v` (locale-independent).
void appendNumber(std::string& out, double v) { out += exactText(v); }

struct ControlPoint {
  int line = 0;
  double time = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector4d rotation = Eigen::Vector4d::Zero();  // x y z w
};

[[noreturn]] void failAt(const std::string& path, int line, const std::string& problem) {
  throw InputError(path + ":" + std::to_string(line) + ": " + problem);
}

std::vector<ControlPoint> parseControlPoints(const std::string& text, const std::string& path) {
  std::vector<ControlPoint> points;
  int lineNo = 0;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string::npos) eol = text.size();
    const std::string_view line(text.data() + pos, eol - pos);
    pos = eol + 1;
    ++lineNo;
    double v[8];
    int n = 0;
    std::size_t i = 0;
    for (;;) {
      while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
      if (i == line.size()) break;
      std::size_t j = i;
      while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
      const std::string_view w = line.substr(i, j - i);
      i = j;
      if (n == 8) failAt(path, lineNo, "expected 8 numbers (time x y z qx qy qz qw), got more");
      const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), v[n]);
      if (ec == std::errc::result_out_of_range || (ec == std::errc() && !std::isfinite(v[n])))
        failAt(path, lineNo, "'" + std::string(w) + "' is not a finite number");
      if (ec != std::errc() || end != w.data() + w.size())
        failAt(path, lineNo, "'" + std::string(w) + "' is not a number");
      ++n;
    }
    if (n == 0) continue;
    if (n != 8)
      failAt(path, lineNo, "expected 8 numbers (time x y z qx qy qz qw), got " + std::to_string(n));
    ControlPoint cp;
    cp.line = lineNo;
    cp.time = v[0];
    cp.position = Eigen::Vector3d(v[1], v[2], v[3]);
    cp.rotation = Eigen::Vector4d(v[4], v[5], v[6], v[7]);
    if (cp.rotation.norm() < kMinQuaternionNorm) failAt(path, lineNo, "the rotation quaternion is zero");
    if (!points.empty() && !(cp.time > points.back().time)) {
      std::string times;
      appendNumber(times, cp.time);
      times += " does not come after the previous control point's ";
      appendNumber(times, points.back().time);
      failAt(path, lineNo, "time " + times + " (times must increase)");
    }
    points.push_back(cp);
  }
  if (points.empty()) throw InputError(path + ": no control points (expected lines \"time x y z qx qy qz qw\")");
  return points;
}

}  // namespace

Eigen::Vector4d cameraQuaternion(double headingDeg, double pitchDeg) {
  const Eigen::Quaterniond q = Eigen::AngleAxisd(-headingDeg / kDegreesPerRadian, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd((90.0 + pitchDeg) / kDegreesPerRadian, Eigen::Vector3d::UnitX());
  return Eigen::Vector4d(q.x(), q.y(), q.z(), q.w());
}

void headingPitchFromQuaternion(const Eigen::Vector4d& xyzw, double& headingDeg, double& pitchDeg) {
  const Eigen::Quaterniond q = Eigen::Quaterniond(xyzw.w(), xyzw.x(), xyzw.y(), xyzw.z()).normalized();
  const Eigen::Vector3d forward = q * Eigen::Vector3d(0, 0, -1);
  const double horizontal = std::hypot(forward.x(), forward.y());
  pitchDeg = std::atan2(forward.z(), horizontal) * kDegreesPerRadian;
  if (horizontal > kVerticalViewEpsilon) {
    headingDeg = wrapDegrees360(std::atan2(forward.x(), forward.y()) * kDegreesPerRadian);
  } else {
    const Eigen::Vector3d right = q * Eigen::Vector3d(1, 0, 0);  // (cos H, -sin H, 0)
    headingDeg = wrapDegrees360(std::atan2(-right.y(), right.x()) * kDegreesPerRadian);
  }
}

void writeAnimationPath(const std::string& path, const std::vector<CameraSample>& samples) {
  std::string text;
  text.reserve(samples.size() * 160);
  for (const CameraSample& s : samples) {
    const Eigen::Vector4d q = cameraQuaternion(s.headingDeg, s.pitchDeg);
    const double values[8] = {s.time, s.eye.x(), s.eye.y(), s.eye.z(), q.x(), q.y(), q.z(), q.w()};
    for (int i = 0; i < 8; ++i) {
      if (i) text += ' ';
      appendNumber(text, values[i]);
    }
    // Every line ends with a newline: osg::AnimationPath::read drops a last point that ends the
    // file without one (it checks eof after reading the point).
    text += '\n';
  }
  writeFileAtomically(path, text);
}

Script scriptFromAnimationPath(const std::string& text, const std::string& path) {
  const std::vector<ControlPoint> points = parseControlPoints(text, path);
  Script script;
  script.path = path;
  auto add = [&](ScriptOp op, int line, double x = 0) -> ScriptCommand& {
    ScriptCommand c;
    c.op = op;
    c.line = line;
    c.v.x() = x;
    script.commands.push_back(c);
    return script.commands.back();
  };
  const ControlPoint& first = points.front();
  double heading = 0, pitch = 0;
  headingPitchFromQuaternion(first.rotation, heading, pitch);
  add(ScriptOp::Mode, first.line).fly = true;
  ScriptCommand& start = add(ScriptOp::Start, first.line);
  start.v = first.position;
  start.hasZ = true;
  start.hasHeading = true;
  start.heading = heading;
  add(ScriptOp::Look, first.line, pitch);
  for (std::size_t i = 1; i < points.size(); ++i) {
    const ControlPoint& prev = points[i - 1];
    const ControlPoint& cp = points[i];
    const double dt = cp.time - prev.time;  // > 0: parseControlPoints checks the order
    const double dist = (cp.position - prev.position).norm();
    headingPitchFromQuaternion(cp.rotation, heading, pitch);
    if (dist < kSamePointDistance) {
      add(ScriptOp::Heading, cp.line, heading);
      add(ScriptOp::Look, cp.line, pitch);
      add(ScriptOp::Wait, cp.line, dt);
      continue;
    }
    add(ScriptOp::Speed, cp.line, dist / dt);
    add(ScriptOp::Heading, cp.line, heading);
    add(ScriptOp::Look, cp.line, pitch);
    ScriptCommand& go = add(ScriptOp::Goto, cp.line);
    go.v = cp.position;
    go.hasZ = true;
  }
  return script;
}

}  // namespace nestwalk
