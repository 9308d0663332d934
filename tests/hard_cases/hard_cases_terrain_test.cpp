// Hard cases of the terrain (terrain/heightfield.h, dem_reader.h) and of the walker's ground
// following on it: grazing rays through grid vertices and along edges, nodata borders, the raster's
// edge, vertical bench faces, and the same terrain at UTM magnitudes and at the origin.
// References: the terrain is built from formulas (a pyramid whose triangulation is exact, planes,
// a step) on dyadic grids, so heights, contact points and ray parameters are exact rationals known
// in closed form; the ground rule of heightfield.h (a point has ground iff the samples of the
// smallest closed simplex holding it are valid) is implemented here on its own (GridRule) from the
// samples' validity and heights, and compared point by point.
#include "nestwalk/core/angles.h"
#include "nestwalk/walker/walker.h"
#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/terrain/heightfield.h"
#include "tests/hard_cases/hard_case_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <optional>
#include <random>
#include <vector>

namespace nestwalk {
namespace {

using terrain::Heightfield;
using hardcase::walkToward;

/// A grid given by formulas: where sample (c, r) is, whether it is valid and its height; ground() is
/// the documented rule evaluated from these alone: the point's barycentric weights in its triangle
/// (cell split from north-west to south-east); the samples with a nonzero weight must all be valid.
struct GridRule {
  int cols, rows;
  double x0, y0, dx, dy;  // map position of sample (0, 0), spacing east and south
  std::function<bool(int, int)> valid;
  std::function<double(int, int)> height;

