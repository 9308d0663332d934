// The ground-following part of the methods report (see terrain_lod_table.h).
#include "nestwalk/report/terrain_lod_table.h"

#include "nestwalk/core/random.h"
#include "nestwalk/core/stopwatch.h"
#include "nestwalk/terrain/heightfield.h"
#include "nestwalk/terrain/terrain_chunk.h"
#include "nestwalk/terrain/terrain_pyramid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace nestwalk {
namespace {

constexpr std::uint64_t kSeed = 0x7e11a1d;

/// A query point in the mesh frame (metres from sample (0, 0)).
struct LodPoint {
  double x, y;
};

/// ns per call of `query` over `points` (the least over `repetitions` loops).
template <class Query>
double nsPerQuery(const std::vector<LodPoint>& points, int repetitions, const Query& query) {
  if (points.empty()) return std::numeric_limits<double>::quiet_NaN();
  return 1e9 / double(points.size()) * leastSeconds(repetitions, [&] {
    double sum = 0;
    for (const LodPoint& p : points) sum += query(p);
    keepResult(sum);
  });
}

}  // namespace

std::vector<TerrainLodRow> measureTerrainLod(const terrain::Heightfield& hf, const terrain::TerrainPyramid* pyramid,
                                             std::size_t count, int repetitions) {
  static_assert(kReportChunkCells == terrain::kPyramidTopCells, "the pyramid's blocks are the report's chunks'");
  const terrain::ChunkLayout layout(hf.cols(), hf.rows(), kReportChunkCells);
  const Eigen::Vector2d origin = hf.origin();
  // The points' window, in cells from sample (0, 0).
  int c0 = 0, r0 = 0, cells = hf.cols() - 1, rowCells = hf.rows() - 1;
  if (hf.paged()) {
    const int w = std::min(cells, kPagedLodWindowCells), h = std::min(rowCells, kPagedLodWindowCells);
    c0 = (cells - w) / 2;
    r0 = (rowCells - h) / 2;
    cells = w;
    rowCells = h;
  }

  // Points over the window, with their full-resolution height (those without ground dropped).
  SplitMix64 rng(kSeed);
  std::vector<LodPoint> points;
  std::vector<double> reference;
  points.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    // Mesh frame: rows go south.
    const double x = (c0 + rng.uniform(0, cells)) * hf.dx(), y = -(r0 + rng.uniform(0, rowCells)) * hf.dy();
    const std::optional<double> h = hf.groundHeight(origin.x() + x, origin.y() + y);
    if (!h) continue;
    points.push_back({x, y});
    reference.push_back(*h);
  }

  std::vector<TerrainLodRow> rows;
  TerrainLodRow full;
  full.name = "full";
  full.points = points.size();
  full.nsPerQuery = nsPerQuery(points, repetitions, [&](const LodPoint& p) {
    return hf.groundHeight(origin.x() + p.x, origin.y() + p.y).value_or(0.0);
  });
  rows.push_back(full);

  const bool fromPyramid =
      pyramid && pyramid->layout().cols == hf.cols() && pyramid->layout().rows == hf.rows();
  for (const terrain::ChunkLevelStats& stats :
       fromPyramid ? terrain::chunkLevelTable(*pyramid) : terrain::chunkLevelTable(hf, layout)) {
    TerrainLodRow row;
    row.name = "L" + std::to_string(stats.level);
    row.level = stats.level;
    row.step = stats.step;
    row.chunks = stats.chunks;
    row.tableMaxError = stats.maxError;
    double sum = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const std::optional<double> h = terrain::levelHeightAt(hf, stats.level, points[i].x, points[i].y);
      if (!h) continue;  // a hole of the coarse level: coverage, not height
      const double e = std::abs(*h - reference[i]);
      row.maxError = std::max(row.maxError, e);
      sum += e;
      ++row.points;
    }
    row.meanError = row.points ? sum / double(row.points) : 0.0;
    row.nsPerQuery = nsPerQuery(points, repetitions, [&](const LodPoint& p) {
      return terrain::levelHeightAt(hf, stats.level, p.x, p.y).value_or(0.0);
    });
    rows.push_back(row);
  }
  return rows;
}

}  // namespace nestwalk
