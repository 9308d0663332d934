// Heightfield: ground lookup and ray casts against independently computed values (planes that the
// triangulation reproduces exactly, hand-made cells, step terrains), at small and UTM magnitudes.
#include "nestwalk/terrain/heightfield.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace nestwalk::terrain {
namespace {

constexpr double kTol = 1e-9;  // metres: the brief's tolerance for ground heights and hit points
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

struct Origin {
  double x, y;
};
// Small, round UTM, and non-integer UTM origins.
const Origin kOrigins[] = {{0.0, 0.0}, {550000.0, 4650000.0}, {323476.072, 5105081.983}};

// Plane z = a * (x - ox) + b * (y - oy) + c sampled exactly (dyadic slopes and spacings keep the
// samples exact in float).
struct Plane {
  double a, b, c;
  double at(double lx, double ly) const { return a * lx + b * ly + c; }
};

Heightfield planeField(int cols, int rows, Origin o, double dx, double dy, Plane p) {
  std::vector<float> h(std::size_t(cols) * rows);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) h[std::size_t(r) * cols + c] = float(p.at(c * dx, -r * dy));
  return Heightfield(cols, rows, std::move(h), o.x, o.y, dx, dy);
}

Heightfield randomField(int cols, int rows, Origin o, double dx, double dy, unsigned seed,
                        std::optional<float> noData = std::nullopt) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> U(0.0f, 50.0f);
  std::vector<float> h(std::size_t(cols) * rows);
  for (auto& v : h) v = U(rng);
  return Heightfield(cols, rows, std::move(h), o.x, o.y, dx, dy, noData);
}

TEST(Heightfield, ConstructorValidates) {
  EXPECT_THROW(Heightfield(3, 3, std::vector<float>(8), 0, 0, 1, 1), std::invalid_argument);
  EXPECT_THROW(Heightfield(1, 3, std::vector<float>(3), 0, 0, 1, 1), std::invalid_argument);
  EXPECT_THROW(Heightfield(3, 3, std::vector<float>(9), 0, 0, 0, 1), std::invalid_argument);
  EXPECT_THROW(Heightfield(3, 3, std::vector<float>(9), 0, 0, 1, -1), std::invalid_argument);
  EXPECT_THROW(Heightfield(3, 3, std::vector<float>(9), 0, 0, std::nan(""), 1), std::invalid_argument);
  EXPECT_THROW(Heightfield(3, 3, std::vector<float>(9), std::numeric_limits<double>::infinity(), 0, 1, 1),
               std::invalid_argument);
  EXPECT_THROW(Heightfield(3, 3, std::vector<float>(9), 0, std::nan(""), 1, 1), std::invalid_argument);
  Heightfield hf(3, 2, std::vector<float>(6, 1.0f), 10.0, 20.0, 2.0, 3.0, -9999.0f, "WKT");
  EXPECT_EQ(hf.cols(), 3);
  EXPECT_EQ(hf.rows(), 2);
  EXPECT_EQ(hf.crsWkt(), "WKT");
  EXPECT_EQ(hf.samplePosition(2, 1), Eigen::Vector2d(14.0, 17.0));
}

TEST(Heightfield, GroundAtSamplesIsExact) {
  for (Origin o : kOrigins)
    for (double d : {1.0, 30.0, 0.7}) {
      Heightfield hf = randomField(9, 7, o, d, d * 1.3, 1);
      for (int r = 0; r < hf.rows(); ++r)
        for (int c = 0; c < hf.cols(); ++c) {
          const Eigen::Vector2d p = hf.samplePosition(c, r);
          const auto g = hf.groundHeight(p.x(), p.y());
          ASSERT_TRUE(g) << c << " " << r;
          EXPECT_EQ(*g, double(hf.sample(c, r))) << "origin " << o.x << " d " << d << " at " << c << "," << r;
        }
    }
}

