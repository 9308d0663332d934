// The static terrain tiles as OpenSceneGraph nodes: a TerrainMesh tile level (terrain/terrain_mesh.h)
// as an osg::Geometry, and a tile with all its levels as an osg::LOD switching at the mesh's own
// switch distances. The scene graph's "terrain" group (scene_graph.h) is made of these; the
// renderer's view-bounded terrain draws the chunk quadtree instead (paged_terrain.h).
//
// Frames: the mesh frame of terrain_mesh.h (x = col * dx, y = -row * dy, z = height: metres from
// sample (0, 0), float vertices).
// Ownership: every call returns new nodes owned by the caller (ref_ptr); they keep no reference to
// the mesh.
// Thread safety: the mesh is only read; the nodes are the caller's.
#pragma once

#include "nestwalk/terrain/terrain_mesh.h"

#include <osg/Geometry>
#include <osg/LOD>
#include <osg/ref_ptr>

namespace nestwalk {

/// Geometry of a tile level: the level's valid samples as float vertices (mesh frame),
/// area-weighted vertex normals of the level's own triangles, colours by height over the mesh's
/// height range (when `colours`), triangles as DrawElementsUInt, counter-clockwise seen from above.
/// Null when the level has no triangle.
osg::ref_ptr<osg::Geometry> terrainTileGeometry(const terrain::TerrainMesh& mesh, const terrain::TerrainTile& t, int level,
                                                bool colours = true);

/// A tile's LOD node: child k holds level k's geometry (in an osg::Geode), shown from
/// mesh.switchDistances(t, rule)[k] to the next (the last to infinity), distances from the eye to
/// the centre of mesh.tileBox(t) (the LOD's user-defined centre and radius).
osg::ref_ptr<osg::LOD> terrainTileLod(const terrain::TerrainMesh& mesh, const terrain::TerrainTile& t,
                                      const terrain::LodRule& rule = {}, bool colours = true);

}  // namespace nestwalk
