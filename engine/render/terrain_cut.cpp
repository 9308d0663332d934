// The static cut of the chunk quadtree (see terrain_cut.h).
#include "nestwalk/render/terrain_cut.h"

#include "nestwalk/render/chunk_node.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <vector>

namespace nestwalk {
namespace {

using terrain::ChunkKey;
using terrain::ChunkLayout;
using terrain::ChunkMesh;

/// Levels apart that the skirts close (terrain_chunk.h: kSkirtReachSteps = 2^3).
constexpr int kMaxLevelGap = 3;
static_assert((1 << kMaxLevelGap) == terrain::kSkirtReachSteps);

/// A chunk quadrant as a region of the grid: quadrant (i & 1) + 2 (j & 1) of chunk (level, i / 2,
/// j / 2), the cells of the chunk (level - 1, i, j) would cover.
struct Region {
  int level, i, j;
  ChunkKey chunk() const { return {level, i / 2, j / 2}; }
  int quadrant() const { return (i & 1) + 2 * (j & 1); }
  friend auto operator<=>(const Region&, const Region&) = default;
};

/// What the selection needs of a chunk: each quadrant's exact error and whether it has triangles.
struct QuadrantErrors {
  std::array<double, 4> error{};
  std::array<bool, 4> drawn{};
};

/// The pyramid's data for a chunk of the cut (TerrainCutOptions::pyramid), nullopt where it is not used.
std::optional<terrain::ChunkPyramidData> pyramidDataFor(const TerrainCutOptions& o, const ChunkKey& key) {
  if (o.chunkCells != terrain::kPyramidTopCells) return std::nullopt;
  return chunkPyramidDataFor(o.pyramid.get(), key, o.pyramidErrorsFromLevel, o.pyramidHeightShift);
}

class Selection {
 public:
  Selection(const terrain::Heightfield& hf, const ChunkLayout& layout, const TerrainCutOptions& o)
      : hf_(hf), layout_(layout), options_(o) {
    geometryOnly_.shade = false;  // colours do not change the geometry or its errors
  }

  /// The regions of a chunk: each non-empty quadrant drawn, or its child chunk's regions.
  void select(const ChunkKey& key, std::set<Region>& out) {
    const QuadrantErrors& e = errors(key);
    for (int q = 0; q < 4; ++q) {
      if (!e.drawn[std::size_t(q)]) continue;
      const Region r{key.level, 2 * key.x + (q & 1), 2 * key.y + (q >> 1)};
      if (key.level == 0 || e.error[std::size_t(q)] <= options_.maxErrorM)
        out.insert(r);
      else
        select({key.level - 1, r.i, r.j}, out);
    }
  }

  /// The regions that replace `r` (level >= 1): its child chunk's, selected as above (a finer
  /// level's error is not always smaller, so the error rule still applies).
  void split(const Region& r, std::set<Region>& out) { select({r.level - 1, r.i, r.j}, out); }

 private:
  const QuadrantErrors& errors(const ChunkKey& key) {
    auto [it, added] = cache_.try_emplace(key);
    if (added) {
      const auto pyramid = pyramidDataFor(options_, key);
      const ChunkMesh m = terrain::buildChunk(hf_, layout_, key, geometryOnly_, options_.simplifyFraction,
                                              pyramid ? &*pyramid : nullptr);
      for (int q = 0; q < 4; ++q) {
        it->second.error[std::size_t(q)] = m.quadrants[std::size_t(q)].maxError;
        it->second.drawn[std::size_t(q)] = m.quadrants[std::size_t(q)].surfaceTriangles > 0;
      }
    }
    return it->second;
  }

