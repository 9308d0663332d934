// A mover's sweeps through a model's tree, answered from a remembered free path (coherent_sweep.h).
#include "nestwalk/geometry/coherent_sweep.h"

#include "nestwalk/geometry/triangle_sweep.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace nestwalk {
namespace {

using V3 = Vec3<double>;

/// Whether p (relative to the free path's start) lies closer than `room` to the segment [0, path].
bool nearPath(const V3& p, const V3& path, double inversePath2, double room) {
  const double s = std::clamp(p.dot(path) * inversePath2, 0.0, 1.0);
  return (p - s * path).squaredNorm() < room * room;
}

/// The look-ahead: the grown box along `motion` (k steps), as far as the tree proves it free
/// (MeshTree::freeUntil: never past a contact); contact false when free all the way.
MeshSweepHit lookAhead(const KdopTree& tree, const Obb<double>& grown, const V3& motion, MeshQueryCounters* counters) {
  const double free = tree.freeUntil(grown, motion, counters);
  MeshSweepHit ahead;
  if (free != std::numeric_limits<double>::infinity()) {
    ahead.contact = true;
    ahead.t = free;
  }
  return ahead;
}

}  // namespace

bool CoherentSweep::covers(const Obb<double>& box, const V3& d, double tStart) const {
  if (!valid_ || box.halfExtents != anchor_.halfExtents) return false;
  // The exact sweep may report a contact up to its slack short of a triangle: the step's box must
  // stay that much further inside the grown box than the margin alone asks, to get the same answer.
  // A step from its start (tStart 0, the walker's usual step) that passes has its centre and its
  // motion bounded by the free path, so remember() found the slack's bound for it once.
  double room = tStart == 0 ? roomFromStart_ : room_ - sweepBoxTriangleSlack(box, d, reach_);
  if (box.axes != anchor_.axes)  // the most a point of the box moves when its axes turn
    for (int j = 0; j < 3; ++j) room -= (box.axes.col(j) - anchor_.axes.col(j)).norm() * box.halfExtents[j];
  if (!(room > 0)) return false;  // nearPath squares it: a negative room must not pass
  const V3 start = box.center - anchor_.center;
  return nearPath(start + tStart * d, path_, inversePath2_, room) && nearPath(start + d, path_, inversePath2_, room);
}

void CoherentSweep::remember(const Obb<double>& box, const V3& start, double margin, const MeshSweepHit& ahead,
                             double k, const V3& step) {
  valid_ = true;
  used_ = 0;
  lastSteps_ = (ahead.contact ? ahead.t : 1.0) * k;
  endsAtSurface_ = ahead.contact;
  anchor_ = box;
  anchor_.center = start;
  // Short of the contact by a relative hair, so the free path's end is strictly before it.
  path_ = (ahead.contact ? ahead.t * (1.0 - kCoverSlack) : 1.0) * k * step;
  inversePath2_ = 1.0 / path_.squaredNorm();
  // Rounding of the coverage test: a point it passes is within the margin of the path, so its
  // coordinates are bounded by these.
  const double magnitude = anchor_.center.cwiseAbs().maxCoeff() + path_.cwiseAbs().maxCoeff() +
                           box.halfExtents.sum() + 2 * margin;
  room_ = margin - kCoverSlack * magnitude;
  // The exact sweep's slack for any step from its start that covers() passes: its centre lies
  // within the margin of the free path (so its max norm is at most farthest.center's), its motion
  // is at most the path and twice the margin long, and the slack grows with both
  // (triangle_sweep.h).
  Obb<double> farthest = box;
  farthest.center = V3::Constant(anchor_.center.cwiseAbs().maxCoeff() + path_.cwiseAbs().maxCoeff() + margin);
  roomFromStart_ = room_ - sweepBoxTriangleSlack(farthest, V3(path_.norm() + 2 * margin, 0, 0), reach_);
  if (ahead.contact) lookAhead_ = std::max(1.0, 0.5 * lookAhead_);  // it met a surface: shorter next
}

