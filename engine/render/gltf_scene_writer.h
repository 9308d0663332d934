// A drawn scene written as glTF 2.0 (`nestwalk export SCENE OUT.glb|.gltf`): the OpenSceneGraph
// graph the renderer draws (scene_graph.h: the terrain's chunk cut, the equipment, the volumes'
// wireframes) turned into glTF nodes, meshes, materials and images, and written by tinygltf as a
// .glb (one file: JSON and binary chunks) or a .gltf with its buffer as a data URI (one file too).
//
// What is written:
//   - a node per OSG group and transform (its matrix, when not the identity), in the graph's tree;
//     a node that OSG shares between parents (a model's node under each of its instances) is
//     written once per path, since glTF nodes form trees, but its meshes once: every instance of a
//     model refers to the same glTF meshes;
//   - per geometry one primitive per kind: its triangles (OSG's triangles, strips, fans, quads and
//     polygons as one indexed triangle list), its lines (lines, strips and loops as line pairs) and
//     its points; positions with their bounds, unit normals, vertex colours (floats or normalized
//     bytes) and the first texture coordinates;
//   - a material per distinct drawing state: the base colour (an overall colour, else the OSG
//     material's diffuse), the unit-0 texture with its wrap modes, alpha blending, and
//     KHR_materials_unlit where OSG draws without lighting (the terrain's baked shading, the
//     wireframes); metallic 0, roughness 1, double-sided unless OSG culls back faces there (it
//     culls none by default; the renderer culls the terrain's);
//   - images as JPEG where opaque, PNG where not, encoded by OSG's own image plugins, in the buffer;
//   - with GltfSceneInfo::instancing, a group's transforms over one shared node (the equipment's
//     instances of a model) as one node per mesh of that node with EXT_mesh_gpu_instancing
//     (translation, rotation, scale per instance; required by the file), when every instance's
//     transform is exactly those three.
// Frames: the graph is in the scene's local frame (metres, z up, x east, y north, the map origin
// subtracted); glTF is +y up. One root node, "nestwalk_local_frame", turns z up into y up
// (glTF = (x, z, -y) of local), and the asset's extras say how to go back to the map:
// extras.nestwalk = {"map_origin": [x, y, z], "crs": WKT, "crs_name": ..., "frame": a sentence}.
// Texture coordinates: OSG's t runs from an image's first stored row, which its plugins write as the
// picture's bottom; glTF's v runs from the top: v = 1 - t.
// Thread safety: reads the graph only; OSG's image plugins are used from the calling thread.
#pragma once

#include <Eigen/Core>
#include <osg/Node>

#include <cstddef>
#include <string>
#include <vector>

namespace nestwalk {

/// What the asset's extras record about the scene.
struct GltfSceneInfo {
  Eigen::Vector3d mapOrigin = Eigen::Vector3d::Zero();  // the map point of the local origin (Scene::origin)
  std::string crsWkt, crsName;                          // the terrain's CRS ("" when unknown)
  std::string generator = "nestwalk";
  /// Instances as EXT_mesh_gpu_instancing (see below) rather than a node each: far fewer draw
  /// calls for a browser (three.js reads it), but readers without the extension refuse the file.
  bool instancing = false;
};

/// The fewest transforms over one shared node that are written as instances (instancing).
inline constexpr std::size_t kMinGltfInstances = 2;

/// JPEG quality of opaque images (OSG's jpeg plugin, 0-100): 90 keeps a draped orthophoto's detail
/// at about a fifth of PNG's size.
inline constexpr int kGltfJpegQuality = 90;

struct GltfWriteStats {
  std::size_t nodes = 0, meshes = 0, primitives = 0, materials = 0, images = 0;
  std::size_t triangles = 0, lineSegments = 0, points = 0;  // as drawn: an instance's count once per instance
  std::size_t bytes = 0;                                    // the file's size
  std::vector<std::string> notes;                           // what was left out, and why
};

/// Writes `root` (local frame, see above) to `path` as a .glb (`binary`) or a .gltf with its buffer
/// embedded, directly (the caller writes to a temporary name and renames). Throws
/// std::runtime_error when the file cannot be written or an image cannot be encoded.
GltfWriteStats writeGltfScene(const osg::Node& root, const GltfSceneInfo& info, const std::string& path, bool binary);

}  // namespace nestwalk
