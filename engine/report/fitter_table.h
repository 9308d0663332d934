// The OBB fitters' table of the methods report (method_report.h): per model of the scene, the
// covariance and hull-search boxes (geometry/obb_fit.h) against CGAL's optimal oriented bounding
// box, volumes and fitting times.
// Thread safety: keeps no state; the scene (its model nodes included) is only read, and CGAL runs
// with a fixed seed of its own.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace nestwalk {

struct Scene;

/// One row of the fitter table: a model of the scene.
struct FitterRow {
  std::string model;              // the file name
  std::size_t triangles = 0, vertices = 0, hullPoints = 0;
  double covarianceVolume = 0, hullSearchVolume = 0, optimalVolume = 0;  // m^3 (model units cubed)
  double covarianceMicros = 0, hullSearchMicros = 0, optimalMicros = 0;  // per fit, least over repetitions
};

/// The fitters on every model of a loaded scene (all of its vertices, as loadModelGeometry reads
/// them), each fit repeated `repetitions` times; CGAL with a fixed seed.
std::vector<FitterRow> measureFitters(const Scene& scene, int repetitions);

}  // namespace nestwalk