  std::optional<double> ground(double x, double y) const {
    const double u = (x - x0) / dx, v = (y0 - y) / dy;
    if (!(u >= 0 && u <= cols - 1 && v >= 0 && v <= rows - 1)) return std::nullopt;
    const int c = std::min(int(u), cols - 2), r = std::min(int(v), rows - 2);
    const double fx = u - c, fy = v - r;
    std::array<std::pair<std::array<int, 2>, double>, 3> w;
    if (fx >= fy) w = {{{{c, r}, 1 - fx}, {{c + 1, r}, fx - fy}, {{c + 1, r + 1}, fy}}};
    else w = {{{{c, r}, 1 - fy}, {{c + 1, r + 1}, fx}, {{c, r + 1}, fy - fx}}};
    double z = 0;
    for (const auto& [s, weight] : w) {
      if (weight == 0) continue;
      if (!valid(s[0], s[1])) return std::nullopt;
      z += weight * height(s[0], s[1]);
    }
    return z;
  }
  Eigen::Vector2d at(double c, double r) const { return {x0 + c * dx, y0 - r * dy}; }
};

Heightfield heightfieldOf(const GridRule& g, std::optional<float> noData = std::nullopt) {
  std::vector<float> h(std::size_t(g.cols) * std::size_t(g.rows));
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c)
      h[std::size_t(r) * std::size_t(g.cols) + std::size_t(c)] = g.valid(c, r) ? float(g.height(c, r)) : noData.value_or(std::numeric_limits<float>::quiet_NaN());
  return Heightfield(g.cols, g.rows, std::move(h), g.x0, g.y0, g.dx, g.dy, noData);
}

/// Compares groundHeight with the rule on a lattice of 1/16 cell (every grid line, diagonal and
/// vertex hit exactly) reaching `margin` cells beyond the samples; returns the points compared.
int compareGroundWithRule(const Heightfield& hf, const GridRule& g, double margin, const char* what) {
  int n = 0, mismatches = 0;
  for (double c = -margin; c <= g.cols - 1 + margin; c += 1.0 / 16)
    for (double r = -margin; r <= g.rows - 1 + margin; r += 1.0 / 16) {
      const Eigen::Vector2d p = g.at(c, r);
      const std::optional<double> want = g.ground(p.x(), p.y()), got = hf.groundHeight(p.x(), p.y());
      ++n;
      if (want.has_value() != got.has_value() || (want && *want != *got)) {
        if (++mismatches <= 5)
          ADD_FAILURE() << what << ": ground at sample coordinates (" << c << ", " << r << ") is "
                        << (got ? std::to_string(*got) : "none") << ", the rule says "
                        << (want ? std::to_string(*want) : "none");
      }
    }
  EXPECT_EQ(mismatches, 0) << what;
  return n;
}

/// The walker on a terrain with no equipment.
struct GroundRig {
  CollisionWorld world{std::vector<NestedVolume<double>>{}, {}, {}, MethodSpec{}};
  std::unique_ptr<Walker> walker;
  GroundRig(const Heightfield& hf, const Eigen::Vector2d& localOrigin) {
    walker = std::make_unique<Walker>(hf, world, Eigen::Vector3d(localOrigin.x(), localOrigin.y(), 0), WalkerOptions{});
  }
};

/// The body footprint's centre and corners (centre, then +f+s, +f-s, -f+s, -f-s) for a heading.
std::array<Eigen::Vector2d, 5> footprint(const Eigen::Vector2d& c, double headingDeg, double hx, double hy) {
  const double a = radians(headingDeg);
  const Eigen::Vector2d f(std::sin(a), std::cos(a)), s(-f.y(), f.x());
  return {c, c + hx * f + hy * s, c + hx * f - hy * s, c - hx * f + hy * s, c - hx * f - hy * s};
}

// ------------------------------------------------------------------------------------------------
// Situation: grazing rays through grid vertices and edges. The pyramid h = 8 - |c - 4| - |r - 4| on a
// 9 x 9 grid with dx = 2, dy = 1 is planar on every cell (each cell lies in one quadrant), so the
// triangulated surface is z = 8 - |x - xp| / 2 - |y - yp| exactly. Rays aimed at a point P of the
// surface start at P - s dir (s dyadic, so the start is exact and t = s is the exact answer):
//  - tangent at the peak (a vertex of 8 triangles), horizontal, along a row line, a column line, a
//    cell diagonal and across the cells: the ray meets the surface at the peak only;
//  - tangent to the ridges (the row and column lines through the peak) at the middle of a grid edge,
//    descending more gently than the flank beyond: it touches at that edge point only;
//  - crossing exactly at a vertex along a row line, and at the middle of a cell diagonal along it.
// Every one must hit at P with t = s (the rays are interior: nothing here is measure-zero).
void checkGrazingRays(const Eigen::Vector2d& origin) {
  const GridRule g{9, 9, origin.x(), origin.y(), 2.0, 1.0, [](int, int) { return true; },
                   [](int c, int r) { return 8.0 - std::abs(c - 4) - std::abs(r - 4); }};
  const Heightfield hf = heightfieldOf(g);
  const Eigen::Vector2d peak = g.at(4, 4);
  auto surfaceAt = [&](const Eigen::Vector2d& p) {
    return 8.0 - std::abs(p.x() - peak.x()) / 2 - std::abs(p.y() - peak.y());
  };
  struct Ray {
    const char* name;
    Eigen::Vector2d at;  // sample coordinates (c, r) of P
    Eigen::Vector3d dir;
    double s;
  };
  const Ray rays[] = {
      {"peak, along the row line", {4, 4}, {1, 0, 0}, 3.0},
      {"peak, along the row line westward", {4, 4}, {-1, 0, 0}, 5.5},
      {"peak, along the column line", {4, 4}, {0, 1, 0}, 2.0},
      {"peak, along the NW-SE diagonal edges", {4, 4}, {2, -1, 0}, 1.5},
      {"peak, across the cells (NE-SW)", {4, 4}, {2, 1, 0}, 0.75},
      {"peak, straight down", {4, 4}, {0, 0, -1}, 10.0},
      {"row ridge, mid-edge, from the north", {2.5, 4}, {0, -1, -0.5}, 2.0},
      {"row ridge, mid-edge, from the south", {5.5, 4}, {0, 1, -0.25}, 1.0},
      {"column ridge, mid-edge, from the west", {4, 6.5}, {1, 0, -0.25}, 2.0},
      {"column ridge, mid-edge, from the east", {4, 1.5}, {-1, 0, -0.125}, 4.0},
      {"vertex crossed along a row line", {2, 4}, {2, 0, -4}, 1.0},
      {"vertex crossed along a column line", {6, 7}, {0, 1, -3}, 0.5},
      {"mid-diagonal crossed along the diagonal", {1.5, 1.5}, {2, -1, -3}, 1.0},
  };
  for (const Ray& ray : rays) {
    const Eigen::Vector2d p2 = g.at(ray.at.x(), ray.at.y());
    const Eigen::Vector3d p(p2.x(), p2.y(), surfaceAt(p2));
    const Eigen::Vector3d start = p - ray.s * ray.dir;
    ASSERT_EQ(start + ray.s * ray.dir, p) << ray.name << ": the start must be exact";
    // The ray stays on or above the surface before P (checked on the construction, in exact steps).
    for (double k = 0; k < ray.s; k += ray.s / 64) {
      const Eigen::Vector3d q = start + k * ray.dir;
      const Eigen::Vector2d local = (q.head<2>() - origin).cwiseQuotient(Eigen::Vector2d(2, -1));
      if (local.x() >= 0 && local.x() <= 8 && local.y() >= 0 && local.y() <= 8) {
        ASSERT_GT(q.z(), surfaceAt(q.head<2>())) << ray.name << ": the construction dips under the surface";
      }
    }
    const std::optional<terrain::RayHit> hit = hf.intersectRay(start, ray.dir);
    ASSERT_TRUE(hit) << ray.name << " slipped through (origin " << origin.transpose() << ")";
    EXPECT_NEAR(hit->t, ray.s, 1e-12) << ray.name;
    EXPECT_LE((hit->point - p).norm(), 1e-12 + 1e-15 * p.norm()) << ray.name;
    const std::optional<double> ground = hf.groundHeight(p.x(), p.y());
    ASSERT_TRUE(ground) << ray.name;
    EXPECT_EQ(*ground, p.z()) << ray.name << ": groundHeight at the contact";
  }
}

TEST(HardCase, GrazingRaysThroughGridVerticesAndEdges) {
  checkGrazingRays({0.0, 0.0});
  checkGrazingRays({550000.0, 4650000.0});
}

// ------------------------------------------------------------------------------------------------
// Situation: UTM magnitudes vs the origin. The pyramid above at the origin and at three map
// positions (dyadic, so that map - origin is exact for the lattice): groundHeight on a 1/16-cell
// lattice must equal the closed form bit for bit in every frame, and rays in random directions
// aimed at lattice points must give the same t (to 1e-12) and the same point shifted.
TEST(HardCase, UtmVsOrigin_TerrainQueries) {
  const Eigen::Vector2d frames[] = {{0, 0}, {550000, 4650000}, {323476.0625, 5105081.9375}, {-799999.75, 7999999.5}};
  auto pyramid = [](const Eigen::Vector2d& o) {
    return GridRule{9, 9, o.x(), o.y(), 2.0, 1.0, [](int, int) { return true; },
                    [](int c, int r) { return 8.0 - std::abs(c - 4) - std::abs(r - 4); }};
  };
  const GridRule g0 = pyramid(frames[0]);
  const Heightfield h0 = heightfieldOf(g0);
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> U(-1, 1);
  for (const Eigen::Vector2d& o : frames) {
    const GridRule g = pyramid(o);
    const Heightfield hf = heightfieldOf(g);
    compareGroundWithRule(hf, g, 0.5, "pyramid");
    for (int k = 0; k < 2000; ++k) {
      const double c = std::floor((4 + 3.5 * U(rng)) * 16) / 16, r = std::floor((4 + 3.5 * U(rng)) * 16) / 16;
      const Eigen::Vector2d p0 = g0.at(c, r), p = g.at(c, r);
      const Eigen::Vector3d d(U(rng), U(rng), -2.0 - std::abs(U(rng)));  // steeper than every flank
      const double s = 1.5;
      const auto a = h0.intersectRay(Eigen::Vector3d(p0.x(), p0.y(), *g0.ground(p0.x(), p0.y())) - s * d, d);
      const auto b = hf.intersectRay(Eigen::Vector3d(p.x(), p.y(), *g.ground(p.x(), p.y())) - s * d, d);
      ASSERT_TRUE(a && b) << k;
      // Starting points round to the map grid (ulp 1e-9 m at 8e6 m), which moves t by as much.
      EXPECT_NEAR(b->t, a->t, o.isZero() ? 1e-12 : 2e-9) << k;
      EXPECT_NEAR(a->t, s, 1e-12) << k;
      EXPECT_LE((b->point - Eigen::Vector3d(o.x(), o.y(), 0) - a->point).norm(), 5e-9) << k;
    }
  }
}

/// The nodata-border terrain of the two cases below (see the first): written with GDAL at `corner`
/// (the raster's outer north-west corner), read back with readDem; the rule of its samples.
std::pair<Heightfield, GridRule> holeyTerrain(const hardcase::ScratchFolder& dir, const Eigen::Vector2d& corner) {
  auto valid = [](int c, int r) { return c >= 2 && r >= 1 && r <= 10 && c - r <= 9; };
  auto plane = [](int c, int r) { return 10.0 + c / 16.0 - r / 32.0; };
  hardcase::writeGeoTiff(dir / "holes.tif", 16, 12, corner.x(), corner.y(), 0.5,
                         [&](int c, int r) { return valid(c, r) ? plane(c, r) : -9999.0; }, -9999.0);
  return {terrain::readDem((dir / "holes.tif").string()), GridRule{16, 12, corner.x() + 0.25, corner.y() - 0.25, 0.5, 0.5, valid, plane}};
}

// ------------------------------------------------------------------------------------------------
// Situation: nodata borders. A GeoTIFF (read through readDem, the engine's reader) of 16 x 12
// samples of 0.5 m holding the plane z = 10 + c / 16 - r / 32 (exact in float), with nodata -9999 on
// a border 2 samples wide in the west and 1 in the north and south, and beyond the diagonal
// staircase c - r > 9 in the north-east, which runs exactly along cell diagonals: there the cells
// keep their lower triangle and lose the upper one. Exact answers: the rule (GridRule) from the
// validity pattern, on a lattice of 1/16 cell; rays across the border; the walker walking into the
// west border and into the staircase stops with every footprint sample on ground (by the rule)
// and its feet at the plane's height exactly.
TEST(HardCase, NodataBorders) {
  for (const Eigen::Vector2d& corner : {Eigen::Vector2d(0, 0), Eigen::Vector2d(550000, 4650006)}) {
    hardcase::ScratchFolder dir;
    const auto [hf, g] = holeyTerrain(dir, corner);
    ASSERT_EQ(hf.origin(), Eigen::Vector2d(g.x0, g.y0)) << "sample centres are half a pixel in";
    for (int r = 0; r < 12; ++r)
      for (int c = 0; c < 16; ++c) ASSERT_EQ(hf.valid(c, r), g.valid(c, r)) << c << "," << r;
    compareGroundWithRule(hf, g, 1.0, "nodata borders");

    // Spot checks named by hand: on the west border line, one ulp west of it, on a staircase diagonal
    // and 2^-20 cell either side of it.
    const Eigen::Vector2d west = g.at(2, 4.25);
    EXPECT_EQ(hf.groundHeight(west.x(), west.y()).value_or(-1), 10.0 + 2 / 16.0 - 4.25 / 32.0);
    EXPECT_FALSE(hf.groundHeight(std::nextafter(west.x(), -1e300), west.y()));
    const Eigen::Vector2d diag = g.at(12.5, 3.5), below = g.at(12.5, 3.5 + 0x1p-20), above = g.at(12.5 + 0x1p-20, 3.5);
    EXPECT_EQ(hf.groundHeight(diag.x(), diag.y()).value_or(-1), 10.0 + 12.5 / 16.0 - 3.5 / 32.0);
    EXPECT_TRUE(hf.groundHeight(below.x(), below.y()));
    EXPECT_FALSE(hf.groundHeight(above.x(), above.y()));

    // Rays: straight down into the holes: none; a horizontal ray from the west over the hole border,
    // 1/8 m above the plane's height at the border line, meets the plane 1 m inside (the plane rises
    // 1/8 m per metre eastward); a ray down through the upper (missing) half of a staircase cell
    // hits nothing there (and nothing below it).
    EXPECT_FALSE(hf.intersectRay({g.at(0.5, 5).x(), g.at(0.5, 5).y(), 50}, {0, 0, -1}));
    const Eigen::Vector2d w5 = g.at(2, 5);
    const double z = 10.0 + 2 / 16.0 - 5 / 32.0 + 0.125;
    const auto hit = hf.intersectRay({w5.x() - 1.0, w5.y(), z}, {1, 0, 0});
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->t, 2.0, 1e-12);
    EXPECT_FALSE(hf.intersectRay({above.x(), above.y(), 50}, {0, 0, -1}));

    // The walker into the west border, and (from the same start, placed afresh) north-east into the
    // staircase.
    const Eigen::Vector2d start = g.at(8, 6);
    for (const auto& [target, heading] : {std::pair{g.at(-4, 6), 270.0}, std::pair{g.at(20, 0), 63.43494882292201}}) {
      GroundRig rig(hf, hf.origin());
      ASSERT_EQ(rig.walker->place({start.x(), start.y(), 0}, false, heading, false, 2.0), "");
      const ViewerSpec& v = rig.walker->options().viewer;
      walkToward(*rig.walker, target, 1.4, heading);
      const WalkerState& s = rig.walker->state();
      EXPECT_TRUE(s.blocked);
      EXPECT_EQ(s.reason, BlockReason::TerrainEdge);
      for (const Eigen::Vector2d& q : footprint(s.feet.head<2>(), s.bodyYawDeg, v.bodyHalfExtents.x(), v.bodyHalfExtents.y()))
        EXPECT_TRUE(g.ground(q.x(), q.y())) << "a footprint sample without ground at " << q.transpose();
      const std::optional<double> zf = g.ground(s.feet.x(), s.feet.y());
      ASSERT_TRUE(zf);
      EXPECT_NEAR(s.feet.z(), *zf, 1e-12) << "feet off the plane";
      // Stopped close to the border: a quarter metre further the footprint would leave the ground.
      const Eigen::Vector2d ahead = s.feet.head<2>() + 0.25 * (target - s.feet.head<2>()).normalized();
      bool allGround = true;
      for (const Eigen::Vector2d& q : footprint(ahead, s.bodyYawDeg, v.bodyHalfExtents.x(), v.bodyHalfExtents.y()))
        allGround = allGround && g.ground(q.x(), q.y()).has_value();
      EXPECT_FALSE(allGround) << "stopped more than a quarter metre short of the border";
    }
  }
}