TEST(Heightfield, GroundOnGridEdgesIsLinear) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> F(0.0, 1.0);
  for (Origin o : kOrigins) {
    const double dx = 30.0, dy = 29.5;
    Heightfield hf = randomField(8, 6, o, dx, dy, 3);
    for (int r = 0; r < hf.rows(); ++r)
      for (int c = 0; c < hf.cols(); ++c) {
        const Eigen::Vector2d p = hf.samplePosition(c, r);
        for (double f : {0.5, F(rng), F(rng)}) {
          if (c + 1 < hf.cols()) {  // east-west edge: y exactly on the row line
            const double x = o.x + (c + f) * dx;
            const double g = (x - o.x) / dx - c;  // the fraction of the query as given
            const double want = hf.sample(c, r) + g * (double(hf.sample(c + 1, r)) - hf.sample(c, r));
            const auto got = hf.groundHeight(x, p.y());
            ASSERT_TRUE(got);
            EXPECT_NEAR(*got, want, kTol);
          }
          if (r + 1 < hf.rows()) {  // north-south edge: x exactly on the column line
            const double y = o.y - (r + f) * dy;
            const double g = (o.y - y) / dy - r;
            const double want = hf.sample(c, r) + g * (double(hf.sample(c, r + 1)) - hf.sample(c, r));
            const auto got = hf.groundHeight(p.x(), y);
            ASSERT_TRUE(got);
            EXPECT_NEAR(*got, want, kTol);
          }
        }
      }
  }
}

TEST(Heightfield, PlaneIsReproducedEverywhere) {
  const Plane pl{0.125, -0.375, 812.5};
  std::mt19937 rng(4);
  for (Origin o : kOrigins) {
    const double dx = 2.0, dy = 4.0;
    Heightfield hf = planeField(17, 11, o, dx, dy, pl);
    std::uniform_real_distribution<double> X(0.0, 16 * dx), Y(0.0, 10 * dy), T(0.0, 1.0);
    for (int k = 0; k < 2000; ++k) {
      const double x = o.x + X(rng), y = o.y - Y(rng);
      const auto g = hf.groundHeight(x, y);
      ASSERT_TRUE(g);
      EXPECT_NEAR(*g, pl.at(x - o.x, y - o.y), kTol);
    }
    // On cell diagonals and at cell centres.
    for (int r = 0; r + 1 < hf.rows(); ++r)
      for (int c = 0; c + 1 < hf.cols(); ++c)
        for (double t : {0.5, T(rng)}) {
          const double x = o.x + (c + t) * dx, y = o.y - (r + t) * dy;
          const auto g = hf.groundHeight(x, y);
          ASSERT_TRUE(g);
          EXPECT_NEAR(*g, pl.at(x - o.x, y - o.y), kTol);
        }
  }
}

TEST(Heightfield, TriangulationRuleNorthWestToSouthEast) {
  for (Origin o : kOrigins) {
    // One cell, only the south-east corner raised: both halves agree on the diagonal.
    Heightfield a(2, 2, {0, 0, 0, 1}, o.x, o.y, 1.0, 1.0);
    auto at = [&](const Heightfield& hf, double fx, double fy) { return *hf.groundHeight(o.x + fx, o.y - fy); };
    EXPECT_NEAR(at(a, 0.5, 0.5), 0.5, kTol);    // diagonal
    EXPECT_NEAR(at(a, 0.75, 0.25), 0.25, kTol);  // upper: 0 + 0.75 * 0 + 0.25 * (1 - 0)
    EXPECT_NEAR(at(a, 0.25, 0.75), 0.25, kTol);  // lower: 0 + 0.75 * 0 + 0.25 * (1 - 0)
    // Only the north-east corner raised: the halves differ (a fold along the diagonal).
    Heightfield b(2, 2, {0, 1, 0, 0}, o.x, o.y, 1.0, 1.0);
    EXPECT_NEAR(at(b, 0.75, 0.25), 0.5, kTol);  // upper: 0.75 * 1 + 0.25 * (0 - 1)
    EXPECT_NEAR(at(b, 0.25, 0.75), 0.0, kTol);  // lower: plane through three zeros
    EXPECT_NEAR(at(b, 0.5, 0.5), 0.0, kTol);    // the diagonal joins two zeros
    EXPECT_NEAR(at(b, 0.6, 0.4), 0.2, kTol);
  }
}

