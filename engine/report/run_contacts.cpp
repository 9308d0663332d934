#include "nestwalk/report/run_contacts.h"

#include "nestwalk/core/angles.h"
#include "nestwalk/geometry/triangle_box.h"
#include "nestwalk/walker/mesh_world.h"
#include "nestwalk/walker/walker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace nestwalk {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Metres: a horizontal eye movement below this between records is standing still (the walker's
/// progress threshold, script_player.h's kProgressEpsilon, is the same order).
constexpr double kMovedEpsilon = 1e-6;

/// The point of the box nearest to `p` (all in one frame).
Vec3<double> nearestPointOf(const Obb<double>& box, const Vec3<double>& p) {
  const Vec3<double> local = box.axes.transpose() * (p - box.center);
  const Vec3<double> clamped = local.cwiseMax(-box.halfExtents).cwiseMin(box.halfExtents);
  return box.center + box.axes * clamped;
}

/// The exact distance from `body` (local frame) to the unit's triangles, scanning each instance's
/// model in the model's own frame: a triangle whose bounding box is at least the best distance so
/// far from the body's (a lower bound of its distance) is skipped.
double gapToUnit(const Scene& scene, const CollisionUnit& unit, const Obb<double>& body) {
  double best = std::numeric_limits<double>::infinity();
  for (std::uint32_t i : unit.instances) {
    const SceneInstance& inst = scene.instances[i];
    const Similarity<double> toModel = inst.toLocal.inverse();
    const Obb<double> box = toModel.apply(body);
    const Aabb<double> bounds = aabbOf(box);
    const double scale = inst.toLocal.scale;  // model distances times this are local ones
    const TriangleMesh& mesh = scene.models[inst.model].mesh;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const Triangle tri = mesh.triangle(t);
      const Vec3<double> lo = tri[0].cwiseMin(tri[1]).cwiseMin(tri[2]), hi = tri[0].cwiseMax(tri[1]).cwiseMax(tri[2]);
      const Vec3<double> apart = (bounds.min - hi).cwiseMax(lo - bounds.max).cwiseMax(0.0);
      if (apart.norm() * scale >= best) continue;
      best = std::min(best, triangleBoxDistance(tri, box) * scale);
    }
  }
  return best;
}

}  // namespace

std::vector<RunContact> runContacts(const Scene& scene, const std::vector<FrameRecord>& records,
                                    const MeshWorld* meshes) {
  std::map<std::string, std::size_t> unitOf;
  for (std::size_t u = 0; u < scene.units.size(); ++u) unitOf.emplace(scene.units[u].name, u);
  const ViewerSpec& viewer = scene.spec.viewer;
  std::vector<RunContact> out;
  std::size_t lastMove = 0;  // the record the eye last moved into (0: none yet)
  for (std::size_t i = 0; i < records.size(); ++i) {
    const FrameRecord& r = records[i];
    if (i > 0 && (r.eye - records[i - 1].eye).head<2>().norm() > kMovedEpsilon) lastMove = i;
    if (!r.blocked || (i > 0 && records[i - 1].blocked && records[i - 1].blockedBy == r.blockedBy)) continue;
    RunContact c;
    c.frame = r.frame;
    c.time = r.time;
    c.eye = r.eye;
    c.unit = r.blockedBy;
    c.approachDeg = c.stopGapM = kNaN;
    const auto it = unitOf.find(r.blockedBy);
    if (it == unitOf.end()) {
      c.kind = "terrain";
      out.push_back(std::move(c));
      continue;
    }
    const CollisionUnit& unit = scene.units[it->second];
    c.kind = unit.kind;
    c.group = unit.group;
    const Eigen::Vector3d feet = r.eye - Eigen::Vector3d(0, 0, viewer.eyeHeight);
    const NestedVolume<double> body = bodyVolumeAt(viewer, scene.origin, feet, r.bodyYawDeg);
    Eigen::Vector2d travel;
    if (lastMove > 0) {
      travel = (records[lastMove].eye - records[lastMove - 1].eye).head<2>();
    } else {
      const auto [s, co] = sinCosDegrees(r.headingDeg);
      travel = {s, co};
    }
    const Eigen::Vector2d toward = (nearestPointOf(unit.volume.inner, body.inner.center) - body.inner.center).head<2>();
    if (toward.norm() > 0 && travel.norm() > 0)
      c.approachDeg = degrees(std::acos(std::clamp(travel.normalized().dot(toward.normalized()), -1.0, 1.0)));
    else
      c.approachDeg = 0;  // the body's centre inside the unit's box: head-on
    MeshQueryCounters counters;
    c.stopGapM = meshes ? meshes->distance(std::uint32_t(it->second), body.inner, counters)
                        : gapToUnit(scene, unit, body.inner);
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace nestwalk