// Situation: nodata borders, turning there. The walker stopped at the west border of the terrain
// above (footprint 2 cm from it, facing west) turns toward the north-east and walks away from the
// border. The footprint turned by 63.4 degrees reaches 0.25 (sin + cos) = 0.335 m west of the
// centre, 6.5 cm over the holes. Expected (the documented walker: "a sample with no ground blocks
// like a wall", and a viewer must be placed with its whole footprint on ground): either the body
// keeps its yaw until the turned footprint has ground (as it does for equipment), or a walk leading
// away from the border is not blocked; in both cases every footprint sample keeps its ground (rule).
TEST(HardCase, NodataBorders_TurningAtTheBorderThenWalkingAway) {
  hardcase::ScratchFolder dir;
  const auto [hf, g] = holeyTerrain(dir, {0.0, 0.0});
  GroundRig rig(hf, hf.origin());
  const Eigen::Vector2d start = g.at(8, 6);
  ASSERT_EQ(rig.walker->place({start.x(), start.y(), 0}, false, 270, false, 2.0), "");
  walkToward(*rig.walker, g.at(-4, 6), 1.4, 270);
  ASSERT_EQ(rig.walker->state().reason, BlockReason::TerrainEdge);
  const Eigen::Vector3d stop = rig.walker->state().feet;
  walkToward(*rig.walker, g.at(20, 0), 1.4, 63.43494882292201, {}, 120);
  const WalkerState& s = rig.walker->state();
  const ViewerSpec& v = rig.walker->options().viewer;
  int off = 0;
  for (const Eigen::Vector2d& q : footprint(s.feet.head<2>(), s.bodyYawDeg, v.bodyHalfExtents.x(), v.bodyHalfExtents.y()))
    off += !g.ground(q.x(), q.y()).has_value();
  std::printf("  after the turn: body yaw %.2f, moved %.4f m, blocked %d (%s), footprint samples without ground %d\n",
              s.bodyYawDeg, (s.feet - stop).norm(), s.blocked, blockReasonName(s.reason), off);
  EXPECT_EQ(off, 0) << "the turned body stands partly over the holes";
  EXPECT_GT((s.feet - stop).norm(), 1.0) << "the walker cannot walk away from the border after turning";
}

