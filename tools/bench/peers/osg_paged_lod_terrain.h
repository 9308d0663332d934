// View-bounded terrain the OpenSceneGraph way: the terrain's chunk quadtree (terrain/terrain_chunk.h)
// as a tree of osg::PagedLOD nodes paged by the viewer's osgDB::DatabasePager, next to the engine's
// own quadtree (paged_terrain.h) so that the two can be measured side by side (both were tried,
// and the quadtree kept: it draws fewer triangles at the same 1 px error). A peer: only `nestwalk
// bench render` draws it, through the renderer's terrain hook (render/terrain_node.h,
// osgPagedLodMaker below); the product always draws PagedTerrain.
//
// The tree: each non-empty chunk is a PagedLOD (ChunkLod below) with
//   child 0: the chunk's whole mesh (one osg::Geometry: float positions relative to the chunk's
//            offset under a MatrixTransform, RGBA8 colours, 16-bit indices where they fit, VBOs);
//   child 1: the file "<level>_<x>_<y>.nwchunk", which the pseudo-loader registered for the
//            extension "nwchunk" (an osgDB::ReaderWriter; no file is ever opened) answers with a
//            Group of the chunk's children's PagedLODs, each built with terrain::buildChunk.
// The loader finds the terrain it builds for in the PagedLOD's database options: their user data is
// the terrain's shared Source (heightfield, layout, shading), so several terrains may live at once.
// Level-0 chunks, and chunks whose error is 0, have no file child. With simplification
// (simplifyFraction > 0, terrain_chunk.h) a level-0 chunk's child 1 is instead its exact grid, built
// with it and kept in memory (a plain LOD switch on the same rule). A chunk that is all holes is
// left out of its parent's Group (as PagedTerrain never draws one, nor anything below it).
//
// Selection: PagedLOD replaces the whole chunk by its (up to four) children at once (PagedTerrain
// does it quadrant by quadrant); the skirts of buildChunk close the gaps between levels up to 3
// apart. The error rule is PagedTerrain's, projected vertical error at most maxPixels with
// pixelsPerRadian: the coarse chunk may be drawn where the eye is at least
//   D = maxError * pixelsPerRadian / maxPixels
// metres from every point of it (maxError: the chunk's exact error, metres). PagedLOD measures
// the distance from one centre (RangeMode DISTANCE_FROM_EYE_POINT), so the threshold between its
// two children is D + R, R the radius of the sphere around the chunk's box (surface and skirts)
// centred on the box's centre: eye distance to the centre >= D + R gives distance >= D to every
// drawn point. This is conservative: it refines wherever one point of the sphere could come within
// D (a chunk seen edge-on, or a low eye beside a tall chunk, refines sooner than PagedTerrain's
// block-by-block bound would), so it draws more triangles for the same 1 px. maxPixels 0 refines
// everywhere (full resolution). Ranges follow setPixelsPerRadian at the next cull.
//
// Loading: a chunk whose file child is in range and not yet loaded is drawn itself (a stand-in) and
// its children are requested from the pager (priority: nearer in its range first); the pager loads
// them on its own thread and merges them in a later frame's update traversal, so no frame waits
// for a chunk. waitUntilIdle() waits for the pager to finish what has been asked for. A frame is
// complete (the rule's full answer) when its cull wanted nothing: lastStats().chunksWanted == 0.
//
// Memory: each resident chunk is counted at twice its nodes' arrays (ChunkNodeMaker::bytes(), as PagedTerrain
// counts it: OSG's copy and the GL driver's). The budget (budgetBytes, 0: defaultTerrainBudgetBytes())
// is handed to the pager as its target number of PagedLODs (budget / the root chunk's count; the
// chunks of one tree have about as many vertices), set on the pager at the first cull; the pager
// expires the children of PagedLODs not drawn recently when there are more. It is the pager's own
// policy: a target, not a bound (PagedTerrain's budget is a bound).
//
// Frames: the node's children are in the mesh frame of terrain_chunk.h (metres from the heightfield's
// sample (0, 0)); the caller places it with a transform (view_graph.cpp).
//
// Ownership and threads: the Source shares the heightfield (immutable, read by the pager's thread
// and the constructor) and owns the imagery reader, which it calls under a mutex of its own, one
// read at a time (the constructor builds the root; then the pager's database threads). Cull and
// update on one thread (the viewers here are SingleThreaded); per-frame statistics are written by the
// cull, the resident and load counts (atomics) also by the pager's thread.
#pragma once

