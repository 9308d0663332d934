// The walker on a small synthetic terrain (a flat toe, a 35-degree bench face up 10 m, a 10 %
// haul ramp cut into it) with boxes as equipment, at the origin and at UTM magnitudes. Gaps are
// checked against FCL's box-box distance (an independent GJK) and the static SAT.
#include "nestwalk/core/angles.h"
#include "nestwalk/terrain/height_tiles.h"
#include "nestwalk/walker/walker.h"

#include <fcl/narrowphase/distance.h>
#include <fcl/geometry/shape/box.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>
#include <memory>
#include <random>
#include <thread>

namespace nestwalk {
namespace {


/// Toe at z = 0 south of y = 100, a 35-degree face up to the 10 m bench, and a 10 % ramp for
/// 20 <= x <= 30 from y = 60 to y = 160. Sample (c, r) sits at map (x0 + c, y0 + 200 - r).
std::shared_ptr<terrain::Heightfield> benchTerrain(double x0, double y0) {
  const int n = 201;
  std::vector<float> h(std::size_t(n) * n);
  const double tan35 = std::tan(radians(35.0));
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      const double x = c, y = 200 - r;
      double z = std::clamp((y - 100.0) * tan35, 0.0, 10.0);
      if (x >= 20 && x <= 30) z = std::clamp((y - 60.0) * 0.1, 0.0, 10.0);
      h[std::size_t(r) * n + std::size_t(c)] = float(z);
    }
  return std::make_shared<terrain::Heightfield>(n, n, std::move(h), x0, y0 + 200.0, 1.0, 1.0);
}

struct Rig {
  Eigen::Vector3d origin;
  std::shared_ptr<terrain::Heightfield> hf;
  std::unique_ptr<CollisionWorld> world;
  std::unique_ptr<Walker> walker;
};

/// Units given in map coordinates; the local frame's origin is the terrain's corner.
Rig makeRig(double x0, double y0, const std::vector<Obb<double>>& mapBoxes, WalkerOptions opts = {},
            MethodSpec method = {}) {
  Rig rig;
  rig.origin = Eigen::Vector3d(x0, y0, 0);
  rig.hf = benchTerrain(x0, y0);
  std::vector<NestedVolume<double>> units;
  std::vector<std::string> names, groups;
  for (std::size_t i = 0; i < mapBoxes.size(); ++i) {
    Obb<double> b = mapBoxes[i];
    b.center -= rig.origin;
    units.push_back(NestedVolume<double>::fromObb(b));
    names.push_back("unit" + std::to_string(i));
    groups.push_back("g" + std::to_string(i % 3));
  }
  rig.world = std::make_unique<CollisionWorld>(units, names, groups, method);
  rig.walker = std::make_unique<Walker>(*rig.hf, *rig.world, rig.origin, opts);
  return rig;
}

Obb<double> uprightBox(double x, double y, double z0, double hx, double hy, double hz, double yawDeg = 0) {
  Obb<double> b;
  b.center = Vec3<double>(x, y, z0 + hz);
  b.axes = Eigen::AngleAxisd(-radians(yawDeg), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  b.halfExtents = Vec3<double>(hx, hy, hz);
  return b;
}

/// Walks toward a target at a speed until it arrives or stops making progress.
void walkTo(Walker& w, const Eigen::Vector2d& target, double speed, int maxSteps = 100000) {
  for (int i = 0; i < maxSteps; ++i) {
    const Eigen::Vector2d d = target - w.state().feet.head<2>();
    const double dist = d.norm();
    if (dist < 1e-9) return;
    const double len = std::min(dist, speed * w.options().dt);
    StepInput in;
    in.move = Eigen::Vector3d(d.x(), d.y(), 0) * (len / dist);
    in.headingDeg = w.state().headingDeg;
    const Eigen::Vector3d before = w.state().feet;
    w.step(in);
    if ((w.state().feet - before).norm() < 1e-9 && w.state().blocked) return;
  }
}

/// FCL's distance between two OBBs (independent of our SAT).
double fclDistance(const Obb<double>& a, const Obb<double>& b) {
  auto box = [](const Obb<double>& o) {
    fcl::Transform3d tf = fcl::Transform3d::Identity();
    tf.linear() = o.axes;
    tf.translation() = o.center;
    return std::make_pair(fcl::Boxd(2 * o.halfExtents.x(), 2 * o.halfExtents.y(), 2 * o.halfExtents.z()), tf);
  };
  const auto [ga, ta] = box(a);
  const auto [gb, tb] = box(b);
  fcl::DistanceRequestd req;
  req.enable_nearest_points = false;
  fcl::DistanceResultd res;
  return fcl::distance(&ga, ta, &gb, tb, req, res);
}

class WalkerAt : public ::testing::TestWithParam<Eigen::Vector2d> {};

TEST_P(WalkerAt, StopsWithinAMillimetreOfRotatedBoxesAndNeverInside) {
  const double x0 = GetParam().x(), y0 = GetParam().y();
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> yaw(0, 360), ext(0.02, 1.5), ang(0, 2 * std::numbers::pi), spd(0.5, 50.0);
  int blocked = 0;
  double worstGap = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Obb<double> box = uprightBox(x0 + 100, y0 + 50, 0, ext(rng), ext(rng), 1.0, yaw(rng));
    Rig rig = makeRig(x0, y0, {box});
    const double a = ang(rng);
    const Eigen::Vector2d dir(std::cos(a), std::sin(a));
    const Eigen::Vector2d start = Eigen::Vector2d(x0 + 100, y0 + 50) - 6.0 * dir;
    ASSERT_EQ(rig.walker->place(Eigen::Vector3d(start.x(), start.y(), 0), false, yaw(rng), false, 2.0), "");
    walkTo(*rig.walker, start + 12.0 * dir, spd(rng));
    const WalkerState& s = rig.walker->state();
    ASSERT_TRUE(s.blocked) << trial;
    ASSERT_EQ(s.reason, BlockReason::Equipment);
    ++blocked;
    const NestedVolume<double> body = rig.walker->bodyVolume(s.feet, s.bodyYawDeg);
    Obb<double> local = box;
    local.center -= rig.origin;
    EXPECT_FALSE(satObbObb(body.inner, local).overlap) << "inside at trial " << trial;
    const double gap = fclDistance(body.inner, local);
    EXPECT_LE(gap, 1e-3 + 1e-6) << trial;
    worstGap = std::max(worstGap, gap);
  }
  EXPECT_EQ(blocked, 200);
  RecordProperty("worst_gap_m", std::to_string(worstGap));
}

TEST_P(WalkerAt, NeverPassesAFiveCentimetrePoleAtAnySpeedUpTo50MetresPerSecond) {
  const double x0 = GetParam().x(), y0 = GetParam().y();
  const Obb<double> pole = uprightBox(x0 + 100, y0 + 50, 0, 0.025, 0.025, 1.5);
  for (double speed : {0.5, 1.4, 5.0, 13.0, 27.0, 50.0}) {
    for (double lateral : {-0.27, -0.2, 0.0, 0.13, 0.2749}) {
      Rig rig = makeRig(x0, y0, {pole});
      ASSERT_EQ(rig.walker->place(Eigen::Vector3d(x0 + 100 + lateral, y0 + 40, 0), false, 0, false, 2.0), "");
      walkTo(*rig.walker, Eigen::Vector2d(x0 + 100 + lateral, y0 + 60), speed);
      const WalkerState& s = rig.walker->state();
      EXPECT_TRUE(s.blocked) << speed << " " << lateral;
      const double frontY = s.feet.y() + 0.25;
      EXPECT_LE(frontY, y0 + 50 - 0.025) << "past the pole's face at " << speed << " m/s";
      EXPECT_GE(frontY, y0 + 50 - 0.025 - 1e-3) << "stopped more than 1 mm short at " << speed << " m/s";
    }
  }
}

TEST_P(WalkerAt, BenchFaceBlocksAndTheRampDoesNot) {
  const double x0 = GetParam().x(), y0 = GetParam().y();
  {
    Rig rig = makeRig(x0, y0, {});
    ASSERT_EQ(rig.walker->place(Eigen::Vector3d(x0 + 60, y0 + 90, 0), false, 0, false, 2.0), "");
    walkTo(*rig.walker, Eigen::Vector2d(x0 + 60, y0 + 150), 1.4);
    const WalkerState& s = rig.walker->state();
    EXPECT_TRUE(s.blocked);
    EXPECT_TRUE(s.reason == BlockReason::TerrainSlope || s.reason == BlockReason::TerrainStep);
    EXPECT_LT(s.feet.y(), y0 + 101.0);
    EXPECT_LT(s.feet.z(), 1.0);
  }
  {
    Rig rig = makeRig(x0, y0, {});
    ASSERT_EQ(rig.walker->place(Eigen::Vector3d(x0 + 25, y0 + 40, 0), false, 0, false, 2.0), "");
    walkTo(*rig.walker, Eigen::Vector2d(x0 + 25, y0 + 180), 1.4);
    const WalkerState& s = rig.walker->state();
    EXPECT_FALSE(s.blocked);
    EXPECT_NEAR(s.feet.y(), y0 + 180, 1e-9);
    EXPECT_NEAR(s.feet.z(), 10.0, 1e-6);
  }
}

TEST_P(WalkerAt, FeetFollowTheTerrainQueryExactly) {
  const double x0 = GetParam().x(), y0 = GetParam().y();
  Rig rig = makeRig(x0, y0, {});
  ASSERT_EQ(rig.walker->place(Eigen::Vector3d(x0 + 25.3, y0 + 30.7, 0), false, 0, false, 2.0), "");
  for (int i = 0; i < 4000; ++i) {
    StepInput in;
    in.move = Eigen::Vector3d(0.001 * std::sin(i * 0.01), 1.4 / 60.0, 0);
    rig.walker->step(in);
    const WalkerState& s = rig.walker->state();
    const std::optional<double> g = rig.hf->groundHeight(s.feet.x(), s.feet.y());
    ASSERT_TRUE(g.has_value());
    ASSERT_EQ(s.feet.z(), *g) << i;
    ASSERT_EQ(s.ground, *g);
  }
}

TEST_P(WalkerAt, SlidesAlongAWallWhenAskedAndStopsOtherwise) {
  const double x0 = GetParam().x(), y0 = GetParam().y();
  const Obb<double> wall = uprightBox(x0 + 100, y0 + 50, 0, 10.0, 0.1, 1.0);
  for (bool slide : {false, true}) {
    WalkerOptions opts;
    opts.slide = slide;
    Rig rig = makeRig(x0, y0, {wall}, opts);
    ASSERT_EQ(rig.walker->place(Eigen::Vector3d(x0 + 95, y0 + 45, 0), false, 45, false, 2.0), "");
    for (int i = 0; i < 600; ++i) {
      StepInput in;
      in.move = Eigen::Vector3d(1, 1, 0).normalized() * (1.4 / 60.0);
      in.headingDeg = 45;
      rig.walker->step(in);
    }
    const WalkerState& s = rig.walker->state();
    const NestedVolume<double> body = rig.walker->bodyVolume(s.feet, s.bodyYawDeg);
    Obb<double> local = wall;
    local.center -= rig.origin;
    EXPECT_FALSE(satObbObb(body.inner, local).overlap);
    EXPECT_LE(fclDistance(body.inner, local), 1e-3 + 1e-6);
    if (slide) {
      EXPECT_GT(s.feet.x(), x0 + 100);  // went on east along the wall
    } else {
      EXPECT_LT(s.feet.x(), x0 + 100);
    }
  }
}

TEST_P(WalkerAt, StaysBlockedUntilTheDirectionLeadsAway) {
  const double x0 = GetParam().x(), y0 = GetParam().y();
  Rig rig = makeRig(x0, y0, {uprightBox(x0 + 100, y0 + 50, 0, 1.0, 1.0, 1.0)});
  ASSERT_EQ(rig.walker->place(Eigen::Vector3d(x0 + 100, y0 + 45, 0), false, 0, false, 2.0), "");
  walkTo(*rig.walker, Eigen::Vector2d(x0 + 100, y0 + 55), 1.4);
  const Eigen::Vector3d stop = rig.walker->state().feet;
  for (int i = 0; i < 30; ++i) {
    StepInput in;
    in.move = Eigen::Vector3d(0, 1.4 / 60, 0);
    rig.walker->step(in);
    EXPECT_TRUE(rig.walker->state().blocked);
    EXPECT_EQ(rig.walker->state().feet, stop);
  }
  StepInput away;
  away.move = Eigen::Vector3d(-1.4 / 60, 0, 0);  // along the face: free
  away.headingDeg = 270;
  rig.walker->step(away);
  EXPECT_FALSE(rig.walker->state().blocked);
  EXPECT_LT(rig.walker->state().feet.x(), stop.x());
}

TEST_P(WalkerAt, FlyingKeepsItsClearanceAndIsBlockedByEquipment) {
  const double x0 = GetParam().x(), y0 = GetParam().y();
  Rig rig = makeRig(x0, y0, {uprightBox(x0 + 60, y0 + 150, 10.0, 2.0, 2.0, 8.0)});
  ASSERT_EQ(rig.walker->place(Eigen::Vector3d(x0 + 60, y0 + 50, 0), false, 0, true, 5.0), "");
  EXPECT_NEAR(rig.walker->state().feet.z(), 5.0, 1e-9);
  for (int i = 0; i < 600; ++i) {
    StepInput in;
    in.move = Eigen::Vector3d(0, 30.0 / 60, 0);
    rig.walker->step(in);
    const WalkerState& s = rig.walker->state();
    const std::optional<double> g = rig.hf->groundHeight(s.feet.x(), s.feet.y());
    ASSERT_TRUE(g);
    ASSERT_GE(s.feet.z() - *g, 5.0 - 1e-9);
  }
  EXPECT_TRUE(rig.walker->state().blocked);
  EXPECT_EQ(rig.walker->state().reason, BlockReason::Equipment);
  EXPECT_LT(rig.walker->state().feet.y(), y0 + 148.0);
}

INSTANTIATE_TEST_SUITE_P(Frames, WalkerAt,
                         ::testing::Values(Eigen::Vector2d(0, 0), Eigen::Vector2d(550000.0, 4650000.0)),
                         [](const auto& info) { return info.param.x() == 0 ? std::string("Origin") : std::string("Utm"); });

TEST(Walker, SameInputsGiveTheSameStatesBitForBit) {
  auto run = [] {
    Rig rig = makeRig(550000, 4650000, {uprightBox(550100, 4650050, 0, 0.5, 0.3, 1.0, 30)});
    rig.walker->place(Eigen::Vector3d(550090, 4650040, 0), false, 45, false, 2.0);
    std::vector<Eigen::Vector3d> path;
    for (int i = 0; i < 2000; ++i) {
      StepInput in;
      in.move = Eigen::Vector3d(std::cos(i * 0.003), std::sin(i * 0.002) + 0.5, 0) * (3.0 / 60);
      in.headingDeg = std::fmod(45 + i * 0.1, 360.0);
      rig.walker->step(in);
      path.push_back(rig.walker->state().feet);
    }
    return path;
  };
  EXPECT_EQ(run(), run());
}

TEST(Walker, PlacedOnAPagedTerrainItHoldsTheGroundAroundItsFeetSoItsFirstStepsNeverWait) {
  // A 5 cm grid of 4 x 4 tiles (12.8 m a side each) whose reads take 5 ms, far longer than a step:
  // a tile only prefetched when the walk starts would be waited for. Placed at the corner of four
  // tiles, its footprint within one, the walker holds all four (every tile within
  // kPrefetchMarginMetres) at once, and its first steps, across the corner into the others, wait
  // for none.
  const int T = terrain::kHeightTileCells, n = 4 * T + 1;
  const double cell = 0.05, x0 = 512345.0, y0 = 7765432.0;
  auto tiles = std::make_shared<const terrain::HeightTileCache>(
      n, n, std::nullopt,
      [](int c0, int r0, int w, int h) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        std::vector<float> heights(std::size_t(w) * std::size_t(h));
        for (int r = 0; r < h; ++r)
          for (int c = 0; c < w; ++c) heights[std::size_t(r) * std::size_t(w) + std::size_t(c)] = float(10 + 0.01 * (c0 + c) + 0.02 * (r0 + r));
        return heights;
      },
      std::vector<float>{});
  const terrain::Heightfield hf(n, n, tiles, std::pair<float, float>{10.0f, float(10 + 0.03 * n)}, x0,
                               y0 + (n - 1) * cell, cell, cell);
  const CollisionWorld world({}, {}, {}, MethodSpec{});
  WalkerOptions opts;
  Walker w(hf, world, Eigen::Vector3d(x0, y0, 0), opts);
  const Eigen::Vector2d corner = hf.samplePosition(2 * T, 2 * T);
  ASSERT_EQ(w.place(Eigen::Vector3d(corner.x() + 0.6, corner.y() - 0.6, 0), false, 0, false, 0), "");
  const auto near = hf.tilesUnder(corner.x() - kPrefetchMarginMetres, corner.y() - kPrefetchMarginMetres,
                                  corner.x() + kPrefetchMarginMetres, corner.y() + kPrefetchMarginMetres);
  ASSERT_TRUE(near);
  EXPECT_EQ(*near, (std::array<int, 4>{1, 1, 2, 2}));
  for (int ty = (*near)[1]; ty <= (*near)[3]; ++ty)
    for (int tx = (*near)[0]; tx <= (*near)[2]; ++tx) EXPECT_TRUE(tiles->holds(tx, ty)) << tx << "," << ty;
  for (int k = 0; k < 8; ++k) {
    StepInput in;
    in.move = Eigen::Vector3d(-0.15, k < 5 ? 0.15 : 0.0, 0);  // north-west across the corner, then west
    in.headingDeg = w.state().bodyYawDeg;
    EXPECT_EQ(w.step(in).groundWaits, 0u) << "step " << k;
    EXPECT_FALSE(w.state().blocked) << "step " << k;
  }
  EXPECT_LT(w.state().feet.x(), corner.x());  // it crossed into tiles (1, 1) and (1, 2)
  EXPECT_GT(w.state().feet.y(), corner.y());
}

