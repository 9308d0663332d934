// The ground-following part of the methods report (method_report.h): the height of every level of
// the terrain mesh (terrain/terrain_mesh.h, tiles of 128 cells as the renderer cuts them) against
// the full-resolution surface (Heightfield::groundHeight) at random map points, and ns per query.
#include "nestwalk/report/terrain_lod_table.h"

#include "nestwalk/core/random.h"
#include "nestwalk/core/stopwatch.h"
#include "nestwalk/terrain/heightfield.h"
#include "nestwalk/terrain/terrain_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace nestwalk {
namespace {

constexpr int kTileCells = 128;  // SceneGraphOptions::terrainTileCells' default
constexpr std::uint64_t kSeed = 0x7e11a1d;

/// A query point: map (x, y), and its tile of the mesh.
struct LodPoint {
  double x, y;
  const terrain::TerrainTile* tile;
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

std::vector<TerrainLodRow> measureTerrainLod(const terrain::Heightfield& hf, std::size_t count, int repetitions) {
  const terrain::TerrainMesh mesh(hf, terrain::TerrainMeshOptions{kTileCells, 0});
  const Eigen::Vector2d origin = hf.origin();
  const double width = (hf.cols() - 1) * hf.dx(), height = (hf.rows() - 1) * hf.dy();

  // Points over the sample extent, with their full-resolution height (those without ground dropped).
  SplitMix64 rng(kSeed);
  std::vector<LodPoint> points;
  std::vector<double> reference;
  points.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double lx = rng.uniform(0, width), ly = -rng.uniform(0, height);  // local frame: rows go south
    const std::optional<double> h = hf.groundHeight(origin.x() + lx, origin.y() + ly);
    if (!h) continue;
    const int tx = std::min(int(lx / hf.dx()) / kTileCells, mesh.tilesX() - 1);
    const int ty = std::min(int(-ly / hf.dy()) / kTileCells, mesh.tilesY() - 1);
    points.push_back({lx, ly, &mesh.tile(tx, ty)});
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

  for (const terrain::TerrainLevelStats& stats : mesh.levelTable()) {
    TerrainLodRow row;
    row.name = "L" + std::to_string(stats.level);
    row.level = stats.level;
    row.step = stats.step;
    row.tiles = stats.tiles;
    row.tableMaxError = stats.maxError;
    std::vector<LodPoint> inLevel;  // the points whose tile has this level
    double sum = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (points[i].tile->levels <= stats.level) continue;
      inLevel.push_back(points[i]);
      const std::optional<double> h = mesh.heightAt(*points[i].tile, stats.level, points[i].x, points[i].y);
      if (!h) continue;  // a hole of the coarse level: coverage, not height
      const double e = std::abs(*h - reference[i]);
      row.maxError = std::max(row.maxError, e);
      sum += e;
      ++row.points;
    }
    row.meanError = row.points ? sum / double(row.points) : 0.0;
    row.nsPerQuery = nsPerQuery(inLevel, repetitions, [&](const LodPoint& p) {
      return mesh.heightAt(*p.tile, stats.level, p.x, p.y).value_or(0.0);
    });
    rows.push_back(row);
  }
  return rows;
}

}  // namespace nestwalk