#include "nestwalk/render/paged_terrain.h"
#include "nestwalk/render/terrain_node.h"
#include "nestwalk/render/view_renderer.h"
#include "nestwalk/terrain/heightfield.h"
#include "nestwalk/terrain/terrain_chunk.h"

#include <osg/Group>
#include <osg/ref_ptr>

#include <cstdint>
#include <memory>
#include <vector>

namespace nestwalk::bench {

/// What the last cull drew (per frame) and what is resident (since the node was made).
struct PagedLodTerrainStats {
  std::size_t chunksDrawn = 0;       // chunks whose mesh the cull visited (inside the frustum)
  std::size_t trianglesDrawn = 0;    // surface and skirt triangles of the drawn chunks
  std::size_t skirtTrianglesDrawn = 0;
  double maxErrorM = 0;              // largest exact error of a drawn chunk, metres
  /// Its largest projected error, pixels, by PagedTerrain's measure (the largest over the chunk's
  /// blocks of error * pixelsPerRadian / distance to the block's box), so the two compare.
  double maxErrorPx = 0;
  std::size_t chunksWanted = 0;      // chunks whose children were in range and not loaded (stand-ins)
  int finestLevel = -1, coarsestLevel = -1;  // of the drawn chunks
  std::size_t chunksResident = 0;    // chunk nodes alive (in the graph, or just loaded)
  std::size_t residentBytes = 0;     // counted as above (twice the arrays)
  std::uint64_t chunksLoaded = 0;    // built since the node was made (the root included)
  double loadSeconds = 0;            // time spent building chunks since the node was made
};

class PagedLodTerrain : public TerrainNode {
 public:
  /// The shared state the pseudo-loader builds from (defined in the .cpp).
  class Source;

  /// Builds the root chunk (so the first frame has terrain) and registers the "nwchunk"
  /// pseudo-loader with osgDB (once per process). Throws std::invalid_argument for bad options (as
  /// PagedTerrain).
  /// The own quadtree's options (paged_terrain.h): the same chunks and rule; `loading` is not used
  /// (the DatabasePager always loads in the background).
  PagedLodTerrain(std::shared_ptr<const terrain::Heightfield> heightfield, PagedTerrainOptions options);
  ~PagedLodTerrain() override;
  PagedLodTerrain(const PagedLodTerrain&) = delete;
  PagedLodTerrain& operator=(const PagedLodTerrain&) = delete;

  const char* libraryName() const override { return "nestwalk"; }
  const char* className() const override { return "PagedLodTerrain"; }
  void traverse(osg::NodeVisitor& nv) override;

  const PagedLodTerrainStats& lastStats() const { return stats_; }
  /// The last cull's figures in PagedTerrain's terms (standIns = chunksWanted), for the renderer.
  PagedTerrainStats frameStats() const override;
  const terrain::ChunkLayout& layout() const;
  std::size_t budgetBytes() const { return budget_; }
  /// The pager's target number of PagedLODs derived from the budget (see "Memory").
  unsigned maxPagedLods() const { return maxPagedLods_; }
  /// The screen changed: the ranges follow at the next cull.
  void setPixelsPerRadian(double pixelsPerRadian) override;
  /// Waits until the pager that the last cull used has no request left to load (or compile), at most
  /// maxSeconds; true when it is idle (also when no cull has run yet or there is no pager). What it
  /// loaded is merged by the next frame's update traversal.
  bool waitUntilIdle(double maxSeconds = 30.0) const;
  /// The chunks the last cull drew (their meshes, inside the frustum).
  const std::vector<terrain::ChunkKey>& drawnChunks() const { return drawn_; }

 private:
  osg::ref_ptr<Source> source_;
  std::size_t budget_ = 0;
  unsigned maxPagedLods_ = 0;
  PagedLodTerrainStats stats_;
  std::vector<terrain::ChunkKey> drawn_;
};

/// A maker for ViewRenderer that draws a PagedLodTerrain and hands it to `made` (the caller's, to
/// wait on its pager and read its own figures).
TerrainNodeMaker osgPagedLodMaker(osg::ref_ptr<PagedLodTerrain>* made);

}  // namespace nestwalk::bench
