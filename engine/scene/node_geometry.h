// The geometry under an OpenSceneGraph node: every vertex and triangle, with the graph's own
// transforms applied. Scene's side of model reading (the loader collects each model's mesh once);
// the simulation layers take the mesh from the scene (SceneModel::mesh) and never see a node.
// Units: the model file's own frame and units (the type's transform to metres is applied later,
// scene.h).
// Thread safety: collectModelGeometry only reads the node (nothing in it changes) and keeps
// nothing.
#pragma once

#include "nestwalk/geometry/triangle_mesh.h"

#include <osg/Node>

#include <string>

namespace nestwalk {

/// Every vertex a primitive refers to, under the node's transforms, and OSG's triangulation of
/// every primitive set (indices into the vertices). `name` is used in error messages.
/// Throws InputError when the node holds no vertex at all, or a vertex that is not finite (NaN,
/// infinity). A node with vertices but no triangles (a point cloud, lines) gives an empty triangle
/// list.
TriangleMesh collectModelGeometry(const osg::Node& node, const std::string& name);

}  // namespace nestwalk
