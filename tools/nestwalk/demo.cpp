// nestwalk demo: the main job until the flythrough exists. Fits the nested volumes of the bundled
// weather station, places it on a UTM-sized site, and walks a viewer's body box towards it,
// printing the three-stage verdict at each position.
#include "nestwalk/core/angles.h"
#include "nestwalk/geometry/nested.h"
#include "nestwalk/geometry/obb_fit.h"
#include "nestwalk/scene/model_geometry.h"
#include "tools/nestwalk/commands.h"

#include <Eigen/Geometry>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

namespace nestwalk::tools {
namespace {

void printBox(const char* label, const Obb<double>& b) {
  std::printf("  %-22s centre (%.3f, %.3f, %.3f)  half extents (%.3f, %.3f, %.3f) m  volume %.4f m3\n", label,
              b.center.x(), b.center.y(), b.center.z(), b.halfExtents.x(), b.halfExtents.y(), b.halfExtents.z(),
              b.volume());
}

void runDemo(const std::string& assets) {
  const std::string path = assets + "/models/weather_station.obj";
  const TriangleMesh model = loadModelGeometry(path);
  std::printf("Model %s: %zu vertices, %zu triangles\n", path.c_str(), model.vertices.size(), model.triangles.size());

  Aabb<double> aabb;
  for (const auto& v : model.vertices) aabb.extend(v);
  std::printf("  %-22s min (%.3f, %.3f, %.3f)  max (%.3f, %.3f, %.3f) m  volume %.4f m3\n", "outer AABB", aabb.min.x(),
              aabb.min.y(), aabb.min.z(), aabb.max.x(), aabb.max.y(), aabb.max.z(), aabb.volume());
  Obb<double> inner;
  for (ObbFitter fitter : {ObbFitter::Covariance, ObbFitter::HullSearch}) {
    const auto t0 = std::chrono::steady_clock::now();
    inner = fitObb(model.vertices, fitter);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    char label[64];
    std::snprintf(label, sizeof label, "inner OBB (%s)", fitterName(fitter));
    printBox(label, inner);
    std::printf("  %-22s fitted in %.2f ms\n", "", ms);
  }

  // The station stands on a bench of a dump in UTM zone 51N, turned 30 degrees.
  Similarity<double> place;
  place.rotation = Eigen::AngleAxisd(radians(30.0), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  place.translation = {550012.25, 4650034.75, 812.0};
  const Obb<double> station = place.apply(inner);
  std::printf("\nStation placed at E %.2f N %.2f Z %.2f, heading 30 deg\n", place.translation.x(), place.translation.y(),
              place.translation.z());

  // A walker's body box (0.5 x 0.5 x 1.8 m) approaching along -x, facing its direction of travel.
  std::printf("\n  %-10s %-8s %-10s %s\n", "distance", "verdict", "stage", "separating axis");
  for (double d : {20.0, 3.0, 1.0, 0.6, 0.45, 0.40, 0.30, 0.0}) {
    Obb<double> body;
    body.center = place.translation + Eigen::Vector3d(d, 0.05, 0.9);
    body.axes = Eigen::AngleAxisd(radians(10.0), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    body.halfExtents = {0.25, 0.25, 0.9};
    const NestedResult r = testBoxPair(body, station);
    const char* axis = r.stage == OverlapStage::AabbAabb ? aabbAxisName(r.axis) : satAxisName(r.axis);
    std::printf("  %-10.2f %-8s %-10s %s\n", d, r.overlap ? "blocked" : "free", stageName(r.stage), axis);
  }
}

}  // namespace

void registerDemo(CLI::App& app) {
  auto assets = std::make_shared<std::string>(NESTWALK_ASSETS_DIR);
  CLI::App* cmd = app.add_subcommand("demo", "Fit the bundled weather station's volumes and test a walker against it");
  cmd->add_option("--assets", *assets, "Folder of the bundled assets")->capture_default_str();
  cmd->callback([assets] { runDemo(*assets); });
}

}  // namespace nestwalk::tools
