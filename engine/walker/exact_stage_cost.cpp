// The exact stage's cost on a unit, from sample sweeps (exact_stage_cost.h).
#include "nestwalk/walker/exact_stage_cost.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace nestwalk {
namespace {

/// Metres: the approaches start this far outside the unit's outer AABB.
constexpr double kApproachMargin = 1.0;
/// Metres: the pressing step starts this far from the contact (the walker's kStopDistance, walker.h,
/// which sits above this file).
constexpr double kPressGap = 0.5e-3;
/// Radians: the pressing step turns this far along the surface.
constexpr double kPressTurn = 20.0 * std::numbers::pi / 180.0;

}  // namespace

ExactStageCost sampleExactStageCost(const MeshWorld& meshes, std::uint32_t unit, const Aabb<double>& outer,
                                    const Vec3<double>& bodyHalfExtents) {
  ExactStageCost cost;
  const Vec3<double> centre = outer.center();
  const double reach = 0.5 * outer.size().head<2>().norm() + bodyHalfExtents.head<2>().norm() + kApproachMargin;
  auto count = [&](const Obb<double>& box, const Vec3<double>& d, double t0) {
    MeshQueryCounters c;
    meshes.firstContact(unit, box, d, t0, c);
    cost.maxTests = std::max(cost.maxTests, c.nodeTests + c.triangleTests);
    ++cost.sweeps;
  };
  for (int side = 0; side < kCostSampleSides; ++side) {
    const double angle = 2 * std::numbers::pi * side / kCostSampleSides;
    const Vec3<double> toward(-std::sin(angle), -std::cos(angle), 0.0);
    Obb<double> box;
    box.halfExtents = bodyHalfExtents;
    box.axes = Eigen::AngleAxisd(std::atan2(toward.y(), toward.x()), Vec3<double>::UnitZ()).toRotationMatrix();
    box.center = Vec3<double>(centre.x(), centre.y(), outer.min.z() + bodyHalfExtents.z()) - reach * toward;
    MeshQueryCounters ignored;
    const std::optional<MeshWorld::Contact> contact = meshes.firstContact(unit, box, reach * toward, 0.0, ignored);
    if (!contact) continue;
    const double along = contact->t * reach;  // metres to the contact
    Obb<double> before = box;
    before.center += std::max(0.0, along - kCostSampleStep) * toward;
    count(before, kCostSampleStep * toward, 0.0);
    Obb<double> held = box;
    held.center += std::max(0.0, along - kPressGap) * toward;
    count(held, kCostSampleStep * (Eigen::AngleAxisd(kPressTurn, Vec3<double>::UnitZ()) * toward), 0.0);
  }
  return cost;
}

}  // namespace nestwalk
