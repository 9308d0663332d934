// The blocking events of a run (report/run_contacts.h) from hand-made records beside a hand-made
// unit: one event per run of records blocked by one thing; the approach angle is the angle between
// the way the walker went and the normal of the face it met, set up here by construction (0 head-on,
// 30 at 30 degrees, 90 grazing); the stop gap is the exact distance from the body box to a
// triangle placed at a known distance; terrain blocks carry no angle and no gap.
#include "nestwalk/report/run_contacts.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace nestwalk {
namespace {

constexpr double kEyeHeight = 1.7;  // the scene's viewer (scene_file.h default)

/// A scene with one unit, a wall: its inner box centred on (wallX + 0.1, 0, 1), 0.2 m thick along
/// x, 20 m long along y, 2 m tall; with one instance, a single triangle of the wall's face x = wallX.
Scene wallScene(double wallX) {
  Scene s;
  s.spec.viewer.eyeHeight = kEyeHeight;
  Obb<double> wall;
  wall.center = Vec3<double>(wallX + 0.1, 0, 1);
  wall.halfExtents = Vec3<double>(0.1, 10, 1);
  CollisionUnit u;
  u.name = "wall";
  u.group = "site/wall";
  u.kind = "barrier";
  u.volume = NestedVolume<double>::fromObb(wall);
  u.instances = {0};
  s.units.push_back(u);
  SceneModel m;
  m.mesh.vertices = {{wallX, -10, 0}, {wallX, 10, 0}, {wallX, 0, 2}};
  m.mesh.triangles = {{0, 1, 2}};
  s.models.push_back(m);
  SceneInstance inst;
  inst.model = 0;
  s.instances.push_back(inst);  // identity transform: model frame = local frame (origin 0)
  return s;
}

/// Records walking from (0, 0) at `headingDeg` (degrees from +y, clockwise) in 0.1 m steps, the
/// last `blockedSteps` of them blocked by `by` without moving.
std::vector<FrameRecord> walk(double headingDeg, int steps, int blockedSteps, const std::string& by) {
  std::vector<FrameRecord> out;
  const double h = headingDeg * std::numbers::pi / 180.0;
  Eigen::Vector3d eye(0, 0, kEyeHeight);
  for (int k = 0; k < steps + blockedSteps; ++k) {
    FrameRecord r;
    r.frame = std::uint64_t(k + 1);
    r.time = (k + 1) / 60.0;
    if (k < steps) eye += 0.1 * Eigen::Vector3d(std::sin(h), std::cos(h), 0);
    r.eye = eye;
    r.headingDeg = r.bodyYawDeg = headingDeg;
    r.blocked = k >= steps;
    if (r.blocked) r.blockedBy = by;
    out.push_back(r);
  }
  return out;
}

TEST(RunContacts, ApproachAngleIsTheWayInAgainstTheFaceNormal) {
  const Scene scene = wallScene(5.0);
  for (const double angle : {0.0, 30.0, 89.0}) {  // from the wall's normal (+x, heading 90)
    const auto records = walk(90.0 - angle, 30, 5, "wall");
    const std::vector<RunContact> c = runContacts(scene, records);
    ASSERT_EQ(c.size(), 1u) << angle;
    EXPECT_EQ(c[0].frame, 31u);
    EXPECT_EQ(c[0].unit, "wall");
    EXPECT_EQ(c[0].kind, "barrier");
    EXPECT_EQ(c[0].group, "site/wall");
    EXPECT_NEAR(c[0].approachDeg, angle, 1e-9) << angle;
  }
}

TEST(RunContacts, StopGapIsTheExactDistanceToTheTriangles) {
  const Scene scene = wallScene(5.0);
  // Head-on: the body (0.25 m half length, turned to heading 90: +x) stops with its front at
  // 0.1 * 30 + 0.25 = 3.25, the wall's face at x = 5.
  const auto records = walk(90.0, 30, 3, "wall");
  const std::vector<RunContact> c = runContacts(scene, records);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].stopGapM, 5.0 - (3.0 + 0.25), 1e-9);
}

TEST(RunContacts, OneEventPerRunOfOneBlockerAndTheTerrainHasNoAngleOrGap) {
  const Scene scene = wallScene(5.0);
  auto records = walk(90.0, 10, 6, "wall");
  records[12].blockedBy = "terrain:slope";  // wall, wall, slope, wall, wall, wall: three events
  const std::vector<RunContact> c = runContacts(scene, records);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[0].frame, 11u);
  EXPECT_EQ(c[1].unit, "terrain:slope");
  EXPECT_EQ(c[1].kind, "terrain");
  EXPECT_TRUE(std::isnan(c[1].approachDeg));
  EXPECT_TRUE(std::isnan(c[1].stopGapM));
  EXPECT_EQ(c[2].frame, 14u);
  EXPECT_EQ(c[2].unit, "wall");
}

}  // namespace
}  // namespace nestwalk