MeshSweepHit CoherentSweep::sweep(const KdopTree& tree, const Obb<double>& box, const V3& d, double tStart,
                                  MeshQueryCounters* counters) {
  if (tree.id() != treeId_) {  // a different tree: nothing learnt holds (the counters go on)
    const CoherentSweepCounters stats = stats_;
    *this = CoherentSweep{};
    stats_ = stats;
    treeId_ = tree.id();
    reach_ = tree.reach();
  }
  const V3 lastEnd = lastEnd_;
  lastEnd_ = box.center + d;
  if (covers(box, d, tStart)) {
    ++stats_.remembered;
    ++used_;
    return MeshSweepHit{};  // what MeshTree::sweep answers for a step that touches nothing
  }
  // Non-finite input (which covers never passes: every comparison with a NaN or an infinite room
  // fails): the tree's own answer, or its error; nothing to remember.
  if (!(box.center.allFinite() && box.axes.allFinite() && box.halfExtents.allFinite() && d.allFinite() &&
        std::isfinite(tStart))) {
    forget();
    lastEnd_ = V3::Constant(std::numeric_limits<double>::quiet_NaN());
    ++stats_.exact;
    return tree.sweep(box, d, tStart, counters);
  }
  // A step that does not start within about a step of where the last one ended (a teleport, a
  // new walk, steps the caller did not ask about): what was learnt about the last place does not
  // hold here.
  const double step2 = d.squaredNorm();
  if (!((box.center - lastEnd).squaredNorm() <= step2 + lastStep2_)) {
    lookAhead_ = kFirstLookAheadSteps;
    lookFirst_ = false;
  }
  lastStep2_ = step2;
  if (valid_) {
    // Left the free path: walked to its end (the next look-ahead goes first, and further), or
    // left it early (turning, steering: the next is shorter, after the step's own sweep).
    lookFirst_ = used_ + 2 >= lastSteps_ && !endsAtSurface_;
    lookAhead_ = lookFirst_ ? 2 * lookAhead_ : std::max(1.0, 0.5 * lookAhead_);
    valid_ = false;
  }
  const V3 rest = (1.0 - tStart) * d;  // the step still to go, from where it starts
  const double halfDiagonal = box.halfExtents.norm(), restLength = rest.norm();
  const double margin = kFreeMarginFraction * box.halfExtents.maxCoeff();
  if (!(restLength > 0) || !(margin > 0)) {
    ++stats_.exact;
    return tree.sweep(box, d, tStart, counters);
  }
  // The longest look-ahead along steps of this length, in steps.
  auto longestFor = [&](double stepLength) { return std::max(1.0, kMaxLookAheadRadii * halfDiagonal / stepLength); };
  Obb<double> grown = box;
  grown.halfExtents.array() += margin;
  if (lookFirst_) {
    // The look-ahead first: the grown box from the step's start, k steps' worth.
    grown.center += tStart * d;
    const double k = lookAhead_ = std::clamp(lookAhead_, 1.0, longestFor(restLength));
    const MeshSweepHit ahead = lookAhead(tree, grown, k * rest, counters);
    ++stats_.lookAheads;
    if (!ahead.contact || ahead.t * k > 1.0) {  // free beyond this step: so is the step
      remember(box, grown.center, margin, ahead, k, rest);
      return MeshSweepHit{};
    }
    // It met a surface within this step: the step is swept exactly, and the look-aheads wait
    // for a step clear of the surfaces.
    lookFirst_ = false;
    lookAhead_ = std::max(1.0, 0.5 * lookAhead_);
    ++stats_.exact;
    return tree.sweep(box, d, tStart, counters);
  }
  // The step's own sweep first; a look-ahead after it only when the step reached no triangle
  // (clear of the surfaces: near them the look-ahead would meet one at once, for nothing).
  MeshQueryCounters work;
  const MeshSweepHit hit = tree.sweep(box, d, tStart, &work);
  ++stats_.exact;
  if (counters) {
    counters->nodeTests += work.nodeTests;
    counters->triangleTests += work.triangleTests;
  }
  if (hit.contact || work.triangleTests > 0) return hit;
  // The look-ahead from the step's end, k steps' worth.
  grown.center += d;
  const double k = lookAhead_ = std::clamp(lookAhead_, 1.0, longestFor(d.norm()));
  const MeshSweepHit ahead = lookAhead(tree, grown, k * d, counters);
  ++stats_.lookAheads;
  if (!ahead.contact || ahead.t > 0) remember(box, grown.center, margin, ahead, k, d);
  return hit;
}

}  // namespace nestwalk
