// A terrain the view graph draws in place of its own quadtree (paged_terrain.h): the hook through
// which a peer is measured beside ours in the same renderer (tools/bench/peers/
// osg_paged_lod_terrain.h: OpenSceneGraph's osg::PagedLOD and DatabasePager). The engine itself
// always draws PagedTerrain.
// Frames: the node's children are in the terrain's mesh frame (terrain_chunk.h: metres from the
// heightfield's sample (0, 0)); the view graph places it as it places its own.
// Ownership: reference counted like every OSG node; the view graph holds one reference.
// Thread safety: as any OSG node (cull and update on the viewer's thread).
#pragma once

#include "nestwalk/render/frame_stats.h"

#include <osg/Group>

namespace nestwalk {

class TerrainNode : public osg::Group {
 public:
  /// The screen changed (pixels per radian of the vertical field of view): the error rule follows.
  virtual void setPixelsPerRadian(double pixelsPerRadian) = 0;
  /// The last cull's figures in PagedTerrain's terms, for the renderer's frame statistics.
  virtual PagedTerrainStats frameStats() const = 0;
};

}  // namespace nestwalk
