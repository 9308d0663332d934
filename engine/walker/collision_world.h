// The walker's view of the equipment: the collision units' nested volumes in one flat array and
// the broad-phase hierarchy over them, with the swept and static queries a step needs. Built once
// from a loaded scene; the per-step queries allocate nothing once their scratch has grown.
//
// Units: local frame (map - scene origin), metres; a sweep's d is the step's displacement, t the
// fraction of it.
// Ownership: the world owns copies of the units' volumes, names and groups; it shares the MeshWorld
// (a shared_ptr to const) and does not own its observer (setObserver).
// Narrow phase: each broad-phase candidate is tested on its own, scalar (sweepNested for a sweep,
// testNested for overlapping()), and stays so: the float batches do not pay at the candidate
// counts the walker sees. Measured with `nestwalk bench walker` (narrow-phase table, the same
// queries in the same run, 2 shared cores, median of 3 runs): on the bundled flythroughs' 18802
// sweeps a query has 0.18 candidates on average, 1 at p99, 2 at most; testNested per candidate
// costs 19 ns per query there, testBoxPairs (obb_batch.h) on the same candidates 215 ns. Against
// each viewer's k nearest units the scalar test stays ahead at every k measured: k = 1: 21 ns vs
// 472 ns, k = 8: 105 ns vs 458 ns, k = 64: 0.80 us vs 2.6 us. (A one-vs-many NestedBoxSet built
// over the candidates did worse still, 594 ns on the flythroughs and 18 us at k = 64, one run at
// commit 4da75a1, before that set was removed as unused.) Candidates are mostly separated by the
// first, cheap stage, which the scalar test exits early on, while a batch pays its gather and all
// three stages for every lane: there is no threshold up to 64 candidates, and a sweep (first
// contact time) has no batch form at all.
// Thread safety: NOT safe to share between threads. sweep() and overlapping() are const but write
// the world's mutable scratch (the broad phase's hit list), and sweep() also its last-sweep cache
// and the mesh stage's memory of free paths (MeshWorld::SweepMemory),
// so a world answers one thread at a time, even through a const reference (Walker holds one). Give
// each thread its own world: copies share the BoxTree's and the MeshWorld's immutable data (a copy
// also takes the observer pointer: clear it first). The setters (setMeshes, setMeshContactSearch,
// setTiming, setObserver) must not run while the world answers.
#pragma once

#include "nestwalk/geometry/swept.h"
#include "nestwalk/hierarchy/box_tree.h"
#include "nestwalk/scene/scene_file.h"
#include "nestwalk/walker/contact_choice.h"
#include "nestwalk/walker/mesh_world.h"

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
  StageCounts stageTests;                   // per nested stage (the broad phase's leaf tests are
                                            // stage 1, AABB-AABB)
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