  const terrain::Heightfield& hf_;
  const ChunkLayout& layout_;
  const TerrainCutOptions& options_;
  terrain::ChunkShading geometryOnly_;
  std::map<ChunkKey, QuadrantErrors> cache_;
};

/// Regions to split so that no two neighbours are more than kMaxLevelGap levels apart: painted on
/// the grid of level-0 regions, compared with the east and south neighbour of every cell.
std::set<Region> tooCoarse(const std::set<Region>& regions, int cellsX, int cellsY) {
  std::vector<const Region*> cell(std::size_t(cellsX) * std::size_t(cellsY), nullptr);
  for (const Region& r : regions) {
    const int side = 1 << r.level;
    for (int y = r.j * side; y < std::min((r.j + 1) * side, cellsY); ++y)
      for (int x = r.i * side; x < std::min((r.i + 1) * side, cellsX); ++x)
        cell[std::size_t(y) * std::size_t(cellsX) + std::size_t(x)] = &r;
  }
  std::set<Region> split;
  auto compare = [&](const Region* a, const Region* b) {
    if (!a || !b) return;  // holes have no neighbour to meet
    if (a->level - b->level > kMaxLevelGap) split.insert(*a);
    if (b->level - a->level > kMaxLevelGap) split.insert(*b);
  };
  for (int y = 0; y < cellsY; ++y)
    for (int x = 0; x < cellsX; ++x) {
      const Region* here = cell[std::size_t(y) * std::size_t(cellsX) + std::size_t(x)];
      if (x + 1 < cellsX) compare(here, cell[std::size_t(y) * std::size_t(cellsX) + std::size_t(x + 1)]);
      if (y + 1 < cellsY) compare(here, cell[std::size_t(y + 1) * std::size_t(cellsX) + std::size_t(x)]);
    }
  return split;
}

}  // namespace

osg::ref_ptr<osg::Group> buildTerrainCut(const terrain::Heightfield& hf, const TerrainCutOptions& options,
                                         TerrainCutStats* statsOut) {
  if (!(options.maxErrorM >= 0)) throw std::invalid_argument("buildTerrainCut: the error must be >= 0 metres");
  const ChunkLayout layout(hf.cols(), hf.rows(), options.chunkCells);  // checks the chunk size
  if (options.pyramid &&
      (options.pyramid->layout().cols != hf.cols() || options.pyramid->layout().rows != hf.rows()))
    throw std::invalid_argument("buildTerrainCut: the pyramid is not of the heightfield's grid");
  TerrainCutStats stats;

  // Which quadrants: by error from the root, then balanced for the skirts.
  Selection selection(hf, layout, options);
  std::set<Region> regions;
  selection.select(layout.root(), regions);
  const int half = options.chunkCells / 2;
  const int cellsX = (hf.cols() - 2) / half + 1, cellsY = (hf.rows() - 2) / half + 1;  // level-0 regions
  for (std::set<Region> split = tooCoarse(regions, cellsX, cellsY); !split.empty();
       split = tooCoarse(regions, cellsX, cellsY)) {
    ++stats.balancingRounds;
    for (const Region& r : split) {
      regions.erase(r);
      selection.split(r, regions);
    }
  }

  // The nodes, chunk by chunk, each built once with its colours (as PagedTerrain colours them).
  terrain::ChunkShading shading;
  shading.shade = options.shade;
  shading.imagery = options.imagery;
  shading.mapOrigin = hf.origin();
  if (const auto range = hf.heightRange()) {
    shading.heightLo = range->first;
    shading.heightHi = range->second;
  }
  std::map<ChunkKey, std::vector<int>> quadrantsOf;
  for (const Region& r : regions) quadrantsOf[r.chunk()].push_back(r.quadrant());
  osg::ref_ptr<osg::Group> group = new osg::Group;
  group->setName("terrain cut");
  for (const auto& [key, quadrants] : quadrantsOf) {
    const auto pyramid = pyramidDataFor(options, key);
    const ChunkMesh mesh = terrain::buildChunk(hf, layout, key, shading, options.simplifyFraction,
                                               pyramid ? &*pyramid : nullptr);
    std::vector<IndexRange> ranges;
    for (const int q : quadrants) {
      const terrain::ChunkQuadrant& quad = mesh.quadrants[std::size_t(q)];
      IndexRange range{quad.firstIndex, quad.indexCount};
      std::size_t surface = quad.surfaceTriangles;
      double error = quad.maxError;
      if (key.level == 0 && error > options.maxErrorM) {
        // The coarsest finer surface within the error: a refinement, else the exact grid.
        const auto refinement = std::find_if(quad.refinements.begin(), quad.refinements.end(),
                                             [&](const auto& r) { return r.maxError <= options.maxErrorM; });
        if (refinement != quad.refinements.end()) {
          range = {refinement->firstIndex, refinement->indexCount};
          surface = refinement->surfaceTriangles;
          error = refinement->maxError;
        } else if (quad.exactIndexCount > 0) {
          range = {quad.exactFirstIndex, quad.exactIndexCount};
          surface = quad.exactSurfaceTriangles;
          error = 0;
        }
      }
      ranges.push_back(range);
      ++stats.quadrants;
      stats.surfaceTriangles += surface;
      stats.skirtTriangles += quad.skirtTriangles;
      // Its skirts on the chunk's midlines beside a quadrant the cut does not take from this chunk
      // (refined, or without triangles; terrain_chunk.h, "Cracks").
      for (std::size_t k = 0; k < 2; ++k) {
        const int across = terrain::quadrantAcrossMidline(q, int(k));
        const terrain::ChunkSkirt& skirt = quad.midlineSkirts[k];
        if (skirt.indexCount == 0 || std::find(quadrants.begin(), quadrants.end(), across) != quadrants.end()) continue;
        ranges.push_back({skirt.firstIndex, skirt.indexCount});
        stats.skirtTriangles += skirt.indexCount / 3;
      }
      stats.maxErrorM = std::max(stats.maxErrorM, error);
    }
    group->addChild(ChunkNodeMaker(mesh)(ranges, ""));
    ++stats.chunks;
    stats.finestLevel = stats.finestLevel < 0 ? key.level : std::min(stats.finestLevel, key.level);
    stats.coarsestLevel = std::max(stats.coarsestLevel, key.level);
  }
  if (statsOut) *statsOut = stats;
  return group;
}

}  // namespace nestwalk