// ------------------------------------------------------------------------------------------------
// Situation: the raster's edge. A GeoTIFF of 20 x 16 pixels of 0.5 m: the raster covers half a pixel
// beyond the outermost sample centres, the ground ends at those centres (heightfield.h). Exact
// answers: the rule on a lattice reaching two cells beyond the samples; rays from outside: a
// vertical ray 1e-9 m beyond the last sample line misses, a low ray entering across the edge hits
// the plane at the closed-form point; the walker walking and flying east stops at the edge with
// every footprint sample on ground, within a quarter metre of leaving it, and placing the viewer
// astride the edge is refused.
TEST(HardCase, RasterEdge_NoGroundOutside) {
  hardcase::ScratchFolder dir;
  const Eigen::Vector2d corner(550000, 4650008);
  auto plane = [](int c, int r) { return 100.0 + c / 16.0 + r / 64.0; };
  hardcase::writeGeoTiff(dir / "edge.tif", 20, 16, corner.x(), corner.y(), 0.5, plane);
  const Heightfield hf = terrain::readDem((dir / "edge.tif").string());
  const GridRule g{20, 16, corner.x() + 0.25, corner.y() - 0.25, 0.5, 0.5, [](int, int) { return true; }, plane};
  compareGroundWithRule(hf, g, 2.0, "raster edge");
  // The raster's own outer corner (half a pixel beyond the samples) has no ground.
  EXPECT_FALSE(hf.groundHeight(corner.x(), corner.y() - 4.0));
  EXPECT_FALSE(hf.groundHeight(corner.x() + 10.0, corner.y() - 4.0));

  const Eigen::Vector2d east = g.at(19, 7);
  EXPECT_FALSE(hf.intersectRay({east.x() + 1e-9, east.y(), 500}, {0, 0, -1}));
  EXPECT_FALSE(hf.intersectRay({east.x() + 1.0, east.y(), 500}, {0, 0, -1}));
  // From 2 m east of the edge, heading west and down at 3/8 per metre, 1/16 m above the edge's
  // height where it crosses the edge: the plane falls westward at 1/8 per metre, so the ray meets
  // it 1/4 m inside, at t = 2.25 and 1/32 m below the edge's height.
  const double zEdge = 100.0 + 19 / 16.0 + 7 / 64.0;
  const auto hit = hf.intersectRay({east.x() + 2.0, east.y(), zEdge + 13.0 / 16}, {-1, 0, -3.0 / 8});
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 2.25, 1e-12);
  EXPECT_NEAR(hit->point.z(), zEdge - 1.0 / 32, 1e-12);

  for (bool flying : {false, true}) {
    GroundRig rig(hf, hf.origin());
    const Eigen::Vector2d start = g.at(10, 7.5);
    ASSERT_EQ(rig.walker->place({start.x(), start.y(), 0}, false, 90, flying, 2.0), "");
    const ViewerSpec& v = rig.walker->options().viewer;
    walkToward(*rig.walker, g.at(30, 7.5), 13.0, 90);
    const WalkerState& s = rig.walker->state();
    EXPECT_TRUE(s.blocked) << (flying ? "flying" : "walking");
    EXPECT_EQ(s.reason, BlockReason::TerrainEdge);
    double front = -1e300;
    for (const Eigen::Vector2d& q : footprint(s.feet.head<2>(), 90, v.bodyHalfExtents.x(), v.bodyHalfExtents.y())) {
      EXPECT_TRUE(g.ground(q.x(), q.y())) << "footprint sample beyond the edge at " << q.transpose();
      front = std::max(front, q.x());
    }
    EXPECT_LE(front, east.x() + 1e-9);
    EXPECT_GT(front, east.x() - 0.25) << "stopped more than a quarter metre short of the edge";
  }
  // Astride the edge: refused.
  GroundRig rig(hf, hf.origin());
  EXPECT_NE(rig.walker->place({east.x() - 0.1, east.y(), 0}, false, 0, false, 2.0), "");
}