/// Watches the sweeps a CollisionWorld answers, for accuracy studies (the report compares every
/// sweep with an exact reference: engine/report/reference_comparison.h). Called after the sweep's
/// own (timed) work, on the thread that swept, with the sweep's input and answer.
class SweepObserver {
 public:
  virtual ~SweepObserver() = default;
  virtual void onSweep(const NestedVolume<double>& viewer, const Vec3<double>& d, const SweepHit& hit) = 0;
};

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
  // when their count differs from the units'. Auto samples the exact stage's cost on each unit
  // whose inner OBB is not tight with a body of `bodyHalfExtents` (exact_stage_cost.h).
  void setMeshes(std::shared_ptr<const MeshWorld> meshes,
                 const Vec3<double>& bodyHalfExtents = ViewerSpec{}.bodyHalfExtents);
  const std::shared_ptr<const MeshWorld>& meshes() const { return meshes_; }
  // How the mesh stage finds a step's first contact (mesh_world.h): swept (default) or by
  // conservative advancement, the independent reference the report compares methods with.
  void setMeshContactSearch(MeshContactSearch search) {
    search_ = search;
    last_.valid = false;  // the last answer was found the other way
  }
  // Auto: whether unit i gets the exact mesh stage after the nested test: its inner OBB is not
  // tight (the verdict on its gap, contact_choice.h) and the stage's sampled cost is affordable
  // (exact_stage_cost.h; sampled only where the OBB is not tight). False and empty for the other
  // methods.
  bool exactStage(std::size_t i) const { return !choices_.empty() && !choices_[i].tight && costs_[i].affordable(); }
  const std::vector<GapVerdict>& contactChoices() const { return choices_; }
  const std::vector<ExactStageCost>& exactStageCosts() const { return costs_; }

  std::size_t size() const { return units_.size(); }
  const NestedVolume<double>& unit(std::size_t i) const { return units_[i]; }
  const std::string& name(std::size_t i) const { return names_[i]; }
  const std::string& group(std::size_t i) const { return groups_[i]; }
  const BoxTree& tree() const { return tree_; }
  const MethodSpec& method() const { return method_; }
  // Measure broad and narrow phase separately (two clock reads per phase and query).
  void setTiming(bool on) { timing_ = on; }
  // Reports every sweep to `observer` (null: none). The world does not own it: the observer must
  // outlive every sweep made while it is set (ObservedSweeps sets it for a scope). Not to be
  // changed while another thread sweeps.
  void setObserver(SweepObserver* observer) { observer_ = observer; }

  // First contact of the viewer's volumes moving by d (local frame) with any unit. A unit the
  // viewer already touches at t = 0 counts only if d presses into it (against the normal of the
  // slab it entered last), so that a viewer stopped in contact can always move away. A sweep
  // identical to the previous one (a body pressed still against a unit, frame after frame) reuses
  // its answer without testing anything again (frame coherence; its counters stay 0). A world
  // answers one thread at a time (its scratch and its last sweep are its own).
  SweepHit sweep(const NestedVolume<double>& viewer, const Vec3<double>& d, CollisionCounters& counters) const;
  // Whether the viewer's volumes overlap any unit (the method's static test); index or -1.
  std::int32_t overlapping(const NestedVolume<double>& viewer, CollisionCounters& counters) const;

 private:
  SweepHit sweepUncached(const NestedVolume<double>& viewer, const Vec3<double>& d, CollisionCounters& counters) const;
  SweptNestedResult sweepUnit(const NestedVolume<double>& viewer, const Vec3<double>& d, std::uint32_t u,
                              CollisionCounters& counters) const;
  // The mesh stage of a sweep: first contact of the body box with unit u's triangles from t0;
  // `normal` is the contact normal reported for t > 0 (sliding).
  SweptNestedResult sweepMesh(const NestedVolume<double>& viewer, const Vec3<double>& d, std::uint32_t u, double t0,
                              const Vec3<double>& normal, CollisionCounters& counters) const;
  bool meshOverlap(const NestedVolume<double>& viewer, std::uint32_t u, CollisionCounters& counters) const;
  // Whether unit u has triangles; the mesh methods test a unit without any (a point cloud, a
  // wireframe) by its nested volumes instead.
  bool hasTriangles(std::uint32_t u) const;
  // Whether the mesh stage follows a nested contact with unit u (NestedMesh: every unit with
  // triangles; Auto: the units whose inner OBB is not tight).
  bool exactAfterNested(std::uint32_t u) const;
  // The meshes, for the mesh methods; throws std::logic_error when they were never set.
  const MeshWorld& meshWorld() const;

  std::vector<NestedVolume<double>> units_;
  std::vector<std::string> names_, groups_;
  MethodSpec method_;
  BoxTree tree_;
  std::shared_ptr<const MeshWorld> meshes_;
  std::vector<GapVerdict> choices_;  // Auto: per unit (setMeshes)
  std::vector<ExactStageCost> costs_;  // Auto: per unit, sampled where the OBB is not tight
  SweepObserver* observer_ = nullptr;  // not owned (setObserver)
  mutable std::vector<std::uint32_t> scratch_;
  struct LastSweep {
    bool valid = false;
    NestedVolume<double> viewer;
    Vec3<double> d = Vec3<double>::Zero();
    SweepHit hit;
  };
  mutable LastSweep last_;  // frame coherence (sweep)
  mutable MeshWorld::SweepMemory sweepMemory_;  // the mesh stage's free paths (swept search)
  MeshContactSearch search_ = MeshContactSearch::Swept;
  bool timing_ = false;
};

/// Sets an observer on a world for the lifetime of this object and clears it again, however the
/// scope ends. The observer and the world must outlive it.
class ObservedSweeps {
 public:
  ObservedSweeps(CollisionWorld& world, SweepObserver& observer) : world_(world) { world_.setObserver(&observer); }
  ~ObservedSweeps() { world_.setObserver(nullptr); }
  ObservedSweeps(const ObservedSweeps&) = delete;
  ObservedSweeps& operator=(const ObservedSweeps&) = delete;

 private:
  CollisionWorld& world_;
};

}  // namespace nestwalk
