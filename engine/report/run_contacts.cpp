#include "nestwalk/report/run_contacts.h"

#include "nestwalk/core/angles.h"
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
    if (meshes) {
      MeshQueryCounters counters;
      c.stopGapM = meshes->distance(std::uint32_t(it->second), body.inner, counters);
    }
    out.push_back(std::move(c));
  }
  return out;
}

std::vector<RunContact> measuredContacts(const Scene& scene, const std::vector<FrameRecord>& records,
                                         const MeshWorld* meshes) {
  std::vector<RunContact> contacts = runContacts(scene, records, meshes);
  if (meshes) return contacts;
  std::vector<std::uint32_t> met;
  for (const RunContact& c : contacts)
    if (const int u = c.kind == "terrain" ? -1 : scene.findUnit(c.unit); u >= 0) met.push_back(std::uint32_t(u));
  if (met.empty()) return contacts;
  return runContacts(scene, records, MeshWorld::fromScene(scene, &met).get());
}

}  // namespace nestwalk
