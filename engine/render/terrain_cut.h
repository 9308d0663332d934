// The terrain as one static surface, for `nestwalk export`: a cut of the chunk quadtree the renderer
// draws (terrain/terrain_chunk.h, the same chunks, simplification and skirts as paged_terrain.h),
// chosen by error instead of by view. From the root down, a chunk quadrant is drawn where its exact
// error is at most maxErrorM, else its child chunk is looked at; at level 0 the coarsest of the
// quadrant's surfaces within maxErrorM (its simplified surface, its refinements, its exact grid,
// which has no error). Skirts close the gaps between quadrants up to log2(kSkirtReachSteps) = 3
// levels apart, so the cut is then refined where neighbours are further apart (a flat next to a
// cliff) until none are: no crack, whatever the terrain. The drawn error never exceeds maxErrorM.
// Frames: the nodes are in the mesh frame (terrain_chunk.h's: metres from the heightfield's sample
// (0, 0)); the caller places them (scene_graph.cpp).
// Ownership: the returned group owns its nodes (every chunk is built, drawn and dropped in turn).
// Thread safety: reads the heightfield (and the pyramid) only; build and use the nodes on one thread.
#pragma once

#include "nestwalk/render/paged_terrain.h"
#include "nestwalk/terrain/heightfield.h"
#include "nestwalk/terrain/terrain_chunk.h"

#include <osg/Group>
#include <osg/ref_ptr>

#include <cstddef>
#include <memory>

namespace nestwalk {

struct TerrainCutOptions {
  double maxErrorM = 0.1;  // the largest vertical error of the cut, metres (0: the exact grid)
  int chunkCells = 64;     // cells per chunk side, a power of two (as RenderOptions::terrainChunkCells)
  double simplifyFraction = kTerrainSimplifyFraction;  // as the renderer's chunks (terrain_chunk.h)
  bool shade = true;                                   // Horn's hillshade baked in, as the renderer's
  terrain::ColourGridReader imagery;                   // draped imagery (empty: colours by height)
  /// The terrain's pyramid (Scene::terrainPyramid), used when chunkCells is its kPyramidTopCells:
  /// chunks of pyramidErrorsFromLevel and coarser take their level samples and errors from it, as
  /// the renderer's do, so a cut of a survey-size terrain reads fine samples only where it draws
  /// level 0 to 3. Null: every error computed from the fine samples (all of them, for the root).
  std::shared_ptr<const terrain::TerrainPyramid> pyramid;
  int pyramidErrorsFromLevel = kPyramidErrorsFromLevel;
  double pyramidHeightShift = 0;  // Scene::terrainHeightShift
};

struct TerrainCutStats {
  std::size_t chunks = 0, quadrants = 0;  // chunks built for drawing, quadrants drawn
  std::size_t surfaceTriangles = 0, skirtTriangles = 0;
  double maxErrorM = 0;                   // the largest exact error of a drawn surface, metres
  int finestLevel = -1, coarsestLevel = -1;
  int balancingRounds = 0;                // refinements of neighbours more than 3 levels apart
};

/// The cut's nodes: one per drawn chunk (its drawn quadrants' ranges, chunk_node.h), in the mesh
/// frame. Throws std::invalid_argument for a negative error, a bad chunk size or a pyramid of
/// another grid; what a pyramid's read throws (InputError naming its file: a damaged page) goes to
/// the caller, which `export` reports (the renderer, which draws on, computes the errors instead).
osg::ref_ptr<osg::Group> buildTerrainCut(const terrain::Heightfield& hf, const TerrainCutOptions& options,
                                         TerrainCutStats* stats = nullptr);

}  // namespace nestwalk
