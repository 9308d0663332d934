// A triangle mesh in its model frame: the one triangle-mesh type of the engine. Scene loading
// fills it from a model file (scene/model_geometry.h); the mesh trees (mesh_tree.h) are built over
// it; the exact contact tests read it.
// Thread safety: a plain value type; reading it from several threads at once is safe.
#pragma once

#include "nestwalk/geometry/triangle_box.h"
#include "nestwalk/geometry/volumes.h"

#include <array>
#include <cstdint>
#include <vector>

namespace nestwalk {

/// Vertices and triangles (corners by index into `vertices`). Degenerate triangles are allowed;
/// a mesh may have vertices and no triangle at all (a point cloud, a model of lines).
struct TriangleMesh {
  std::vector<Vec3<double>> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;

  Triangle triangle(std::size_t i) const {
    return {vertices[triangles[i][0]], vertices[triangles[i][1]], vertices[triangles[i][2]]};
  }
};

}  // namespace nestwalk