// 4 x 4 grid with a hole at sample (1, 1) under each sentinel convention.
TEST(Heightfield, HolesFollowTheClosedSimplexRule) {
  struct Case {
    float holeValue;
    std::optional<float> noData;
  };
  const Case cases[] = {{32767.0f, 32767.0f},
                        {-9999.0f, -9999.0f},
                        {kNaN, std::nullopt},
                        {kNaN, -9999.0f},
                        {std::numeric_limits<float>::infinity(), std::nullopt}};
  for (Origin o : kOrigins)
    for (const Case& cs : cases) {
      const double dx = 30.0, dy = 30.0;
      std::vector<float> h(16);
      for (int i = 0; i < 16; ++i) h[i] = float(100 + i);
      h[1 * 4 + 1] = cs.holeValue;
      Heightfield hf(4, 4, h, o.x, o.y, dx, dy, cs.noData);
      auto g = [&](double c, double r) { return hf.groundHeight(o.x + c * dx, o.y - r * dy); };
      auto H = [&](int c, int r) { return double(h[std::size_t(r) * 4 + c]); };
      EXPECT_FALSE(hf.valid(1, 1));
      EXPECT_TRUE(hf.valid(0, 0));
      EXPECT_DOUBLE_EQ(hf.noDataFraction(), 1.0 / 16.0);
      auto range = hf.heightRange();
      ASSERT_TRUE(range);
      EXPECT_EQ(range->first, 100.0f);
      EXPECT_EQ(range->second, 115.0f);
      EXPECT_FALSE(g(1, 1));             // the hole itself
      EXPECT_FALSE(g(0.7, 0.3));         // upper triangle of cell (0,0) uses (1,1)
      EXPECT_FALSE(g(0.3, 0.7));         // lower triangle of cell (0,0)
      EXPECT_FALSE(g(1.0, 0.5));         // on the edge (1,0)-(1,1)
      EXPECT_FALSE(g(0.5, 0.5));         // on the diagonal (0,0)-(1,1)
      EXPECT_FALSE(g(1.3, 0.7));         // lower triangle of cell (1,0) uses (1,1)
      ASSERT_TRUE(g(1.7, 0.3));          // upper triangle of cell (1,0): (1,0),(2,0),(2,1)
      EXPECT_NEAR(*g(1.7, 0.3), H(1, 0) + 0.7 * (H(2, 0) - H(1, 0)) + 0.3 * (H(2, 1) - H(2, 0)), kTol);
      ASSERT_TRUE(g(1.5, 0.5));          // diagonal (1,0)-(2,1): both samples valid
      EXPECT_NEAR(*g(1.5, 0.5), 0.5 * (H(1, 0) + H(2, 1)), kTol);
      ASSERT_TRUE(g(0.5, 0.0));          // edge (0,0)-(1,0), next to the hole
      EXPECT_NEAR(*g(0.5, 0.0), 0.5 * (H(0, 0) + H(1, 0)), kTol);
      ASSERT_TRUE(g(0.0, 0.25));         // edge (0,0)-(0,1)
      EXPECT_NEAR(*g(0.0, 0.25), 0.75 * H(0, 0) + 0.25 * H(0, 1), kTol);
      ASSERT_TRUE(g(1.0, 0.0));          // sample (1,0), all its triangles but one touch the hole
      EXPECT_EQ(*g(1.0, 0.0), H(1, 0));
      ASSERT_TRUE(g(0.0, 1.0));
      EXPECT_EQ(*g(0.0, 1.0), H(0, 1));
      ASSERT_TRUE(g(2.5, 2.5));
      // Rays: a vertical ray into the hole's triangles misses, elsewhere it matches the ground.
      EXPECT_FALSE(hf.intersectRay({o.x + 0.7 * dx, o.y - 0.3 * dy, 500.0}, {0, 0, -1}));
      auto hit = hf.intersectRay({o.x + 2.5 * dx, o.y - 2.5 * dy, 500.0}, {0, 0, -1});
      ASSERT_TRUE(hit);
      EXPECT_NEAR(hit->point.z(), *g(2.5, 2.5), kTol);
      // A ray dropping steeply into the hole region from the north-west, and one leaving it beyond
      // the west edge of the raster: no hit.
      EXPECT_FALSE(hf.intersectRay({o.x + 0.2 * dx, o.y - 0.2 * dy, 500.0}, {0.5 * dx, -0.5 * dy, -1000.0}));
      EXPECT_FALSE(hf.intersectRay({o.x + 0.8 * dx, o.y - 0.8 * dy, 104.0}, {-dx, 0.1, -0.001}));
    }
}

