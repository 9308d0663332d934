// The ground-following part of the methods report (method_report.h): the height of every level of
// the terrain's chunk quadtree (terrain/terrain_chunk.h, chunks of kReportChunkCells cells as the
// renderer cuts them; each level's grid surface, before the renderer's simplification) against the
// full-resolution surface (Heightfield::groundHeight) at random map points, and ns per query.
// Thread safety: keeps no state; the heightfield and the pyramid are only read (the chunks measured
// are built by the call).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace nestwalk {
namespace terrain {
class Heightfield;
class TerrainPyramid;
}

/// The renderer's default chunk size (RenderOptions::terrainChunkCells), which the report measures.
inline constexpr int kReportChunkCells = 64;

/// One row of the terrain table: a level of the chunk quadtree (or the heightfield itself).
struct TerrainLodRow {
  std::string name;           // "full" (Heightfield::groundHeight) or "L0", "L1", ...
  int level = -1;             // -1 for the heightfield
  int step = 1;               // samples per coarse cell side (2^level)
  std::size_t chunks = 0;     // chunks of the level with triangles (from a pyramid: with a valid sample)
  double tableMaxError = 0;   // the level's exact maximum error (terrain::chunkLevelTable; from a
                              // pyramid rounded up to float), metres
  std::size_t points = 0;     // sample points where both surfaces exist
  double maxError = 0, meanError = 0;  // measured |level - full resolution|, metres
  double nsPerQuery = 0;      // the least over the timing repetitions
};

/// A paged terrain's points lie in a window of at most this many cells a side at its centre: at
/// most 9 x 9 of its 256-cell tiles (about 21 MiB), within the tile cache's default budget, so the
/// timed loops measure ground following and not reading tiles from disk.
inline constexpr int kPagedLodWindowCells = 2048;

/// Ground following per level of detail: `points` uniform random map points over the terrain's
/// sample extent (a paged terrain's: its central window of kPagedLodWindowCells; fixed seed), each
/// query loop timed `repetitions` times. With the terrain's pyramid (of its grid), the levels'
/// chunk counts and errors come from its blocks (terrain_pyramid.h's chunkLevelTable) instead of
/// building every chunk of every level.
std::vector<TerrainLodRow> measureTerrainLod(const terrain::Heightfield& hf, const terrain::TerrainPyramid* pyramid,
                                             std::size_t points, int repetitions);

}  // namespace nestwalk
