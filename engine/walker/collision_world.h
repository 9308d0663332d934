// The walker's view of the equipment: the collision units' nested volumes in one flat array and
// the broad-phase hierarchy over them, with the swept and static queries a step needs. Built once
// from a loaded scene; the per-step queries allocate nothing once their scratch has grown.
#pragma once

#include "engine/geometry/swept.h"
#include "engine/hierarchy/box_tree.h"
#include "engine/scene/scene_file.h"
#include "engine/walker/mesh_world.h"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace nestwalk {

struct Scene;

// Counters of one query, added to the frame's record (cost model T = Nv Cv + Np Cp + Nu Cu).
struct CollisionCounters {
  std::uint64_t nodeTests = 0;              // hierarchy inner-node tests (broad phase, and the
                                            // mesh trees' BV tests for the mesh methods)
  std::array<std::uint64_t, 3> stageTests{};  // AABB-AABB, AABB-OBB, OBB-OBB
  std::uint64_t primitiveTests = 0;         // triangle tests (mesh methods)
  double broadMicros = 0, narrowMicros = 0;   // wall-clock, when the world times its queries
  void clear() { *this = {}; }
};

struct SweepHit {
  bool contact = false;
  double t = 1.0;                    // first contact along the step, in [0, 1]
  std::int32_t unit = -1;            // the unit touched first (lowest index on ties)
  Vec3<double> normal = Vec3<double>::Zero();
};

// A method's sweeps compared with an exact reference's on the very same steps (compareWith).
struct ReferenceTally {
  std::uint64_t sweeps = 0;             // sweeps compared
  std::uint64_t contacts = 0;           // the method found a contact within the step
  std::uint64_t referenceContacts = 0;  // the reference did
  std::uint64_t missed = 0;             // the reference's contact came before the method's, or the
                                        // method found none: the viewer would go into real geometry
  std::uint64_t earlyStops = 0;         // the method stopped the step, the real geometry did not,
                                        // but would further along the same direction (within
                                        // kEarlyStopHorizon): the volumes stop the body short
  std::uint64_t falseBlocks = 0;        // the method stopped the step, and the real geometry is not
                                        // met along that direction within kEarlyStopHorizon either
};
inline constexpr double kEarlyStopHorizon = 1.0;  // metres

class CollisionWorld {
 public:
  CollisionWorld() = default;
  // units: local-frame volumes; groups: their group paths (template hierarchy); names for reports.
  CollisionWorld(std::vector<NestedVolume<double>> units, std::vector<std::string> names,
                 std::vector<std::string> groups, const MethodSpec& method);
  // The mesh methods (nested+mesh, kdop18) build the scene's MeshWorld (or share `meshes`).
  static CollisionWorld fromScene(const Scene& scene, const MethodSpec& method,
                                  std::shared_ptr<const MeshWorld> meshes = nullptr);
  // The triangles of the units (same order), for the mesh methods; throws std::invalid_argument
  // when their count differs from the units'.
  void setMeshes(std::shared_ptr<const MeshWorld> meshes);
  const std::shared_ptr<const MeshWorld>& meshes() const { return meshes_; }

  std::size_t size() const { return units_.size(); }
  const NestedVolume<double>& unit(std::size_t i) const { return units_[i]; }
  const std::string& name(std::size_t i) const { return names_[i]; }
  const std::string& group(std::size_t i) const { return groups_[i]; }
  const BoxTree& tree() const { return tree_; }
  const MethodSpec& method() const { return method_; }
  // Measure broad and narrow phase separately (two clock reads per phase and query).
  void setTiming(bool on) { timing_ = on; }
  // Every sweep is also run on `reference` (an exact world over the same units) and the two are
  // compared into `tally` (after the timed part; for accuracy runs, not for timing ones). A
  // contact counts as missed when the reference's comes earlier by more than the mesh contact
  // tolerance (both exact methods stop within it); a contact the reference does not have within
  // the step is an early stop or a false block (ReferenceTally). Null turns it off.
  void compareWith(const CollisionWorld* reference, ReferenceTally* tally) {
    reference_ = reference;
    tally_ = tally;
  }

  // First contact of the viewer's volumes moving by d (local frame) with any unit. A unit the
  // viewer already touches at t = 0 counts only if d presses into it (against the normal of the
  // slab it entered last), so that a viewer stopped in contact can always move away.
  SweepHit sweep(const NestedVolume<double>& viewer, const Vec3<double>& d, CollisionCounters& counters) const;
  // Whether the viewer's volumes overlap any unit (the method's static test); index or -1.
  std::int32_t overlapping(const NestedVolume<double>& viewer, CollisionCounters& counters) const;

 private:
  SweptNestedResult sweepUnit(const NestedVolume<double>& viewer, const Vec3<double>& d, std::uint32_t u,
                              CollisionCounters& counters) const;
  // The mesh stage of a sweep: first contact of the body box with unit u's triangles from t0;
  // `normal` is the contact normal reported for t > 0 (sliding).
  SweptNestedResult sweepMesh(const NestedVolume<double>& viewer, const Vec3<double>& d, std::uint32_t u, double t0,
                              const Vec3<double>& normal, MeshTreeKind kind, CollisionCounters& counters) const;
  bool meshOverlap(const NestedVolume<double>& viewer, std::uint32_t u, MeshTreeKind kind,
                   CollisionCounters& counters) const;
  // Whether unit u has triangles; the mesh methods test a unit without any (a point cloud, a
  // wireframe) by its nested volumes instead.
  bool hasTriangles(std::uint32_t u) const;
  // The meshes, for the mesh methods; throws std::logic_error when they were never set.
  const MeshWorld& meshWorld() const;

  std::vector<NestedVolume<double>> units_;
  std::vector<std::string> names_, groups_;
  MethodSpec method_;
  BoxTree tree_;
  std::shared_ptr<const MeshWorld> meshes_;
  const CollisionWorld* reference_ = nullptr;
  ReferenceTally* tally_ = nullptr;
  mutable std::vector<std::uint32_t> scratch_;
  bool timing_ = false;
};

}  // namespace nestwalk