TEST(Heightfield, SentinelOnlyMatchesItsOwnValue) {
  Heightfield hf(2, 2, {-9999.0f, 1.0f, 2.0f, 3.0f}, 0, 0, 1, 1, 32767.0f);
  EXPECT_TRUE(hf.valid(0, 0));
  EXPECT_EQ(hf.noDataFraction(), 0.0);
  EXPECT_EQ(hf.heightRange()->first, -9999.0f);
  Heightfield allHoles(2, 2, {kNaN, kNaN, 5.0f, 5.0f}, 0, 0, 1, 1, 5.0f);
  EXPECT_FALSE(allHoles.heightRange());
  EXPECT_EQ(allHoles.noDataFraction(), 1.0);
  EXPECT_FALSE(allHoles.groundHeight(0.5, -0.5));
  EXPECT_FALSE(allHoles.intersectRay({0.5, -0.5, 10}, {0, 0, -1}));
}

TEST(Heightfield, RasterEdge) {
  for (Origin o : kOrigins) {
    const double dx = 30.0, dy = 25.0;
    Heightfield hf = randomField(5, 4, o, dx, dy, 5);
    const double xLast = hf.samplePosition(4, 0).x(), yLast = hf.samplePosition(0, 3).y();
    const double yMid = o.y - 1.5 * dy, xMid = o.x + 2.5 * dx;
    // Exactly on the outer sample lines: ground; one ulp outside: none.
    for (int r = 0; r < 4; ++r) {
      EXPECT_EQ(*hf.groundHeight(xLast, hf.samplePosition(4, r).y()), double(hf.sample(4, r)));
      EXPECT_EQ(*hf.groundHeight(o.x, hf.samplePosition(0, r).y()), double(hf.sample(0, r)));
    }
    EXPECT_EQ(*hf.groundHeight(xLast, yLast), double(hf.sample(4, 3)));
    ASSERT_TRUE(hf.groundHeight(xLast, yMid));
    EXPECT_NEAR(*hf.groundHeight(xLast, yMid), 0.5 * (double(hf.sample(4, 1)) + hf.sample(4, 2)), kTol);
    ASSERT_TRUE(hf.groundHeight(xMid, yLast));
    EXPECT_NEAR(*hf.groundHeight(xMid, yLast), 0.5 * (double(hf.sample(2, 3)) + hf.sample(3, 3)), kTol);
    EXPECT_FALSE(hf.groundHeight(std::nextafter(xLast, 1e300), yMid));
    EXPECT_FALSE(hf.groundHeight(std::nextafter(o.x, -1e300), yMid));
    EXPECT_FALSE(hf.groundHeight(xMid, std::nextafter(o.y, 1e300)));
    EXPECT_FALSE(hf.groundHeight(xMid, std::nextafter(yLast, -1e300)));
    EXPECT_FALSE(hf.groundHeight(xLast + 1000.0, yMid));
    EXPECT_FALSE(hf.groundHeight(std::nan(""), yMid));
    // Rays beyond the edge miss; a ray starting outside and entering hits.
    EXPECT_FALSE(hf.intersectRay({xLast + 1.0, yMid, 100.0}, {0, 0, -1}));
    EXPECT_FALSE(hf.intersectRay({xLast + 1.0, yMid, 100.0}, {1, 0.2, -0.5}));
    EXPECT_TRUE(hf.intersectRay({xLast + 10.0, yMid, 100.0}, {-1, 0.0, -1.0}));
  }
}

