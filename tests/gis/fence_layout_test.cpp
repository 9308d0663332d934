// Fence layout (gis/fence_layout.h) against an independent measure of the line it covers: every
// piece is the stretch [centre - length/2, centre + length/2] along its own segment (overhangs
// past a vertex continue along the next segment, as the line's arc length does); walking the
// line's arc length, no stretch is left uncovered longer than max_gap and no two pieces cover the
// same stretch longer than max_overlap. Headings follow the segments.
#include "nestwalk/gis/fence_layout.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace nestwalk::gis {
namespace {

struct Coverage {
  double largestGap = 0, largestOverlap = 0;  // metres along the line
};

/// The arc-length coverage of the pieces (computed from the pieces and the line only).
Coverage measure(const std::vector<Eigen::Vector2d>& line, bool closed, const FenceLayout& layout, double piece) {
  const std::size_t segments = closed ? line.size() : line.size() - 1;
  std::vector<double> start(segments + 1, 0.0);  // arc length at each vertex
  for (std::size_t k = 0; k < segments; ++k) start[k + 1] = start[k] + (line[(k + 1) % line.size()] - line[k]).norm();
  const double total = start[segments];
  std::vector<std::pair<double, double>> spans;
  for (const FencePiece& p : layout.pieces) {
    const double along = start[p.segment] + (p.centre - line[p.segment]).norm();
    spans.push_back({along - 0.5 * piece, along + 0.5 * piece});
  }
  std::sort(spans.begin(), spans.end());
  Coverage c;
  for (std::size_t i = 0; i + 1 < spans.size(); ++i) {
    const double joint = spans[i + 1].first - spans[i].second;  // + gap, - overlap
    c.largestGap = std::max(c.largestGap, joint);
    c.largestOverlap = std::max(c.largestOverlap, -joint);
  }
  if (closed && spans.size() > 1) {  // the last piece meets the first across the ring's start
    const double joint = spans.front().first + total - spans.back().second;
    c.largestGap = std::max(c.largestGap, joint);
    c.largestOverlap = std::max(c.largestOverlap, -joint);
  }
  return c;
}

TEST(FenceLayout, RandomLinesStayWithinTheLimits) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> turn(-2.0, 2.0), length(2.0, 40.0);
  const double piece = 3.0, maxGap = 0.3, maxOverlap = 1.5;  // the catalog's defaults for a 3 m barrier
  for (int n = 0; n < 200; ++n) {
    std::vector<Eigen::Vector2d> line = {{550000.0, 4650000.0}};
    double heading = 0;
    const int vertices = 2 + n % 6;
    for (int k = 1; k < vertices; ++k) {
      heading += turn(rng);
      line.push_back(line.back() + length(rng) * Eigen::Vector2d(std::sin(heading), std::cos(heading)));
    }
    const bool closed = n % 5 == 0 && vertices > 2;
    const FenceLayout layout = layoutFence(line, closed, piece, maxGap, maxOverlap);
    ASSERT_TRUE(layout.problems.empty()) << n << ": " << layout.problems.front();  // every segment >= 2 m
    const Coverage c = measure(line, closed, layout, piece);
    EXPECT_LE(c.largestGap, maxGap + 1e-9) << n;
    EXPECT_LE(c.largestOverlap, maxOverlap + 1e-9) << n;
    EXPECT_NEAR(c.largestGap, layout.largestGap, 1e-9) << n << ": the layout reports what it laid";
    EXPECT_NEAR(c.largestOverlap, layout.largestOverlap, 1e-9) << n;
    for (const FencePiece& p : layout.pieces) {
      const Eigen::Vector2d d = line[(p.segment + 1) % line.size()] - line[p.segment];
      const double want = std::fmod(std::atan2(d.x(), d.y()) * 180.0 / std::numbers::pi + 360.0, 360.0);
      EXPECT_NEAR(std::remainder(p.headingDeg - want, 360.0), 0.0, 1e-9) << n;
    }
  }
}

TEST(FenceLayout, ExactMultiplesTouchEndToEnd) {
  const std::vector<Eigen::Vector2d> line = {{0, 0}, {12, 0}, {12, 9}};  // 12 m and 9 m: 4 + 3 pieces
  const FenceLayout layout = layoutFence(line, false, 3.0, 0.0, 0.0);
  ASSERT_EQ(layout.pieces.size(), 7u);
  EXPECT_TRUE(layout.problems.empty());
  EXPECT_NEAR(layout.largestGap, 0.0, 1e-12);
  EXPECT_NEAR(layout.largestOverlap, 0.0, 1e-12);
  EXPECT_NEAR(layout.pieces[0].centre.x(), 1.5, 1e-12);
  EXPECT_NEAR(layout.pieces[0].headingDeg, 90.0, 1e-12);  // east
  EXPECT_NEAR(layout.pieces[6].centre.y(), 7.5, 1e-12);
  EXPECT_NEAR(layout.pieces[6].headingDeg, 0.0, 1e-12);   // north
}

TEST(FenceLayout, SegmentsThatCannotBeCoveredAreReported) {
  // 10 m with 3 m pieces: 3 leave 1/3 m gaps, 4 overlap by 1/2 m; with 0.1 m limits both fail.
  const std::vector<Eigen::Vector2d> line = {{0, 0}, {10, 0}};
  const FenceLayout tight = layoutFence(line, false, 3.0, 0.1, 0.1);
  ASSERT_EQ(tight.problems.size(), 1u);
  EXPECT_NE(tight.problems[0].find("segment 0 (10.000 m) cannot be covered"), std::string::npos) << tight.problems[0];
  EXPECT_EQ(tight.pieces.size(), 3u) << "the count that exceeds its limit least: 0.233 m past 0.1 against 0.4";
  // A stretch shorter than half a piece, with the default limits.
  const std::vector<Eigen::Vector2d> shortLine = {{0, 0}, {1.2, 0}};
  EXPECT_EQ(layoutFence(shortLine, false, 3.0, 0.3, 1.5).problems.size(), 1u);
  EXPECT_TRUE(layoutFence(std::vector<Eigen::Vector2d>{{0, 0}, {1.6, 0}}, false, 3.0, 0.3, 1.5).problems.empty());
}

}  // namespace
}  // namespace nestwalk::gis
