// The geometry of an equipment model as the collision side needs it: every vertex and triangle
// of a file OpenSceneGraph reads, with the file's own transforms applied, in the file's units.
#pragma once

#include "nestwalk/geometry/triangle_mesh.h"

#include <osg/Node>
#include <osg/ref_ptr>

#include <string>

namespace nestwalk {

/// A model file read with osgDB (any format a plugin reads): the node, or why there is none
/// ("no such file", "is a folder", "no OpenSceneGraph plugin reads it", the plugin's message).
/// Every model nestwalk loads is read here.
struct ModelFile {
  osg::ref_ptr<osg::Node> node;
  std::string problem;  // "" when the node was read
};
ModelFile readModelFile(const std::string& path);

/// Reads a model with osgDB (any format a plugin reads) and collects its geometry: every vertex a
/// primitive refers to, under the file's transforms, and OSG's triangulation of every primitive
/// set (indices into the vertices).
/// Throws InputError naming the file when it does not exist, no plugin reads it, or it holds no
/// vertex at all. A model with vertices but no triangles (a point cloud, lines) is returned with
/// an empty triangle list.
TriangleMesh loadModelGeometry(const std::string& path);

/// The geometry under an already loaded node (same rules; `name` is used in error messages).
TriangleMesh collectModelGeometry(const osg::Node& node, const std::string& name);

}  // namespace nestwalk