TEST(Heightfield, GroundCeilingBoundsEveryGroundHeightInItsRectangleAndRefusesHolesAndEdges) {
  // Random heights with a patch of holes; rectangles of up to 30 cells (a third of them up to 3, which
  // their cells' own samples bound rather than the 8 x 8-cell blocks), some reaching past the edge
  // or onto the patch, some with corners exactly on samples. Brute force: the ground is linear on
  // each triangle, so its highest point in a rectangle is at a sample inside it, a corner, or where
  // a side crosses a grid line or a cell diagonal; every such point is asked for.
  const int cols = 203, rows = 157;
  const double dx = 0.05, dy = 0.04;
  const int holeC0 = 100, holeC1 = 110, holeR0 = 60, holeR1 = 70;
  int bounded = 0, refused = 0;
  for (Origin o : kOrigins) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> U(0.0f, 50.0f);
    std::vector<float> h(std::size_t(cols) * rows);
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c)
        h[std::size_t(r) * cols + c] = (c >= holeC0 && c <= holeC1 && r >= holeR0 && r <= holeR1) ? kNaN : U(rng);
    const Heightfield hf(cols, rows, h, o.x, o.y, dx, dy);
    std::uniform_real_distribution<double> uc(-3.0, cols + 2.0), ur(-3.0, rows + 2.0), size(0.0, 30.0);
    for (int k = 0; k < 3000; ++k) {
      double c0 = uc(rng), r0 = ur(rng), c1 = c0 + size(rng), r1 = r0 + size(rng);
      if (k % 3 == 1) c1 = c0 + (c1 - c0) / 10, r1 = r0 + (r1 - r0) / 10;  // at most 3 cells: bounded by their samples
      if (k % 4 == 0) c0 = std::floor(c0), r0 = std::floor(r0), c1 = std::floor(c1), r1 = std::floor(r1);
      const double x0 = o.x + c0 * dx, x1 = o.x + c1 * dx, y0 = o.y - r1 * dy, y1 = o.y - r0 * dy;
      // Points: the corners, every sample inside, the sides' crossings with grid lines and diagonals.
      std::vector<Eigen::Vector2d> pts = {{x0, y0}, {x0, y1}, {x1, y0}, {x1, y1}};
      for (int r = std::max(0, int(std::ceil(r0))); r <= std::min(rows - 1, int(std::floor(r1))); ++r)
        for (int c = std::max(0, int(std::ceil(c0))); c <= std::min(cols - 1, int(std::floor(c1))); ++c) {
          pts.push_back(hf.samplePosition(c, r));
          pts.push_back({hf.samplePosition(c, r).x(), y0});
          pts.push_back({hf.samplePosition(c, r).x(), y1});
          pts.push_back({x0, hf.samplePosition(c, r).y()});
          pts.push_back({x1, hf.samplePosition(c, r).y()});
        }
      for (int c = int(std::floor(c0)); c <= int(std::ceil(c1)); ++c) {  // diagonals across the top and bottom sides
        pts.push_back({o.x + (c + (r0 - std::floor(r0))) * dx, y1});
        pts.push_back({o.x + (c + (r1 - std::floor(r1))) * dx, y0});
      }
      for (int r = int(std::floor(r0)); r <= int(std::ceil(r1)); ++r) {  // across the west and east sides
        pts.push_back({x0, o.y - (r + (c0 - std::floor(c0))) * dy});
        pts.push_back({x1, o.y - (r + (c1 - std::floor(c1))) * dy});
      }
      bool allGround = true;
      double highest = -std::numeric_limits<double>::infinity();
      for (const Eigen::Vector2d& p : pts) {
        if (p.x() < x0 || p.x() > x1 || p.y() < y0 || p.y() > y1) continue;
        const std::optional<double> g = hf.groundHeight(p.x(), p.y());
        if (!g) allGround = false;
        else highest = std::max(highest, *g);
      }
      const std::optional<double> ceiling = hf.groundCeiling(x1, y1, x0, y0);  // either order
      ASSERT_EQ(ceiling, hf.groundCeiling(x0, y0, x1, y1));
      if (!allGround) {
        ASSERT_FALSE(ceiling) << "a point without ground in rectangle " << k;
      } else if (ceiling) {
        ASSERT_GE(*ceiling, highest) << "rectangle " << k;
        ASSERT_LE(*ceiling, 50.0 * (1 + 1e-11));
      }
      // Inside the hull and more than a block (8 cells) from the hole patch: never refused.
      const bool clear = c0 >= 0 && r0 >= 0 && c1 <= cols - 1 && r1 <= rows - 1 &&
                         (c1 < holeC0 - 9 || c0 > holeC1 + 9 || r1 < holeR0 - 9 || r0 > holeR1 + 9);
      if (clear) {
        ASSERT_TRUE(ceiling) << "rectangle " << k;
      }
      ceiling ? ++bounded : ++refused;
    }
  }
  EXPECT_GT(bounded, 3000);
  EXPECT_GT(refused, 1000);
}

