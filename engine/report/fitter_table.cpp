// The OBB fitters' table (fitter_table.h) against CGAL's optimal oriented
// bounding box (CGAL::oriented_bounding_box, Chang, Gorissen & Melchior 2011: a genetic and
// Nelder-Mead search over rotations, near-optimal), volumes and fitting times. The only file of
// the report compiled with CGAL.
#include "nestwalk/report/fitter_table.h"

#include "nestwalk/core/stopwatch.h"
#include "nestwalk/geometry/obb_fit.h"
#include "nestwalk/scene/scene.h"

#include <CGAL/Aff_transformation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/optimal_bounding_box.h>

#include <filesystem>

namespace nestwalk {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
constexpr unsigned kCgalSeed = 20240601;  // CGAL's search is randomised: a fixed seed, the same box every run

/// The volume of CGAL's optimal box of `points`: the points are moved to their AABB's centre (CGAL
/// computes in double too), CGAL finds the rotation, and the volume is that of the rotated points'
/// axis-aligned bounds. CGAL takes its own convex hull, so nothing of ours enters this value.
double optimalVolume(const std::vector<Vec3<double>>& points) {
  Aabb<double> bounds;
  for (const Vec3<double>& p : points) bounds.extend(p);
  const Vec3<double> centre = bounds.center();
  std::vector<Kernel::Point_3> moved;
  moved.reserve(points.size());
  for (const Vec3<double>& p : points) moved.emplace_back(p.x() - centre.x(), p.y() - centre.y(), p.z() - centre.z());
  Kernel::Aff_transformation_3 rotation;
  CGAL::oriented_bounding_box(moved, rotation, CGAL::parameters::random_seed(kCgalSeed).use_convex_hull(true));
  Aabb<double> rotated;
  for (const Kernel::Point_3& p : moved) {
    const Kernel::Point_3 q = rotation.transform(p);
    rotated.extend(Vec3<double>(q.x(), q.y(), q.z()));
  }
  return rotated.volume();
}

}  // namespace

std::vector<FitterRow> measureFitters(const Scene& scene, int repetitions) {
  std::vector<FitterRow> rows;
  for (const SceneModel& model : scene.models) {
    const TriangleMesh& g = model.mesh;
    FitterRow row;
    row.model = std::filesystem::path(model.path).filename().string();
    row.triangles = g.triangles.size();
    row.vertices = g.vertices.size();
    row.hullPoints = model.hullPoints.size();
    row.covarianceMicros = 1e6 * leastSeconds(repetitions, [&] {
      row.covarianceVolume = fitObb(g.vertices, ObbFitter::Covariance).volume();
    });
    row.hullSearchMicros = 1e6 * leastSeconds(repetitions, [&] {
      row.hullSearchVolume = fitObb(g.vertices, ObbFitter::HullSearch).volume();
    });
    row.optimalMicros = 1e6 * leastSeconds(repetitions, [&] { row.optimalVolume = optimalVolume(g.vertices); });
    rows.push_back(row);
  }
  return rows;
}

}  // namespace nestwalk
