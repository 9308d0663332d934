#include "nestwalk/walker/collision_world.h"

#include "nestwalk/core/stopwatch.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/walker/exact_stage_cost.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>

namespace nestwalk {
namespace {

/// The box the broad phase files a unit under: its outer AABB, or for the OBB-only method the
/// AABB of its inner OBB (the outer AABB need not contain the OBB; see scene.h).
Aabb<double> broadPhaseBox(const NestedVolume<double>& v, VolumeMethod m) {
  return m == VolumeMethod::Obb ? aabbOf(v.inner) : v.outer;
}

/// Whether two sweeps are the same to the last bit (the same body volumes and motion).
bool sameSweep(const NestedVolume<double>& a, const Vec3<double>& da, const NestedVolume<double>& b,
               const Vec3<double>& db) {
  return da == db && a.outer.min == b.outer.min && a.outer.max == b.outer.max && a.inner.center == b.inner.center &&
         a.inner.axes == b.inner.axes && a.inner.halfExtents == b.inner.halfExtents;
}

}  // namespace

CollisionWorld::CollisionWorld(std::vector<NestedVolume<double>> units, std::vector<std::string> names,
                               std::vector<std::string> groups, const MethodSpec& method)
    : units_(std::move(units)), names_(std::move(names)), groups_(std::move(groups)), method_(method) {
  if (names_.size() != units_.size() || groups_.size() != units_.size())
    throw std::invalid_argument("CollisionWorld: units, names and groups differ in length");
  std::vector<Aabb<double>> boxes;
  boxes.reserve(units_.size());
  for (const auto& u : units_) boxes.push_back(broadPhaseBox(u, method_.volumes));
  tree_ = method_.templateHierarchy ? BoxTree::buildTemplate(boxes, groups_) : BoxTree::buildAuto(boxes, method_.autoTree);
}

CollisionWorld CollisionWorld::fromScene(const Scene& scene, const MethodSpec& method,
                                         std::shared_ptr<const MeshWorld> meshes) {
  std::vector<NestedVolume<double>> units;
  std::vector<std::string> names, groups;
  units.reserve(scene.units.size());
  for (const auto& u : scene.units) {
    units.push_back(u.volume);
    names.push_back(u.name);
    groups.push_back(u.group);
  }
  CollisionWorld world(std::move(units), std::move(names), std::move(groups), method);
  if (usesMeshes(method.volumes))
    world.setMeshes(meshes ? std::move(meshes) : MeshWorld::fromScene(scene), scene.spec.viewer.bodyHalfExtents);
  return world;
}

void CollisionWorld::setMeshes(std::shared_ptr<const MeshWorld> meshes, const Vec3<double>& bodyHalfExtents) {
  if (meshes && meshes->units() != units_.size())
    throw std::invalid_argument("CollisionWorld: the meshes' units differ from the world's");
  meshes_ = std::move(meshes);
  last_.valid = false;  // the last answer was found with the old meshes
  sweepMemory_ = meshes_ ? meshes_->sweepMemory() : MeshWorld::SweepMemory{};
  choices_.clear();
  costs_.clear();
  if (method_.volumes != VolumeMethod::Auto || !meshes_) return;
  choices_.reserve(units_.size());
  costs_.resize(units_.size());
  for (std::uint32_t u = 0; u < units_.size(); ++u) {
    if (meshes_->triangles(u) == 0) {  // points or lines: the nested volumes stand for the unit
      choices_.push_back({true, 0.0, 0});
      continue;
    }
    choices_.push_back(obbSurfaceGap(units_[u].inner, [&](const Vec3<double>& p, std::optional<Triangle>& t) {
      return meshes_->nearestTriangle(u, p, t);
    }));
    if (!choices_.back().tight) costs_[u] = sampleExactStageCost(*meshes_, u, units_[u].outer, bodyHalfExtents);
  }
}

SweptNestedResult CollisionWorld::sweepMesh(const NestedVolume<double>& viewer, const Vec3<double>& d, std::uint32_t u,
                                            double t0, const Vec3<double>& normal,
                                            CollisionCounters& counters) const {
  MeshQueryCounters mc;
  const std::optional<MeshWorld::Contact> c = meshWorld().firstContact(u, viewer.inner, d, t0, mc, search_, &sweepMemory_);
  counters.nodeTests += mc.nodeTests;
  counters.primitiveTests += mc.triangleTests;
  SweptNestedResult r;
  if (!c) return r;
  r.contact = true;
  r.t = c->t;
  // sweep() keeps a contact at t = 0 only when the normal opposes the motion: so it must when the
  // motion presses into the triangles, and must not when it leads away.
  const Vec3<double> along = d.normalized();
  if (c->t <= 0.0) r.normal = c->pressing ? Vec3<double>(-along) : along;
  else if (!c->normal.isZero()) r.normal = c->normal;  // the triangles' own (sliding)
  else r.normal = normal.isZero() ? Vec3<double>(-along) : normal;
  return r;
}

const MeshWorld& CollisionWorld::meshWorld() const {
  if (!meshes_) throw std::logic_error("CollisionWorld: a mesh method without meshes (setMeshes)");
  return *meshes_;
}

bool CollisionWorld::hasTriangles(std::uint32_t u) const {
  return meshWorld().triangles(u) > 0;
}

bool CollisionWorld::exactAfterNested(std::uint32_t u) const {
  switch (method_.volumes) {
    case VolumeMethod::NestedMesh: return hasTriangles(u);
    case VolumeMethod::Auto: return exactStage(u);
    default: return false;
  }
}

bool CollisionWorld::meshOverlap(const NestedVolume<double>& viewer, std::uint32_t u,
                                 CollisionCounters& counters) const {
  MeshQueryCounters mc;
  const bool overlap = meshWorld().overlaps(u, viewer.inner, mc);
  counters.nodeTests += mc.nodeTests;
  counters.primitiveTests += mc.triangleTests;
  return overlap;
}

SweptNestedResult CollisionWorld::sweepUnit(const NestedVolume<double>& viewer, const Vec3<double>& d, std::uint32_t u,
                                            CollisionCounters& counters) const {
  const NestedVolume<double>& obj = units_[u];
  switch (method_.volumes) {
    case VolumeMethod::Aabb:
      return sweepOuterOnly(viewer, d, obj);
    case VolumeMethod::Obb:
      ++counters.stageTests[OverlapStage::ObbObb];
      return sweepInnerOnly(viewer, d, obj);
    case VolumeMethod::Kdop18:
      if (hasTriangles(u)) return sweepMesh(viewer, d, u, 0.0, Vec3<double>::Zero(), counters);
      break;  // no triangles (points, lines): the unit's nested volumes stand for it
    case VolumeMethod::Nested:
    case VolumeMethod::NestedMesh:
    case VolumeMethod::Auto:
      break;
  }
  // Stage 1 ran in the broad phase as a static test of the swept box (counted there); its
  // interval is recomputed here because contact needs all three stages at the same t.
  const SweptNestedResult r = sweepNested(viewer, d, obj);
  if (r.stage >= OverlapStage::AabbObb) ++counters.stageTests[OverlapStage::AabbObb];
  if (r.stage >= OverlapStage::ObbObb) ++counters.stageTests[OverlapStage::ObbObb];
  // The triangles lie inside both volumes: no real contact before the nested one.
  if (r.contact && exactAfterNested(u)) return sweepMesh(viewer, d, u, r.t, r.normal, counters);
  return r;
}

SweepHit CollisionWorld::sweep(const NestedVolume<double>& viewer, const Vec3<double>& d,
                               CollisionCounters& counters) const {
  // Frame coherence: a body pressed still against a unit asks the very same sweep frame after
  // frame; the answer is the same, so it is reused (no test is run, none counted).
  using Clock = std::chrono::steady_clock;
  Clock::time_point t0;
  if (timing_) t0 = Clock::now();
  if (last_.valid && sameSweep(last_.viewer, last_.d, viewer, d)) {
    if (timing_) counters.narrowMicros += microsBetween(t0, Clock::now());
    if (observer_) observer_->onSweep(viewer, d, last_.hit);
    return last_.hit;
  }
  const SweepHit hit = sweepUncached(viewer, d, counters);
  last_ = {true, viewer, d, hit};
  return hit;
}

SweepHit CollisionWorld::sweepUncached(const NestedVolume<double>& viewer, const Vec3<double>& d,
                                       CollisionCounters& counters) const {
  Aabb<double> swept = viewer.outer;
  swept.extend(Aabb<double>{viewer.outer.min + d, viewer.outer.max + d});
  if (method_.volumes == VolumeMethod::Obb) {
    const Aabb<double> b = aabbOf(viewer.inner);
    swept = b;
    swept.extend(Aabb<double>{b.min + d, b.max + d});
  }
  using Clock = std::chrono::steady_clock;
  Clock::time_point t0, t1;
  if (timing_) t0 = Clock::now();
  scratch_.clear();
  BroadPhaseCounters bc;
  tree_.query(swept, scratch_, &bc);
  counters.nodeTests += bc.nodeTests;
  counters.stageTests[OverlapStage::AabbAabb] += bc.leafTests;
  if (timing_) t1 = Clock::now();

  SweepHit hit;
  for (std::uint32_t u : scratch_) {
    const SweptNestedResult r = sweepUnit(viewer, d, u, counters);
    if (!r.contact) continue;
    // Touching or overlapping at t = 0: a contact only if the motion presses into the unit along
    // the slab it entered last, so that a viewer placed in contact can always move away.
    if (r.t <= 0.0 && !(r.normal.dot(d) < 0.0)) continue;
    if (!hit.contact || r.t < hit.t || (r.t == hit.t && std::int32_t(u) < hit.unit)) {
      hit.contact = true;
      hit.t = r.t;
      hit.unit = std::int32_t(u);
      hit.normal = r.normal;
    }
  }
  if (timing_) {
    const Clock::time_point t2 = Clock::now();
    counters.broadMicros += microsBetween(t0, t1);
    counters.narrowMicros += microsBetween(t1, t2);
  }
  if (observer_) observer_->onSweep(viewer, d, hit);
  return hit;
}

std::int32_t CollisionWorld::overlapping(const NestedVolume<double>& viewer, CollisionCounters& counters) const {
  scratch_.clear();
  BroadPhaseCounters bc;
  const Aabb<double> box = method_.volumes == VolumeMethod::Obb ? aabbOf(viewer.inner) : viewer.outer;
  tree_.query(box, scratch_, &bc);
  counters.nodeTests += bc.nodeTests;
  counters.stageTests[OverlapStage::AabbAabb] += bc.leafTests;
  std::int32_t found = -1;
  for (std::uint32_t u : scratch_) {
    bool overlap = false;
    switch (method_.volumes) {
      case VolumeMethod::Aabb:
        overlap = true;  // the broad phase's leaf test was the AABB-AABB test
        break;
      case VolumeMethod::Obb:
        ++counters.stageTests[OverlapStage::ObbObb];
        overlap = satObbObb(viewer.inner, units_[u].inner).overlap;
        break;
      case VolumeMethod::Nested:
      case VolumeMethod::NestedMesh:
      case VolumeMethod::Auto: {
        const NestedResult r = testNested(viewer, units_[u]);
        if (r.stage >= OverlapStage::AabbObb) ++counters.stageTests[OverlapStage::AabbObb];
        if (r.stage >= OverlapStage::ObbObb) ++counters.stageTests[OverlapStage::ObbObb];
        overlap = r.overlap;
        if (overlap && exactAfterNested(u)) overlap = meshOverlap(viewer, u, counters);
        break;
      }
      case VolumeMethod::Kdop18:
        if (hasTriangles(u)) {
          overlap = meshOverlap(viewer, u, counters);
        } else {
          overlap = testNested(viewer, units_[u]).overlap;
        }
        break;
    }
    if (overlap && (found < 0 || std::int32_t(u) < found)) found = std::int32_t(u);
  }
  return found;
}

}  // namespace nestwalk
