// A contact method's sweeps compared with an exact reference on the very same steps: the accuracy
// half of the methods report (method_report.h). The comparison watches a method's CollisionWorld
// (a SweepObserver, collision_world.h); for every sweep it answers, the reference world (an exact
// method, nested+mesh by conservative advancement (mesh_world.h), over the same units) sweeps the
// same body along the same step, and the two answers are tallied.
//
// Lifetimes: the comparison holds the reference world by reference and must not outlive it; the
// method's world holds the comparison by pointer while it observes (ObservedSweeps), so the
// comparison must outlive that scope. Not thread-safe: one world, one thread.
// Units: as CollisionWorld's (local frame, metres); the tally's fields ending in Mm are
// millimetres.
#pragma once

#include "nestwalk/walker/collision_world.h"

#include <cstdint>

namespace nestwalk {

/// How far beyond the end of a blocked step the reference looks for real geometry along the same
/// direction, metres: a stop with real geometry within it is an early stop (the volumes stop the
/// body short), one without is a false block. 1 m is about a stride: a stop that short of the
/// real surface still looks like contact to a walker; anything further away is not contact.
inline constexpr double kEarlyStopHorizon = 1.0;

struct ReferenceTally {
  std::uint64_t sweeps = 0;             // sweeps compared
  std::uint64_t contacts = 0;           // the method found a contact within the step
  std::uint64_t referenceContacts = 0;  // the reference did
  std::uint64_t missed = 0;             // the reference's contact came before the method's (by more
                                        // than both exact methods' contact tolerance), or the method
                                        // found none: the viewer would go into real geometry
  std::uint64_t earlyStops = 0;         // the method stopped the body short of the real geometry along
                                        // the same direction by more than both exact methods' contact
                                        // tolerance: within the step, or further on within
                                        // kEarlyStopHorizon (the volumes stop the body short)
  double earlyStopMaxMm = 0, earlyStopSumMm = 0;  // how far short: the distance the body could still
                                                  // have moved along the step to the real contact
  std::uint64_t falseBlocks = 0;        // the method stopped the step, and the real geometry is not
                                        // met along that direction within kEarlyStopHorizon either
};

class ReferenceComparison : public SweepObserver {
 public:
  explicit ReferenceComparison(const CollisionWorld& reference) : reference_(reference) {}

  void onSweep(const NestedVolume<double>& viewer, const Vec3<double>& d, const SweepHit& hit) override;
  const ReferenceTally& tally() const { return tally_; }

 private:
  const CollisionWorld& reference_;
  ReferenceTally tally_;
};

}  // namespace nestwalk
