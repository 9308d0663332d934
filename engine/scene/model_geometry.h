// The geometry of an equipment model as the collision side needs it: every vertex and triangle
// of a file OpenSceneGraph reads, with the file's own transforms applied, in the file's units.
#pragma once

#include "engine/geometry/volumes.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace osg {
class Node;
}

namespace nestwalk {

struct ModelGeometry {
  std::vector<Vec3<double>> vertices;                   // all vertices, under the file's transforms
  std::vector<std::array<std::uint32_t, 3>> triangles;  // indices into vertices (OSG's triangulation)
};

/// Reads a model with osgDB (any format a plugin reads) and collects its geometry.
/// Throws InputError naming the file when it does not exist, no plugin reads it, or it holds no
/// vertex at all. A model with vertices but no triangles (a point cloud, lines) is returned with
/// an empty triangle list.
ModelGeometry loadModelGeometry(const std::string& path);

/// The geometry under an already loaded node (same rules; `name` is used in error messages).
ModelGeometry collectModelGeometry(const osg::Node& node, const std::string& name);

}  // namespace nestwalk
