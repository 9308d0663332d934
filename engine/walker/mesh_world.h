// The equipment's real triangles for the walker's exact methods: per model a k-DOP-18 tree over
// its triangles (mesh_tree.h, built once per model file), per collision unit
// the instances (model and transform) it is made of. Answers, for the viewer's body box in the
// local frame: does it touch a unit's triangles, how far is it from them, and where along a step
// does it first come within a contact tolerance of them.
//
// First contact along a step (box + t d, t in [t0, 1]), two ways to the same answer:
//  - MeshContactSearch::Swept (the walker's): the box grown by kMeshContactGrowth on every side is
//    swept through the tree once (MeshTree::sweep: exact intervals in t per triangle, never
//    late). The grown box touches a triangle exactly when the real box's distance to it, measured
//    in the box's own axes (the largest of the three per-axis gaps), is at most the growth: so at
//    the contact the Euclidean distance is between kMeshContactGrowth and
//    sqrt(3) kMeshContactGrowth = kMeshContactTolerance, and no earlier time has it at or below
//    kMeshContactGrowth. One traversal per step, whatever the approach angle; with a mover's
//    SweepMemory, none for the steps inside a free path an earlier look-ahead proved
//    (coherent_sweep.h), with the same answers.
//  - MeshContactSearch::Advancement (the reference the report compares every method with):
//    conservative advancement on exact distances. At t the distance D is computed; no point of the
//    box moves more than |d| dt, so nothing can be touched before t + D / |d|, and t advances by
//    that much until D falls to kMeshContactTolerance (or the step ends). Independent of the swept
//    tests (it uses only triangleBoxDistance), slower on grazing motions (more iterations, capped:
//    at the cap the current t is returned, a conservative early contact).
// Neither steps over an obstacle, however thin or fast (a 5 cm pole at 50 m/s is met like any
// other); both stop within kMeshContactTolerance of the surface.
//
// Frames: instances' transforms are similarities (rotation, uniform scale, translation; scene.h);
// the box is taken into each model's frame by the inverse, the distance scaled back.
//
// Units: boxes, d and distances in the local frame, metres; t is the fraction of d.
// Ownership: the trees and the units' transforms are built and copied by fromScene; nothing refers
// back to the Scene or its OSG nodes afterwards.
// Thread safety: a built MeshWorld is immutable (fromScene hands it out as a shared_ptr to const);
// its const queries keep no scratch and may run from several threads at once, each with its own
// MeshQueryCounters and SweepMemory (a mover's: one per thread).
#pragma once

#include "nestwalk/geometry/coherent_sweep.h"
#include "nestwalk/geometry/mesh_tree.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace nestwalk {

struct Scene;

// Contact: within this distance of the triangles (metres). The walker then stops kStopDistance
// (0.5 mm) short along its step, so the stop gap stays within about 0.6 mm.
inline constexpr double kMeshContactTolerance = 1e-4;
// The swept search grows the box by this on every side (metres): its corners then reach
// sqrt(3) times as far, the contact tolerance.
inline constexpr double kMeshContactGrowth = kMeshContactTolerance / 1.7320508075688772;

enum class MeshContactSearch : std::uint8_t { Swept, Advancement };
// Advancement steps per sweep at most: a motion grazing a face keeps the distance small and the
// steps short; at the cap the current t is returned (a conservative early contact). 4096 steps
// of at least kMeshContactTolerance / 2 cover 0.2 m, more than any step at walking speeds.
inline constexpr int kMaxAdvancementSteps = 4096;

class MeshWorld {
 public:
  /// One mover's memory of free space, a CoherentSweep (coherent_sweep.h) per part of every unit:
  /// given to firstContact, the swept search answers the steps inside a remembered free path
  /// without opening the tree (the same answers). Made by sweepMemory(), for this world only
  /// (firstContact throws std::logic_error when given another world's, even one at the same address).
  class SweepMemory {
   public:
    CoherentSweepCounters counters() const;

   private:
    friend class MeshWorld;
    std::uint64_t worldId_ = 0;  // the world's id_ (0: made for none)
    std::vector<CoherentSweep> parts_;
  };
  SweepMemory sweepMemory() const;

  // Trees for every model the scene's units use.
  static std::shared_ptr<const MeshWorld> fromScene(const Scene& scene);

  std::size_t units() const { return unitParts_.size(); }
  std::size_t triangles(std::size_t unit) const;
  bool overlaps(std::uint32_t unit, const Obb<double>& box, MeshQueryCounters& c) const;
  double distance(std::uint32_t unit, const Obb<double>& box, MeshQueryCounters& c) const;
  /// The distance from a point (local frame) to the unit's triangles and the triangle at that
  /// distance (local frame); +infinity and no triangle for a unit without triangles.
  double nearestTriangle(std::uint32_t unit, const Vec3<double>& point, std::optional<Triangle>& nearest) const;

  struct Contact {
    double t = 1.0;
    bool pressing = true;  // at t0 already within the tolerance: whether d moves closer
    Vec3<double> normal = Vec3<double>::Zero();  // local frame, from the triangles toward the box;
                                                 // zero when unknown (at t0, or by advancement)
  };
  // The first t in [t0, 1] at which box + t d comes within the contact tolerance of the unit's
  // triangles (see the header comment); nullopt when it never does within the step.
  std::optional<Contact> firstContact(std::uint32_t unit, const Obb<double>& box, const Vec3<double>& d, double t0,
                                      MeshQueryCounters& c, MeshContactSearch search = MeshContactSearch::Swept,
                                      SweepMemory* memory = nullptr) const;

 private:
  struct Model {
    KdopTree tree;
    std::size_t triangles;
  };
  struct Part {
    std::uint32_t model;
    std::uint32_t slot;     // its place in a SweepMemory
    Mat3<double> rotation;  // model -> local
    double scale;
    Vec3<double> translation;
  };
  Obb<double> toModel(const Part& p, const Obb<double>& box) const;
  std::optional<Contact> sweptContact(std::uint32_t unit, const Obb<double>& box, const Vec3<double>& d, double t0,
                                      MeshQueryCounters& c, SweepMemory* memory) const;
  std::optional<Contact> advancementContact(std::uint32_t unit, const Obb<double>& box, const Vec3<double>& d,
                                            double t0, MeshQueryCounters& c) const;
  // At the very start of a step, within the tolerance already: whether the motion presses in.
  bool pressesIn(std::uint32_t unit, const Obb<double>& box, const Vec3<double>& d, MeshQueryCounters& c) const;
  std::vector<Model> models_;
  std::vector<std::vector<Part>> unitParts_;
  std::uint32_t partCount_ = 0;
  std::uint64_t id_ = 0;  // unique to each world fromScene builds (a SweepMemory names its world by it)
};

}  // namespace nestwalk