TEST(HeightfieldRay, VerticalRaysEqualGroundHeight) {
  std::mt19937 rng(6);
  for (Origin o : kOrigins) {
    const double dx = 30.0, dy = 30.0;
    Heightfield hf = randomField(33, 21, o, dx, dy, 7);
    std::uniform_real_distribution<double> X(0.0, 32 * dx), Y(0.0, 20 * dy);
    std::uniform_int_distribution<int> C(0, 32), R(0, 20);
    for (int k = 0; k < 3000; ++k) {
      double x = o.x + X(rng), y = o.y - Y(rng);
      if (k % 3 == 1) x = hf.samplePosition(C(rng), 0).x();  // on a column line
      if (k % 3 == 2) y = hf.samplePosition(0, R(rng)).y();  // on a row line
      if (k % 7 == 0) {                                        // at a sample
        const Eigen::Vector2d p = hf.samplePosition(C(rng), R(rng));
        x = p.x(), y = p.y();
      }
      const auto g = hf.groundHeight(x, y);
      ASSERT_TRUE(g);
      const auto hit = hf.intersectRay({x, y, 1000.0}, {0, 0, -1});
      ASSERT_TRUE(hit) << k;
      EXPECT_NEAR(hit->point.z(), *g, kTol);
      EXPECT_NEAR(hit->t, 1000.0 - *g, kTol);
      // Longer direction vectors scale t.
      const auto hit2 = hf.intersectRay({x, y, 1000.0}, {0, 0, -4});
      ASSERT_TRUE(hit2);
      EXPECT_NEAR(hit2->t, (1000.0 - *g) / 4, kTol);
      // Upward from below.
      const auto up = hf.intersectRay({x, y, -100.0}, {0, 0, 1});
      ASSERT_TRUE(up);
      EXPECT_NEAR(up->point.z(), *g, kTol);
    }
  }
}

// Rays aimed at vertices, edges and diagonals of a plane: the hit is the analytic ray-plane point.
TEST(HeightfieldRay, RaysThroughVerticesEdgesAndDiagonalsOfAPlane) {
  const Plane pl{0.25, 0.125, 50.0};
  std::mt19937 rng(8);
  std::normal_distribution<double> N(0.0, 1.0);
  for (Origin o : kOrigins) {
    const double dx = 2.0, dy = 2.0;
    Heightfield hf = planeField(12, 10, o, dx, dy, pl);
    for (int r = 1; r + 1 < hf.rows(); ++r)
      for (int c = 1; c + 1 < hf.cols(); ++c)
        for (int kind = 0; kind < 4; ++kind) {
          double lx = c * dx, ly = -r * dy;                 // vertex
          if (kind == 1) lx += 0.37 * dx;                    // east-west edge
          if (kind == 2) ly -= 0.61 * dy;                    // north-south edge
          if (kind == 3) lx += 0.29 * dx, ly -= 0.29 * dy;  // diagonal
          const Eigen::Vector3d target(o.x + lx, o.y + ly, pl.at(lx, ly));
          // Directions: along the grid lines (2D), along the diagonal, and random, all downward and
          // at least 0.5 steeper than the plane (so that t is well conditioned).
          const double rx = N(rng), ry = N(rng);
          const Eigen::Vector3d random(rx, ry, -std::abs(N(rng)) - 0.5 - 0.25 * std::abs(rx) - 0.125 * std::abs(ry));
          const Eigen::Vector3d dirs[] = {{1, 0, -0.8}, {0, -1, -0.8}, {dx, -dy, -1.0}, {-dx, dy, -1.0},
                                          random};
          for (const Eigen::Vector3d& d : dirs) {
            const double s = 3.0;
            const Eigen::Vector3d org = target - s * d;  // from above the plane
            const auto hit = hf.intersectRay(org, d);
            ASSERT_TRUE(hit) << "kind " << kind << " at " << c << "," << r;
            // Analytic: plane z - a lx - b ly = c along the ray.
            const Eigen::Vector3d lo(org.x() - o.x, org.y() - o.y, org.z());
            const double f0 = lo.z() - pl.at(lo.x(), lo.y());
            const double f1 = d.z() - pl.a * d.x() - pl.b * d.y();
            const double t = -f0 / f1;
            EXPECT_NEAR(hit->t, t, 1e-9);
            EXPECT_NEAR((hit->point - target).norm(), 0.0, 1e-8);
          }
        }
  }
}

