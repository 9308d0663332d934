// The walker's view of the equipment: the collision units' nested volumes in one flat array and
// the broad-phase hierarchy over them, with the swept and static queries a step needs. Built once
// from a loaded scene; the per-step queries allocate nothing once their scratch has grown.
#pragma once

#include "engine/geometry/swept.h"
#include "engine/hierarchy/box_tree.h"
#include "engine/scene/scene_file.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace nestwalk {

struct Scene;

// Counters of one query, added to the frame's record (cost model T = Nv Cv + Np Cp + Nu Cu).
struct CollisionCounters {
  std::uint64_t nodeTests = 0;              // hierarchy inner-node tests
  std::array<std::uint64_t, 3> stageTests{};  // AABB-AABB, AABB-OBB, OBB-OBB
  std::uint64_t primitiveTests = 0;
  double broadMicros = 0, narrowMicros = 0;   // wall-clock, when the world times its queries
  void clear() { *this = {}; }
};

struct SweepHit {
  bool contact = false;
  double t = 1.0;                    // first contact along the step, in [0, 1]
  std::int32_t unit = -1;            // the unit touched first (lowest index on ties)
  Vec3<double> normal = Vec3<double>::Zero();
};

class CollisionWorld {
 public:
  CollisionWorld() = default;
  // units: local-frame volumes; groups: their group paths (template hierarchy); names for reports.
  CollisionWorld(std::vector<NestedVolume<double>> units, std::vector<std::string> names,
                 std::vector<std::string> groups, const MethodSpec& method);
  static CollisionWorld fromScene(const Scene& scene, const MethodSpec& method);

  std::size_t size() const { return units_.size(); }
  const NestedVolume<double>& unit(std::size_t i) const { return units_[i]; }
  const std::string& name(std::size_t i) const { return names_[i]; }
  const std::string& group(std::size_t i) const { return groups_[i]; }
  const BoxTree& tree() const { return tree_; }
  const MethodSpec& method() const { return method_; }
  // Measure broad and narrow phase separately (two clock reads per phase and query).
  void setTiming(bool on) { timing_ = on; }

  // First contact of the viewer's volumes moving by d (local frame) with any unit. A unit the
  // viewer already touches at t = 0 counts only if d presses into it (against the normal of the
  // slab it entered last), so that a viewer stopped in contact can always move away.
  SweepHit sweep(const NestedVolume<double>& viewer, const Vec3<double>& d, CollisionCounters& counters) const;
  // Whether the viewer's volumes overlap any unit (the method's static test); index or -1.
  std::int32_t overlapping(const NestedVolume<double>& viewer, CollisionCounters& counters) const;

 private:
  SweptNestedResult sweepUnit(const NestedVolume<double>& viewer, const Vec3<double>& d, std::uint32_t u,
                              CollisionCounters& counters) const;

  std::vector<NestedVolume<double>> units_;
  std::vector<std::string> names_, groups_;
  MethodSpec method_;
  BoxTree tree_;
  mutable std::vector<std::uint32_t> scratch_;
  bool timing_ = false;
};

}  // namespace nestwalk
