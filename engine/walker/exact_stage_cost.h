// What the exact mesh stage costs on one collision unit, measured at load on sample sweeps of the
// viewer's body box: Auto's second criterion (contact_choice.h states both, and holds the verdict,
// ExactStageCost). A unit whose inner
// OBB is not tight gets the exact stage only when its sweeps stay within kMaxExactStageTests
// bounding-volume and triangle tests; above that (a scanned wall of millions of tiny triangles, a
// lattice mast tessellated to the millimetre) Auto keeps the nested test alone for it, and the
// report's auto table counts it.
//
// Samples: the body box, upright, on the unit's outer AABB's floor, approaches the AABB's centre
// from kCostSampleSides directions, starting a metre outside. For each, one long sweep finds the
// first contact (none: the direction is skipped); then the two sweeps the walker makes there are
// counted: the walking step (kCostSampleStep metres) that ends at the contact, and a step pressing
// on from 0.5 mm short of it (where the walker stops), turned 20 degrees along the surface. The cost is the most
// tests any counted sweep made. Counted, not timed: the verdict is the same on every machine and
// every run. On this machine a test costs 25-80 ns, so the bound is about 100-300 us a step.
// Load time: 3 sweeps a direction, about 0.1 ms a unit on the shared 23k-triangle dump truck.
//
// Units: the local frame, metres. Thread safety: a pure function of its arguments (the MeshWorld
// is read only).
#pragma once

#include "nestwalk/geometry/volumes.h"
#include "nestwalk/walker/contact_choice.h"
#include "nestwalk/walker/mesh_world.h"

namespace nestwalk {

/// Directions the body approaches a unit from, and its step (metres: 1.4 m/s at 60 Hz).
inline constexpr int kCostSampleSides = 8;
inline constexpr double kCostSampleStep = 1.4 / 60.0;

/// The exact stage's cost on `unit` (see above); `outer` is the unit's outer AABB, `bodyHalfExtents`
/// the viewer's body (forward, sideways, up).
ExactStageCost sampleExactStageCost(const MeshWorld& meshes, std::uint32_t unit, const Aabb<double>& outer,
                                    const Vec3<double>& bodyHalfExtents);

}  // namespace nestwalk