// ------------------------------------------------------------------------------------------------
// Situation: vertical bench faces. A step of 10 m between columns 19 and 20 of a grid of 0.5 m cells
// (a face of slope 20, 87 degrees, as steep as a grid gets): the ground in the face cell is
// 20 (x - x19) exactly, every row. The walker walks at it from below and from above at 1.4, 13 and
// 50 m/s (up to 0.83 m per step, more than the cell): it is blocked (step or slope), never stands on
// the face (feet exactly at 0 below, exactly at 10 above, equal to groundHeight), at no step gets
// past the face's foot (below) or its brink (above), and the footprint's corners stay where the
// documented slope limit allows: the least-squares slope of the corners, 2 h_front / (4 hx) along
// the motion, at most tan 30 degrees.
TEST(HardCase, VerticalBenchFace) {
  const Eigen::Vector2d o(550000.25, 4650000.75);
  const GridRule g{40, 12, o.x(), o.y(), 0.5, 0.5, [](int, int) { return true; },
                   [](int c, int) { return c >= 20 ? 10.0 : 0.0; }};
  const Heightfield hf = heightfieldOf(g);
  compareGroundWithRule(hf, g, 0.0, "bench");
  const double xFoot = g.at(19, 0).x(), xBrink = g.at(20, 0).x();
  for (double f : {0.0, 0.125, 0.5, 0.875, 1.0}) {
    const std::optional<double> z = hf.groundHeight(xFoot + 0.5 * f, o.y() - 2.3);
    ASSERT_TRUE(z);
    EXPECT_EQ(*z, 10.0 * f) << "on the face at " << f << " of the cell";
  }

  const double maxFrontRise = std::tan(radians(30.0)) * 4 * 0.25 / 2;
  for (double speed : {1.4, 13.0, 50.0}) {
    for (bool fromBelow : {true, false}) {
      GroundRig rig(hf, o);
      const double heading = fromBelow ? 90 : 270;
      const Eigen::Vector2d start(fromBelow ? xFoot - 4.0 : xBrink + 4.0, o.y() - 2.75);
      ASSERT_EQ(rig.walker->place({start.x(), start.y(), 0}, false, heading, false, 2.0), "");
      const double bench = fromBelow ? 0.0 : 10.0;
      walkToward(*rig.walker, {fromBelow ? xBrink + 4.0 : xFoot - 4.0, start.y()}, speed, heading, [&](const Walker& w) {
        const double x = w.state().feet.x();
        ASSERT_TRUE(fromBelow ? x < xFoot : x > xBrink) << "on the face at " << speed << " m/s";
        ASSERT_EQ(w.state().feet.z(), bench);
      });
      const WalkerState& s = rig.walker->state();
      EXPECT_TRUE(s.blocked);
      EXPECT_TRUE(s.reason == BlockReason::TerrainStep || s.reason == BlockReason::TerrainSlope) << blockReasonName(s.reason);
      EXPECT_EQ(s.feet.z(), *hf.groundHeight(s.feet.x(), s.feet.y()));
      const auto fp = footprint(s.feet.head<2>(), heading, 0.25, 0.25);
      for (int k = 1; k <= 2; ++k) {  // the front corners
        const double rise = std::abs(*g.ground(fp[k].x(), fp[k].y()) - bench);
        EXPECT_LE(rise, maxFrontRise + 1e-12) << speed << " m/s: front corner " << rise << " m up the face";
      }
    }
  }
}

}  // namespace
}  // namespace nestwalk
