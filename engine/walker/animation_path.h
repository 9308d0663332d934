// OpenSceneGraph AnimationPath files, the camera paths osgviewer records and replays: read as a
// flythrough script (a recorded camera path flies at its own speed), and written from a run's
// camera (`nestwalk run` writes camera.path; `osgviewer scene.osgb -p camera.path` replays it).
//
// Units: times in seconds, positions map coordinates (metres), headings and pitch in degrees.
// Thread safety: pure functions; writeAnimationPath writes through core/output_file.h (one writer
// per path).
#pragma once

#include "nestwalk/walker/script.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace nestwalk {

// An OpenSceneGraph AnimationPath (as osgviewer records with 'z' and AnimationPathManipulator
// reads: lines "time x y z qx qy qz qw", camera orientation) made into a script: `mode fly`, a
// start at the first control point, then for each later point a `speed` (distance over the time
// between points), `heading`/`look` from the camera orientation and a `goto x y z`; points closer
// than 1 mm in space become a `wait`. Positions are map coordinates (export writes the scene in
// map coordinates).
Script scriptFromAnimationPath(const std::string& text, const std::string& path);

struct CameraSample {
  double time = 0;
  Eigen::Vector3d eye = Eigen::Vector3d::Zero();  // map frame
  double headingDeg = 0, pitchDeg = 0;
};

// OSG camera orientation (camera looks down its -Z with +Y up) for a heading and pitch in a z-up
// map frame, as a quaternion (x, y, z, w); and back.
Eigen::Vector4d cameraQuaternion(double headingDeg, double pitchDeg);
void headingPitchFromQuaternion(const Eigen::Vector4d& q, double& headingDeg, double& pitchDeg);

// Writes an AnimationPath text file osgviewer replays (`osgviewer scene.osgb -p run.path`);
// through a temporary file renamed at the end.
void writeAnimationPath(const std::string& path, const std::vector<CameraSample>& samples);

}  // namespace nestwalk
