// The geometry of an equipment model as the collision side needs it: every vertex and triangle
// of a file OpenSceneGraph reads, with the file's own transforms applied, in the file's units.
// Units: the model file's own frame and units (the type's transform to metres is applied later,
// scene.h).
// Thread safety: loadModelGeometry reads through readModelFile (model_file.h: one thread at a
// time).
#pragma once

#include "nestwalk/geometry/triangle_mesh.h"

#include <string>

namespace nestwalk {

/// Reads a model (readModelFile, model_file.h: guarded) and collects its geometry
/// (collectModelGeometry, node_geometry.h): every vertex a primitive refers to, under the file's
/// transforms, and OSG's triangulation of every primitive set (indices into the vertices).
/// Throws InputError (modelFileError's message) when it does not exist, no plugin reads it, the
/// read fails, or it holds no vertex at all, or a vertex that is not finite (NaN, infinity). A
/// model with vertices but no triangles (a point cloud, lines) is returned with an empty triangle
/// list.
TriangleMesh loadModelGeometry(const std::string& path);

}  // namespace nestwalk