TEST(Walker, FlyingLegsAnswerAsSamplingEveryFootprintPointToTheBit) {
  // A rough 5 cm grid (40 m a side) at UTM magnitudes with a patch of holes, flown over at 30 m/s
  // (0.5 m a step: 20 samples of the footprint's 5 points), climbing, sinking and turning, with the
  // clearance changed now and then. Reference: the leg as walker.h states it, every footprint point
  // sampled at every sample, computed here; the walker skips the points whose ground cannot lift
  // the body (Heightfield::groundCeiling), and must end every step on the same feet to the bit.
  const int n = 801;
  const double cell = 0.05, x0 = 512345.0, y0 = 7765432.0;
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> rough(-0.05, 0.05);
  std::vector<float> h(std::size_t(n) * n);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      const bool hole = c >= 380 && c <= 420 && r >= 380 && r <= 420;
      h[std::size_t(r) * n + std::size_t(c)] = hole ? std::numeric_limits<float>::quiet_NaN()
                                                    : float(10 + 2 * std::sin(0.02 * c) * std::cos(0.015 * r) + rough(rng));
    }
  const terrain::Heightfield hf(n, n, std::move(h), x0, y0 + (n - 1) * cell, cell, cell);
  const CollisionWorld world({}, {}, {}, MethodSpec{});
  WalkerOptions opts;
  opts.viewer.bodyHalfExtents = {0.25, 0.35, 0.9};
  Walker w(hf, world, Eigen::Vector3d(x0, y0, 0), opts);
  ASSERT_EQ(w.place(Eigen::Vector3d(x0 + 5, y0 + 5, 0), false, 30, true, 0.5), "");

  const double spacing = kGroundSampleSpacing * cell;
  auto reference = [&](const Eigen::Vector3d& start, const Eigen::Vector3d& move, double yawDeg, double clearance,
                       bool& edge) {
    const Eigen::Vector2d fw(std::sin(radians(yawDeg)), std::cos(radians(yawDeg)));
    const Eigen::Vector2d f = fw * opts.viewer.bodyHalfExtents.x(),
                          sd = Eigen::Vector2d(-fw.y(), fw.x()) * opts.viewer.bodyHalfExtents.y();
    auto highest = [&](const Eigen::Vector3d& p) -> std::optional<double> {
      const Eigen::Vector2d c(p.x(), p.y());
      const Eigen::Vector2d pts[5] = {c, c + f + sd, c + f - sd, c - f + sd, c - f - sd};
      double top = -std::numeric_limits<double>::infinity();
      for (const Eigen::Vector2d& q : pts) {
        const std::optional<double> g = hf.groundHeight(q.x(), q.y());
        if (!g) return std::nullopt;
        top = std::max(top, *g);
      }
      return top;
    };
    const double len = move.head<2>().norm();
    const int samples = len > 0 ? std::max(1, int(std::ceil(len / spacing))) : 0;
    double lowest = -std::numeric_limits<double>::infinity();
    int good = 0;
    edge = false;
    for (int k = 1; k <= samples; ++k) {
      const std::optional<double> top = highest(start + move * (double(k) / samples));
      if (!top) {
        edge = true;
        break;
      }
      lowest = std::max(lowest, *top + clearance);
      good = k;
    }
    Eigen::Vector3d target = samples == 0 ? Eigen::Vector3d(start + move)
                                          : Eigen::Vector3d(start + move * (double(good) / samples));
    if (samples == 0)
      if (const auto top = highest(target)) lowest = *top + clearance;
    target.z() = std::max(target.z(), lowest);
    return target;
  };

  std::uniform_real_distribution<double> turn(-0.3, 0.3), rise(-0.4, 0.25), unit(0, 1);
  double direction = 0.7, clearance = 0.5;
  int lifted = 0, kept = 0, edges = 0;
  for (int i = 0; i < 6000; ++i) {
    if (i % 250 == 0) {
      clearance = 0.2 + 3.0 * unit(rng);
      w.setFlying(true, clearance);
    }
    direction += turn(rng);
    StepInput in;
    in.move = Eigen::Vector3d(std::sin(direction), std::cos(direction), rise(rng)) * 0.5;
    if (i % 7 == 0) in.move.head<2>() *= unit(rng);  // shorter legs, some of one sample
    in.headingDeg = i % 50 < 25 ? w.state().bodyYawDeg : std::fmod(w.state().bodyYawDeg + 7.0, 360.0);
    const Eigen::Vector3d start = w.state().feet;
    w.step(in);
    bool edge = false;
    const Eigen::Vector3d expected = reference(start, in.move, w.state().bodyYawDeg, clearance, edge);
    const Eigen::Vector3d got = w.state().feet;
    ASSERT_TRUE(got.x() == expected.x() && got.y() == expected.y() && got.z() == expected.z())
        << "step " << i << ": " << got.transpose() << " vs " << expected.transpose();
    ASSERT_EQ(w.state().blocked, edge) << "step " << i;
    if (edge) {
      ++edges;
      direction += 3.0;  // turn away from the edge or the holes
    }
    (got.z() > start.z() + in.move.z() ? lifted : kept)++;
    // Keep over the grid: steer back toward its centre when near its edge.
    const Eigen::Vector2d toCentre = Eigen::Vector2d(x0 + 20, y0 + 20) - got.head<2>();
    if (toCentre.norm() > 17) direction = std::atan2(toCentre.x(), toCentre.y());
  }
  // Both kinds of step were flown: lifted by the ground (its points sampled) and not (skipped).
  EXPECT_GT(lifted, 500);
  EXPECT_GT(kept, 500);
  EXPECT_GT(edges, 5);
}

