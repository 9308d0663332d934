// The OSG nodes of a terrain chunk (terrain/terrain_chunk.h) for both ways of paging it: the own
// quadtree (paged_terrain.h) draws one node per quadrant surface, the PagedLOD tree
// (the benchmarks' peer, tools/bench/peers/osg_paged_lod_terrain.h) one node per chunk (its quadrants' ranges together).
//
// A node is the chunk's offset as a MatrixTransform over one Geode with one Geometry: the chunk's
// float positions (metres, relative to the offset) drawn from vertex buffer objects, with the given
// index ranges as one triangle list (16-bit indices where the chunk has at most 65535 vertices). Its
// colours are the chunk's texture (terrain_chunk.h, "Shading": one texel per kept sample, linear
// between texel centres, no mipmaps: see chunk_node.cpp) on texture unit 0, over white; a mesh without
// a texture gives its vertex colours instead. Every node made by one ChunkNodeMaker shares the same
// arrays and texture, so the surfaces of one chunk cost their indices only. Named "chunk LEVEL/X/Y" + the given suffix (tests
// and the scene graph's readers tell the surfaces apart by it).
//
// Imagery coordinates (when a span is given, for a mesh built without base colours): the vertex
// colours (the light) stay, and texture unit 0 gets each vertex's place in the chunk's nominal area,
// u = x / spanX east and v = -y / spanY south of the chunk's first sample (mesh-frame metres over
// the area's sides: chunkCells 2^level samples' spacing), for the imagery tiles the renderer lays
// over it with a texture matrix (imagery_tiles.h).
//
// Ownership: the maker copies the mesh's positions and colours once; it reads the mesh's indices
// while it lives (the mesh must outlive it). Not thread-safe (one maker, one thread).
#pragma once

#include "nestwalk/terrain/terrain_chunk.h"

#include <osg/Array>
#include <osg/MatrixTransform>
#include <osg/StateSet>
#include <osg/ref_ptr>

#include <cstddef>
#include <string>
#include <vector>

namespace nestwalk {

/// A range of a chunk's index array: `count` indices from `first`.
struct IndexRange {
  std::size_t first = 0, count = 0;
};

class ChunkNodeMaker {
 public:
  explicit ChunkNodeMaker(const terrain::ChunkMesh& mesh);
  /// With imagery coordinates over a chunk area of spanX x spanY metres (see above).
  ChunkNodeMaker(const terrain::ChunkMesh& mesh, double spanX, double spanY);
  /// A node drawing the ranges (in order), named "chunk L/X/Y" + suffix.
  osg::ref_ptr<osg::MatrixTransform> operator()(const std::vector<IndexRange>& ranges, const std::string& suffix) const;
  /// The bytes of the arrays the nodes made so far hold: the shared vertex arrays and texture once,
  /// each node's indices (one copy: what the GL's buffers hold once more).
  std::size_t bytes() const { return sharedBytes_ + indexBytes_; }

 private:
  const terrain::ChunkMesh& mesh_;
  osg::ref_ptr<osg::Vec3Array> positions_;
  osg::ref_ptr<osg::Vec4ubArray> colours_;
  osg::ref_ptr<osg::Vec2Array> texCoords_;  // null without a texture
  osg::ref_ptr<osg::StateSet> textureState_;
  bool perVertexColours_ = true;
  std::size_t sharedBytes_ = 0;
  mutable std::size_t indexBytes_ = 0;
};

}  // namespace nestwalk
