// What one rendered frame did: the renderer's times and counts, the paged terrain's figures (what
// its cull drew and what its cache holds) and nested culling's counts. Filled by the renderer
// (view_renderer.h), the paged terrain (paged_terrain.h) and the culler (nested_cull.h); read by
// the run's files (report/render_record.h) and the benchmarks.
// Units: milliseconds and microseconds as named, metres, pixels, bytes.
#pragma once

#include <cstddef>
#include <cstdint>

namespace nestwalk {

/// What the last cull drew and what the cache holds.
struct PagedTerrainStats {
  std::size_t chunksDrawn = 0;       // chunk quadrants drawn
  std::size_t trianglesDrawn = 0;    // surface and skirt triangles of the drawn chunks
  std::size_t skirtTrianglesDrawn = 0;
  std::size_t refinedTrianglesDrawn = 0;  // of level-0 quadrants drawn as a refinement (terrain/terrain_chunk.h)
  std::size_t exactTrianglesDrawn = 0;    // of level-0 quadrants drawn as their exact grid
  double maxErrorM = 0;              // largest exact error of a drawn quadrant, metres
  double maxErrorPx = 0;             // its largest projected error, pixels (paged_terrain.h's rule)
  std::size_t standIns = 0;          // drawn quadrants over maxPixels whose child was not resident
  std::size_t chunksResident = 0;
  std::size_t residentBytes = 0;     // as paged_terrain.h counts them (twice the arrays)
  std::size_t chunksWanted = 0;      // asked for and not yet resident
  std::size_t chunksMerged = 0;      // built chunks this frame made drawable (within its merge bound, or one)
  std::size_t bytesMerged = 0;       // their bytes (as residentBytes counts them)
  std::uint64_t chunksLoaded = 0;    // built since the node was made
  std::uint64_t chunksEvicted = 0;
  double loadSeconds = 0;            // time spent building chunks since the node was made
  int finestLevel = -1, coarsestLevel = -1;  // of the drawn chunks
  // Imagery tiles (imagery_tiles.h; zero without them):
  std::size_t imageryTilesResident = 0, imageryBytes = 0;  // bytes counted as the cache counts them (in residentBytes too)
  std::size_t imageryTilesWanted = 0;  // drawn parts whose tile was loading (a coarser one stood in)
  std::size_t imageryRefinements = 0;  // quadrants drawn finer than the error rule asks, for their texels
  int finestTexelLevelDrawn = 0;       // the finest texel level drawn (imagery_tiles.h's levels)
};

/// What one culling frame did.
struct CullCounts {
  std::uint64_t instances = 0;    // tested
  std::uint64_t aabbOutside = 0;  // culled by the outer AABB test
  std::uint64_t aabbInside = 0;   // accepted by the AABB (fully inside every plane), OBB not tested
  std::uint64_t obbTested = 0;    // undecided by the AABB, went to the OBB
  std::uint64_t obbOutside = 0;   // culled by the OBB
  std::uint64_t visible = 0;      // drawn
  double micros = 0;              // time of the test (update() or sphereCull), microseconds
};

struct RenderFrameStats {
  double cullMs = 0;       // event, update and cull traversals (nested culling included)
  double drawMs = 0;       // draw traversal until the GL has finished (glFinish)
  double readbackMs = 0;   // glReadPixels into the image
  double totalMs = 0;      // the whole frame
  std::uint64_t triangles = 0;    // triangles drawn (OSG's scene statistics)
  std::uint64_t terrainChunks = 0;  // terrain chunks drawn
  double terrainErrorM = 0;       // largest vertical error (m) of the terrain chunks drawn
  double terrainErrorPx = 0;      // largest projected vertical error of a drawn chunk, pixels
  PagedTerrainStats terrain;      // the paged terrain's own figures for this frame (paged_terrain.h)
  CullCounts cull;                // nested culling's counts (all zero when it is off)
};

}  // namespace nestwalk
