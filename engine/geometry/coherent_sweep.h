// MeshTree::sweep for one mover that steps through a model step after step (the walker's body box,
// 60 steps a second): it remembers a stretch of space it has proven free and answers the steps
// that stay inside it without opening the tree. The answers are MeshTree::sweep's, to the bit.
//
// The proof (a look-ahead): the box grown by a margin m on every side (along its own axes) is swept
// through the tree along the step's direction for a longer stretch (the look-ahead: k steps).
// MeshTree::freeUntil is never late, so before the time it reports, the grown box touches no
// triangle: the free path is that stretch of the box centre's motion, [a, a + D]. (freeUntil stops
// at the first contact it meets, where a full sweep would go on to prove which is first: near a
// lattice that was a step's most costly sweep, 90 us on the drill rig's mast.) A later step (box B' =
// centre c', axes R', the same half extents h, moving from c' + tStart d' to c' + d') touches
// nothing when both ends of its centre's path lie closer than m - turn to the free path, with
// turn = sum_j |R'_j - R_j| h_j (the most a point of the box moves when its axes turn from R to
// R'): every point of B' along its path then lies within m of a point of the remembered box on the
// free path, so inside the grown box there (distance to a segment is convex, so the path's two
// ends bound all of it). Such a step is answered "no contact", which is what MeshTree::sweep
// answers for it: the box never touches what the grown box did not.
// A step outside the free path is swept in full, in one of two orders:
//  - the step's own sweep first (after a teleport, a turn off the free path, or a step near a
//    surface), then, only when that step reached no triangle (clear of the surfaces), a look-ahead
//    from its end, which becomes the free path: near a surface a look-ahead would meet it at once,
//    a second sweep for nothing;
//  - the look-ahead first (after a free path walked to its end, where the look-ahead met no
//    triangle: the mover goes on straight, most likely through more free space; a free path that
//    ended at a surface is followed by the step's own sweep, since the mover is about to reach
//    it, and a look-ahead would only pay a second sweep): when the grown box's first contact lies
//    beyond this step, the step is free, answered by that one sweep, and the look-ahead is the
//    new free path; when it lies within the step, the step is swept exactly (two sweeps, once),
//    and the next steps go back to the first order.
// The look-ahead's length adapts to the motion: it starts at kFirstLookAheadSteps steps, doubles
// (up to kMaxLookAheadRadii half diagonals of the box) each time the mover walks a free path to
// its end, and halves (down to the step itself) each time the mover leaves one early (turning,
// steering) or the grown box meets a triangle inside it, so that a turning walker's look-ahead
// costs about its step's own sweep, and a straight one opens the tree once every many steps.
// A step that does not start within about a step of where the last one ended (a teleport, a new
// walk, steps the caller did not ask about) starts afresh: the first order, the first length.
//
// The margin is small (kFreeMarginFraction of the box's largest half extent: 4.5 mm on the body
// box): a larger one lets a turning box keep its free path longer, but every look-ahead near a
// surface meets it sooner, and the steps in that band are swept in full. Measured on the contact
// benchmark (60 Hz walking steps into the shared data's excavator, 441 sweeps, 2026-11-28):
// margins of 5 %, 2 %, 0.5 % and 0.2 % of the half extent answered 41, 49, 52 and 53 % of the
// sweeps from memory, at p50 2.13, 0.32, 0.03 and 0.02 us, p99 38, 25, 19 and 19 us and mean 4.2,
// 3.2, 2.9 and 2.8 us a sweep (each step alone: p50 0.9, p99 13, mean 2.3 us); 0.5 % keeps most of
// the gain with room for a slow turn.
//
// Cost: a remembered step costs two point-to-segment distances (13 ns here, whatever the model); a
// look-ahead one search along its longer motion, stopped at the first contact it meets
// (freeUntil) instead of proving which is first. The price: a step that meets a surface right
// after a free path that met none ends pays two searches, as does a clear step near a surface (its
// look-ahead meets it): the p99 above, against 13 us for each step alone. Sending the steps after
// a free path that ended at a surface to their own sweep first (2026-11-28) took the excavator's
// p99 from 19.4 to 15.9 us and its triangle tests from 10.2 to 9.0 a sweep, the truck's from 7.7 to
// 7.0; the cover test's slack bound for steps from their start, found once per free path, took
// the remembered step's p50 on the drill rig from 0.02-0.03 to 0.01 us (clock's cost taken off).
//
// Units: the tree's (model frame); t is the fraction of d. Tolerances: kFreeMarginFraction,
// kCoverSlack (relative: rounding of the coverage test).
// Exactness: the step is answered from memory only when its box stays, besides the margin's
// allowance for the turn, the exact sweep's own slack (sweepBoxTriangleSlack) inside the grown
// box, so even the sweep's rounding could not have reported a contact: the same answer, to the bit.
// Non-finite input goes to MeshTree::sweep as it is (and is not remembered).
// Ownership: remembers the tree it was last used with by its id (MeshTree::id: a different tree,
// even at the same address, forgets the free path); keeps no reference to triangles.
// Thread safety: one per mover and tree; not to be shared between threads (sweep() writes it).
#pragma once