// Watertightness on a rough surface: rays crossing the surface exactly at vertices, on edges and on
// diagonals (and running along grid lines and diagonals in 2D) hit there. Heights in [0, 2] m on a
// 1 m grid bound every triangle's rise along a horizontal step (ex, ey) by 2 (|ex| + |ey|); a ray
// steeper than that crosses the surface exactly once, so the first hit is the aimed-at point.
TEST(HeightfieldRay, WatertightOnRoughSurface) {
  std::mt19937 rng(9);
  std::normal_distribution<double> N(0.0, 1.0);
  std::uniform_real_distribution<double> F(0.0, 1.0);
  std::uniform_real_distribution<float> Hgt(0.0f, 2.0f);
  for (Origin o : kOrigins) {
    const int n = 20;
    std::vector<float> h(n * n);
    for (auto& v : h) v = Hgt(rng);
    Heightfield hf(n, n, h, o.x, o.y, 1.0, 1.0);
    // Interior targets: a ray that meets the surface only at its outer boundary (entering the
    // footprint exactly where it crosses the surface) is a grazing, measure-zero case.
    std::uniform_int_distribution<int> CI(1, n - 3);
    for (int k = 0; k < 20000; ++k) {
      const int c = CI(rng), r = CI(rng);
      const double f = k % 4 == 0 ? 0.0 : F(rng);
      double fx = 0, fy = 0;
      switch (k % 3) {
        case 0: fx = f; break;        // east-west edge (vertex when f = 0)
        case 1: fy = f; break;        // north-south edge
        default: fx = fy = f; break;  // diagonal
      }
      const Eigen::Vector2d p0 = hf.samplePosition(c, r);
      const double x = fx == 0 ? p0.x() : o.x + (c + fx), y = fy == 0 ? p0.y() : o.y - (r + fy);
      const auto g = hf.groundHeight(x, y);
      ASSERT_TRUE(g);
      Eigen::Vector2d e(N(rng), N(rng));
      if (k % 5 == 0) e = {k % 2 ? 1.0 : -1.0, 0.0};  // along a row line
      if (k % 5 == 1) e = {0.0, k % 2 ? 1.0 : -1.0};  // along a column line
      if (k % 5 == 2) e = {k % 2 ? 1.0 : -1.0, k % 2 ? -1.0 : 1.0};  // along the cell diagonals
      const double steep = 2.0 * (std::abs(e.x()) + std::abs(e.y())) + 0.05 + std::abs(N(rng));
      const Eigen::Vector3d d(e.x(), e.y(), k % 7 == 0 ? steep : -steep);  // 1 in 7 from below
      const double s = 0.5 + 3.0 * F(rng);
      const Eigen::Vector3d target(x, y, *g);
      const auto hit = hf.intersectRay(target - s * d, d);
      ASSERT_TRUE(hit) << "k " << k << " origin " << o.x;
      // target - s d rounds to the UTM grid of doubles (ulp 1e-9 m at 5e6 m), which moves the
      // crossing by up to a few 1e-9 m: 1e-8 here; the hit itself lies on the surface to 1e-9 m.
      EXPECT_NEAR(hit->t, s, 1e-8) << "k " << k;
      EXPECT_NEAR((hit->point - target).norm(), 0.0, 1e-8);
      const auto gHit = hf.groundHeight(hit->point.x(), hit->point.y());
      ASSERT_TRUE(gHit);
      EXPECT_NEAR(hit->point.z(), *gHit, 1e-8);
    }
  }
}

