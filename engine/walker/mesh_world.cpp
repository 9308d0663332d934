// The equipment's triangles for the exact methods (mesh_world.h).
#include "nestwalk/walker/mesh_world.h"

#include "nestwalk/scene/scene.h"

#include <algorithm>
#include <atomic>
#include <limits>
#include <stdexcept>

namespace nestwalk {
namespace {

/// Metres along the step: already within the contact tolerance at its start, the body presses
/// into the triangles when moving this far along the step brings it closer (1 mm is far above the
/// distance's rounding and far below any step).
constexpr double kPressProbeDistance = 1e-3;
/// Metres: conservative advancement stops this far short of the computed distance, so that the
/// last advance lands within the contact tolerance instead of on the surface.
constexpr double kAdvanceMargin = 0.5 * kMeshContactTolerance;

}  // namespace

std::shared_ptr<const MeshWorld> MeshWorld::fromScene(const Scene& scene) {
  auto world = std::make_shared<MeshWorld>();
  static std::atomic<std::uint64_t> lastId{0};
  world->id_ = ++lastId;
  world->models_.reserve(scene.models.size());
  for (const SceneModel& m : scene.models) {
    world->models_.push_back({KdopTree(m.mesh), m.mesh.triangles.size()});
  }
  world->unitParts_.resize(scene.units.size());
  for (std::size_t u = 0; u < scene.units.size(); ++u)
    for (std::uint32_t i : scene.units[u].instances) {
      const SceneInstance& inst = scene.instances[i];
      world->unitParts_[u].push_back(
          {inst.model, world->partCount_++, inst.toLocal.rotation, inst.toLocal.scale, inst.toLocal.translation});
    }
  return world;
}

std::size_t MeshWorld::triangles(std::size_t unit) const {
  std::size_t n = 0;
  for (const Part& p : unitParts_[unit]) n += models_[p.model].triangles;
  return n;
}

Obb<double> MeshWorld::toModel(const Part& p, const Obb<double>& box) const {
  Obb<double> b;
  b.center = p.rotation.transpose() * (box.center - p.translation) / p.scale;
  b.axes = p.rotation.transpose() * box.axes;
  b.halfExtents = box.halfExtents / p.scale;
  return b;
}

bool MeshWorld::overlaps(std::uint32_t unit, const Obb<double>& box, MeshQueryCounters& c) const {
  for (const Part& p : unitParts_[unit]) {
    const Model& m = models_[p.model];
    const Obb<double> b = toModel(p, box);
    if (m.tree.overlaps(b, &c)) return true;
  }
  return false;
}

double MeshWorld::distance(std::uint32_t unit, const Obb<double>& box, MeshQueryCounters& c) const {
  double best = std::numeric_limits<double>::infinity();
  for (const Part& p : unitParts_[unit]) {
    const Model& m = models_[p.model];
    const Obb<double> b = toModel(p, box);
    const double dm = m.tree.distance(b, &c);
    best = std::min(best, dm * p.scale);
  }
  return best;
}

double MeshWorld::nearestTriangle(std::uint32_t unit, const Vec3<double>& point, std::optional<Triangle>& nearest) const {
  double best = std::numeric_limits<double>::infinity();
  nearest.reset();
  const Obb<double> probe{point, Mat3<double>::Identity(), Vec3<double>::Zero()};
  MeshQueryCounters c;
  for (const Part& p : unitParts_[unit]) {
    Triangle t;
    const double d = models_[p.model].tree.distance(toModel(p, probe), &c, &t) * p.scale;
    if (d < best) {
      best = d;
      for (Vec3<double>& v : t) v = p.scale * (p.rotation * v) + p.translation;  // model -> local
      nearest = t;
    }
  }
  return best;
}

std::optional<MeshWorld::Contact> MeshWorld::firstContact(std::uint32_t unit, const Obb<double>& box,
                                                           const Vec3<double>& d, double t0, MeshQueryCounters& c,
                                                           MeshContactSearch search, SweepMemory* memory) const {
  if (memory && (memory->worldId_ != id_ || memory->parts_.size() != partCount_))
    throw std::logic_error("MeshWorld: a sweep memory made for another world");
  return search == MeshContactSearch::Swept ? sweptContact(unit, box, d, t0, c, memory)
                                            : advancementContact(unit, box, d, t0, c);
}

MeshWorld::SweepMemory MeshWorld::sweepMemory() const {
  SweepMemory memory;
  memory.worldId_ = id_;
  memory.parts_.resize(partCount_);
  return memory;
}

CoherentSweepCounters MeshWorld::SweepMemory::counters() const {
  CoherentSweepCounters sum;
  for (const CoherentSweep& part : parts_) {
    sum.remembered += part.counters().remembered;
    sum.lookAheads += part.counters().lookAheads;
    sum.exact += part.counters().exact;
  }
  return sum;
}

bool MeshWorld::pressesIn(std::uint32_t unit, const Obb<double>& box, const Vec3<double>& d,
                          MeshQueryCounters& c) const {
  const double length = d.norm();
  if (length == 0.0) return true;
  Obb<double> probe = box;
  probe.center += std::min(1.0, kPressProbeDistance / length) * d;
  return distance(unit, probe, c) < distance(unit, box, c);
}

std::optional<MeshWorld::Contact> MeshWorld::sweptContact(std::uint32_t unit, const Obb<double>& box,
                                                           const Vec3<double>& d, double t0,
                                                           MeshQueryCounters& c, SweepMemory* memory) const {
  Obb<double> grown = box;
  grown.halfExtents.array() += kMeshContactGrowth;
  const double start = std::max(0.0, t0);
  std::optional<Contact> first;
  for (const Part& p : unitParts_[unit]) {
    const Model& m = models_[p.model];
    const Obb<double> b = toModel(p, grown);
    const Vec3<double> dm = p.rotation.transpose() * d / p.scale;
    const MeshSweepHit hit =
        memory ? memory->parts_[p.slot].sweep(m.tree, b, dm, start, &c) : m.tree.sweep(b, dm, start, &c);
    if (hit.contact && (!first || hit.t < first->t)) first = Contact{hit.t, true, p.rotation * hit.normal};
  }
  // Touching where the search starts, at the very start of the step: a contact only if the motion
  // presses in (the walker must be able to move away from a contact).
  if (first && first->t == 0.0) first->pressing = pressesIn(unit, box, d, c);
  return first;
}

std::optional<MeshWorld::Contact> MeshWorld::advancementContact(std::uint32_t unit, const Obb<double>& box,
                                                                 const Vec3<double>& d, double t0,
                                                                 MeshQueryCounters& c) const {
  const double length = d.norm();
  Obb<double> moved = box;
  auto distanceAt = [&](double t) {
    moved.center = box.center + t * d;
    return distance(unit, moved, c);
  };
  double t = std::max(0.0, t0);
  double dist = distanceAt(t);
  if (dist <= kMeshContactTolerance) {
    // Already in contact where the search starts (see sweptContact).
    Contact contact{t, true};
    if (t == 0.0) contact.pressing = pressesIn(unit, box, d, c);
    return contact;
  }
  if (length == 0.0) return std::nullopt;
  for (int i = 0; i < kMaxAdvancementSteps; ++i) {
    t += (dist - kAdvanceMargin) / length;
    if (t > 1.0) return std::nullopt;
    dist = distanceAt(t);
    if (dist <= kMeshContactTolerance) return Contact{t, true};
  }
  return Contact{t, true};  // grazing for too long: a conservative early contact
}

}  // namespace nestwalk
