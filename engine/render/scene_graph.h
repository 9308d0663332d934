// The OpenSceneGraph graph of a loaded scene, for drawing (the renderer, `nestwalk export`): the
// terrain as a static cut of its chunk quadtree (terrain_cut.h) and the equipment's instances over the models' nodes (one node per model,
// model_nodes.h, shared by its instances), optionally the volumes as wireframes. The walker never
// touches it.
//
// Ownership: the graph owns its nodes (the model nodes are rebuilt for it from the scene's .osgb
// bytes) and copies everything else it needs; it keeps no reference to the Scene, which may go
// after the call. The caller owns the returned graph.
// Thread safety: as any OSG graph: build and use it on one thread. Graphs built from one Scene
// share no node: each may be drawn from its own thread.
#pragma once

#include "nestwalk/scene/scene.h"
#include "nestwalk/render/terrain_cut.h"

#include <osg/Group>
#include <osg/MatrixTransform>
#include <osg/ref_ptr>

#include <memory>
#include <vector>

namespace nestwalk {

struct SceneGraphOptions {
  bool terrain = true;
  bool equipment = true;
  bool volumes = false;   // outer AABBs (and inner OBBs) as wireframes
  /// The terrain's error and chunk size (its colours: by height, shaded); without a pyramid of its own
  /// the cut takes the scene's (Scene::terrainPyramid and terrainHeightShift).
  TerrainCutOptions terrainCut;
};

// What the renderer needs to find again in a built graph (buildSceneGraph's optional output).
struct SceneGraphParts {
  TerrainCutStats terrainCut;                               // the cut drawn (empty without terrain)
  osg::ref_ptr<osg::MatrixTransform> terrain;               // mesh frame -> local frame
  osg::ref_ptr<osg::Group> equipment;                       // child i: instance i
  std::vector<osg::ref_ptr<osg::Node>> modelNodes;          // node k: model k (buildModelNodes)
  osg::ref_ptr<osg::Group> volumes;
};

// The OpenSceneGraph graph: root Group -> MatrixTransform "local_to_map" (translation by the origin,
// double) over
//  - "terrain": a MatrixTransform moving the mesh frame (metres from sample (0, 0)) to the local
//    frame, over the terrain's cut (buildTerrainCut, terrain_cut.h: one node per drawn chunk);
//  - "equipment": one MatrixTransform per instance (toLocal as a double matrix), named after the
//    instance, over its model's node (the same node pointer for every instance of a model);
//  - "volumes" (options.volumes): the units' outer AABBs (yellow) and inner OBBs (cyan) as lines,
//    lighting off, local frame.
// For drawing and `nestwalk export`; the walker never touches it. Throws std::invalid_argument for
// bad terrain cut options (terrain_cut.h).
osg::ref_ptr<osg::Group> buildSceneGraph(const Scene& scene, const SceneGraphOptions& options = {},
                                         SceneGraphParts* parts = nullptr);

}  // namespace nestwalk
