// The ground-following part of the methods report (method_report.h): the height of every level of
// the terrain's chunk quadtree (terrain/terrain_chunk.h, chunks of kReportChunkCells cells as the
// renderer cuts them; each level's grid surface, before the renderer's simplification) against the
// full-resolution surface (Heightfield::groundHeight) at random map points, and ns per query.
// Thread safety: keeps no state; the heightfield is only read (the chunks measured are built by the
// call).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace nestwalk {
namespace terrain {
class Heightfield;
}

/// The renderer's default chunk size (RenderOptions::terrainChunkCells), which the report measures.
inline constexpr int kReportChunkCells = 64;

/// One row of the terrain table: a level of the chunk quadtree (or the heightfield itself).
struct TerrainLodRow {
  std::string name;           // "full" (Heightfield::groundHeight) or "L0", "L1", ...
  int level = -1;             // -1 for the heightfield
  int step = 1;               // samples per coarse cell side (2^level)
  std::size_t chunks = 0;     // chunks of the level with triangles
  double tableMaxError = 0;   // the level's exact maximum error (terrain::chunkLevelTable), metres
  std::size_t points = 0;     // sample points where both surfaces exist
  double maxError = 0, meanError = 0;  // measured |level - full resolution|, metres
  double nsPerQuery = 0;      // the least over the timing repetitions
};

/// Ground following per level of detail: `points` uniform random map points over the terrain's
/// sample extent (fixed seed), each query loop timed `repetitions` times.
std::vector<TerrainLodRow> measureTerrainLod(const terrain::Heightfield& hf, std::size_t points, int repetitions);

}  // namespace nestwalk