// A bench: columns 0..4 at 0 m, columns 5..9 at 10 m; the face between columns 4 and 5 is the
// plane z = 10 (x - 4 dx) / dx for every row.
TEST(HeightfieldRay, HorizontalRaysGrazeAStepTerrain) {
  for (Origin o : kOrigins) {
    const int cols = 10, rows = 6;
    const double dx = 3.0, dy = 2.0;
    std::vector<float> h(cols * rows);
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) h[r * cols + c] = c >= 5 ? 10.0f : 0.0f;
    Heightfield hf(cols, rows, h, o.x, o.y, dx, dy);
    for (int r = 0; r < rows; ++r)
      for (double fy : {0.0, 0.5, 0.25}) {
        if (r == rows - 1 && fy != 0.0) continue;
        const double y = fy == 0.0 ? hf.samplePosition(0, r).y() : o.y - (r + fy) * dy;
        for (double z : {0.0, 5.0, 10.0, 2.5}) {
          const double xFace = o.x + (4.0 + z / 10.0) * dx;
          const Eigen::Vector3d org(o.x - 7.0, y, z);  // west of the raster
          const auto hit = hf.intersectRay(org, {1, 0, 0});
          ASSERT_TRUE(hit) << "row " << r << " fy " << fy << " z " << z;
          EXPECT_NEAR(hit->point.x(), xFace, kTol);
          EXPECT_NEAR(hit->t, xFace - org.x(), kTol);
          EXPECT_EQ(hit->col, 4);
          // Coming from the east at the same height: the flat top is above the ray for z < 10, so
          // the face is hit at the same point; at z = 10 the ray lies in the top's plane (ignored)
          // and hits the face at its upper edge.
          const Eigen::Vector3d east(o.x + 12.0 * dx, y, z);
          const auto back = hf.intersectRay(east, {-1, 0, 0});
          ASSERT_TRUE(back);
          EXPECT_NEAR(back->point.x(), z < 10.0 ? xFace : o.x + 5.0 * dx, kTol);
        }
        // Above the bench, parallel: no hit.
        EXPECT_FALSE(hf.intersectRay({o.x - 7.0, y, 10.5}, {1, 0, 0}));
        EXPECT_FALSE(hf.intersectRay({o.x - 7.0, y, 10.0 + 1e-9}, {1, 0, 0}));
      }
  }
}

TEST(HeightfieldRay, StartBelowTheSurfaceAndRange) {
  const Plane pl{0.0, 0.0, 20.0};
  for (Origin o : kOrigins) {
    Heightfield hf = planeField(8, 8, o, 5.0, 5.0, pl);
    const Eigen::Vector3d org(o.x + 12.0, o.y - 13.0, 15.0);  // 5 m below
    auto up = hf.intersectRay(org, {0.3, -0.2, 1.0});
    ASSERT_TRUE(up);
    EXPECT_NEAR(up->t, 5.0, kTol);
    EXPECT_NEAR(up->point.z(), 20.0, kTol);
    EXPECT_FALSE(hf.intersectRay(org, {0.3, -0.2, -1.0}));  // going down, away from it
    EXPECT_FALSE(hf.intersectRay(org, {0.3, -0.2, 1.0}, 0.0, 4.9));
    EXPECT_FALSE(hf.intersectRay(org, {0.3, -0.2, 1.0}, 5.1));
    EXPECT_TRUE(hf.intersectRay(org, {0.3, -0.2, 1.0}, 0.0, 5.0 + 1e-9));
    // Parallel above: no hit; parallel below: none either.
    EXPECT_FALSE(hf.intersectRay({o.x - 10.0, o.y - 10.0, 20.5}, {1, -0.3, 0}));
    EXPECT_FALSE(hf.intersectRay({o.x - 10.0, o.y - 10.0, 19.5}, {1, -0.3, 0}));
    // A ray starting on the surface hits at t = 0.
    auto on = hf.intersectRay({o.x + 10.0, o.y - 10.0, 20.0}, {1, 1, -1});
    ASSERT_TRUE(on);
    EXPECT_NEAR(on->t, 0.0, kTol);
  }
}

TEST(HeightfieldRay, FirstHitOfSeveral) {
  // A ridge in the middle: a low ray from the west hits its west flank, not the far side.
  for (Origin o : kOrigins) {
    std::vector<float> h(9 * 3);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 9; ++c) h[r * 9 + c] = c == 4 ? 8.0f : 0.0f;
    Heightfield hf(9, 3, h, o.x, o.y, 1.0, 1.0);
    auto hit = hf.intersectRay({o.x - 1.0, o.y - 1.0, 4.0}, {1, 0, 0});
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->point.x(), o.x + 3.5, kTol);
    hit = hf.intersectRay({o.x + 9.0, o.y - 0.5, 4.0}, {-1, 0, 0});
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->point.x(), o.x + 4.5, kTol);
  }
}

}  // namespace
}  // namespace nestwalk::terrain
