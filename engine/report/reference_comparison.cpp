#include "nestwalk/report/reference_comparison.h"

#include <algorithm>

namespace nestwalk {
namespace {

/// The shortest step length the comparison divides by, metres: a zero-length step has no contact
/// time to compare, and 1e-12 m keeps the slack finite (below it every contact is at t = 0).
constexpr double kShortestStep = 1e-12;

}  // namespace

void ReferenceComparison::onSweep(const NestedVolume<double>& viewer, const Vec3<double>& d, const SweepHit& hit) {
  CollisionCounters ignored;
  const SweepHit exact = reference_.sweep(viewer, d, ignored);
  const double length = d.norm();
  // Both exact methods stop within kMeshContactTolerance of the triangles: a contact up to twice
  // that later (as a fraction of the step) is the same contact.
  const double slack = 2.0 * kMeshContactTolerance / std::max(length, kShortestStep);
  ++tally_.sweeps;
  tally_.contacts += hit.contact;
  tally_.referenceContacts += exact.contact;
  if (exact.contact && (!hit.contact || hit.t > exact.t + slack)) ++tally_.missed;
  if (!hit.contact) return;
  // Where along the motion (metres from the step's start) the real geometry stops the body: in this
  // step, or further along the same direction within the horizon; nowhere: a false block.
  double real = exact.t * length;
  if (!exact.contact) {
    const double reach = std::max(length, kEarlyStopHorizon);
    const SweepHit further = length > 0.0 ? reference_.sweep(viewer, d * (reach / length), ignored) : exact;
    if (!further.contact) {
      ++tally_.falseBlocks;
      return;
    }
    real = further.t * reach;
  }
  const double shortBy = real - hit.t * length;
  if (shortBy > 2.0 * kMeshContactTolerance) {
    ++tally_.earlyStops;
    tally_.earlyStopMaxMm = std::max(tally_.earlyStopMaxMm, 1000.0 * shortBy);
    tally_.earlyStopSumMm += 1000.0 * shortBy;
  }
}

}  // namespace nestwalk