#include "nestwalk/geometry/mesh_tree.h"

#include <cstdint>
#include <limits>

namespace nestwalk {

// The grown box's margin, as a fraction of the box's largest half extent (unitless): how far a
// later step may stray from the free path (steering, turning) and still be answered from it.
inline constexpr double kFreeMarginFraction = 0.005;
// The first look-ahead's length, in steps (the step being answered is the first of them).
inline constexpr double kFirstLookAheadSteps = 4.0;
// The longest look-ahead, in half diagonals of the box (unitless): about 2 m for the body box,
// 80 walking steps.
inline constexpr double kMaxLookAheadRadii = 2.0;
// Relative rounding allowance of the coverage test (times the magnitude of the centres, the path
// and the margin): two point-to-segment distances in double, far below any margin.
inline constexpr double kCoverSlack = 1e-12;

/// What a CoherentSweep did, step by step (added to, never reset by it, not even for a new tree).
struct CoherentSweepCounters {
  std::uint64_t remembered = 0;  // steps answered from the free path (no tree opened)
  std::uint64_t lookAheads = 0;  // look-ahead sweeps (the grown box along the longer stretch)
  std::uint64_t exact = 0;       // exact sweeps (the step's own)
};

class CoherentSweep {
 public:
  /// MeshTree::sweep(box, d, tStart, counters) on `tree`, answered from the free path where it can.
  MeshSweepHit sweep(const KdopTree& tree, const Obb<double>& box, const Vec3<double>& d, double tStart = 0.0,
                     MeshQueryCounters* counters = nullptr);
  /// Forgets the free path (the next step is swept in full).
  void forget() { valid_ = false; }
  const CoherentSweepCounters& counters() const { return stats_; }

  /// Whether the step (box moving by d from tStart) lies inside the remembered free path.
  bool covers(const Obb<double>& box, const Vec3<double>& d, double tStart) const;

 private:
  // Makes the look-ahead `ahead` (the grown box from `start` along k `step`) the free path.
  void remember(const Obb<double>& box, const Vec3<double>& start, double margin, const MeshSweepHit& ahead,
                double k, const Vec3<double>& step);

  std::uint64_t treeId_ = 0;                    // the tree of the free path (MeshTree::id; 0: none)
  double reach_ = 0;                            // its MeshTree::reach (the exact sweep's slack)
  bool valid_ = false;
  Obb<double> anchor_;                          // the box at the free path's start (not grown)
  Vec3<double> path_ = Vec3<double>::Zero();    // the free path: anchor_.center + s path_, s in [0, 1]
  double inversePath2_ = 0;                     // 1 / |path_|^2
  double room_ = 0;                             // the margin less the coverage test's rounding
  double roomFromStart_ = 0;                    // room_ less the exact sweep's slack, for steps from tStart 0
  double lookAhead_ = kFirstLookAheadSteps;     // the next look-ahead's length, in steps
  double lastSteps_ = 0;                        // the free path's length, in the steps that made it
  Vec3<double> lastEnd_ = Vec3<double>::Constant(std::numeric_limits<double>::quiet_NaN());  // the last step's end
  double lastStep2_ = 0;                        // the last step's squared length
  int used_ = 0;                                // steps answered from the free path
  bool lookFirst_ = false;                      // the next step not remembered: look-ahead first
  bool endsAtSurface_ = false;                  // the free path ends where the grown box met a triangle
  CoherentSweepCounters stats_;
};

}  // namespace nestwalk