TEST(Walker, TheSameSceneAtUtmAndAtTheOriginGivesTheSameContactsAndHeights) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> px(40, 80), py(20, 60), ext(0.05, 1.0), yaw(0, 360);
  std::vector<Obb<double>> boxes0, boxes1;
  for (int i = 0; i < 60; ++i) {
    const double x = px(rng), y = py(rng), hx = ext(rng), hy = ext(rng), a = yaw(rng);
    boxes0.push_back(uprightBox(x, y, 0, hx, hy, 1.0, a));
    boxes1.push_back(uprightBox(550000 + x, 4650000 + y, 0, hx, hy, 1.0, a));
  }
  Rig r0 = makeRig(0, 0, boxes0), r1 = makeRig(550000, 4650000, boxes1);
  ASSERT_EQ(r0.walker->place(Eigen::Vector3d(35, 15, 0), false, 0, false, 2), "");
  ASSERT_EQ(r1.walker->place(Eigen::Vector3d(550035, 4650015, 0), false, 0, false, 2), "");
  int contacts = 0;
  Eigen::Vector2d waypoint(px(rng), py(rng));
  int blockedFor = 0;
  for (int i = 0; i < 20000; ++i) {
    // Inputs from the origin run's state; the UTM run must follow the same states.
    Eigen::Vector2d d = waypoint - r0.walker->state().feet.head<2>();
    if (d.norm() < 0.05 || blockedFor > 20) {
      waypoint = Eigen::Vector2d(px(rng), py(rng));
      d = waypoint - r0.walker->state().feet.head<2>();
      blockedFor = 0;
    }
    StepInput in;
    in.move = Eigen::Vector3d(d.x(), d.y(), 0).normalized() * (3.0 / 60);
    in.headingDeg = std::fmod(std::atan2(d.x(), d.y()) * 180.0 / std::numbers::pi + 360.0, 360.0);
    r0.walker->step(in);
    r1.walker->step(in);
    const WalkerState &a = r0.walker->state(), &b = r1.walker->state();
    ASSERT_EQ(a.blocked, b.blocked) << i;
    ASSERT_EQ(a.blockedUnit, b.blockedUnit) << i;
    contacts += a.blocked;
    blockedFor = a.blocked ? blockedFor + 1 : 0;
    ASSERT_NEAR(a.feet.x(), b.feet.x() - 550000, 1e-6) << i;
    ASSERT_NEAR(a.feet.y(), b.feet.y() - 4650000, 1e-6) << i;
    ASSERT_NEAR(a.feet.z(), b.feet.z(), 1e-6) << i;
  }
  EXPECT_GT(contacts, 10);
}

}  // namespace
}  // namespace nestwalk
