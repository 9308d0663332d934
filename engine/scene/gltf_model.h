// Reading glTF 2.0 models (.gltf with external or data-URI buffers and images, and .glb) into an
// OpenSceneGraph graph, so that a glTF model becomes the same scene graph and triangle mesh as a
// model in any format OSG's plugins read (OSG 3.6 has no glTF plugin). The file is parsed by
// tinygltf (Debian's libtinygltf, images decoded by its stb_image); this file turns the parsed
// document into nodes and checks every index and byte range first, so a bad file gives a reason
// that names the glTF object ("meshes[3].primitives[0]: accessor 7 reads past the end of buffer
// view 2") and never a read out of bounds.
//
// What is read:
//   - the default scene (`scene`, else scenes[0], else every node without a parent), its node
//     trees with their transforms (`matrix`, or translation, rotation, scale);
//   - each mesh once (nodes that use the same mesh share its geometry);
//   - primitives of mode TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN, indexed (unsigned byte, short
//     or int) or not; POSITION, NORMAL, TEXCOORD_n and COLOR_0, as floats or normalized integers
//     (KHR_mesh_quantization);
//   - materials: the base colour factor (times the vertex colours where both are present), the base
//     colour texture with its sampler's wrap modes, and alpha blending for alphaMode BLEND;
//   - EXT_mesh_gpu_instancing: a node's mesh drawn at each of its instances' translation, rotation
//     and scale (as `nestwalk export --instancing` writes the equipment).
// Skipped with a note (notes, below): points and lines, and a file's unused or unsupported parts
// (animations, skins, morph targets, cameras, lights). Refused: a file that requires an extension
// not read here (Draco or meshopt compression, for instance: decompress it first).
// Frames and units: the file's own (glTF is metres, +y up, its front towards +z); the model
// catalog turns it into the engine's frame (model_catalog.h: glTF files default to up "y", forward
// "-y").
// Untrusted input: every accessor, buffer view, index and node reference is checked against what
// the file holds before it is read; node graphs must be trees (glTF's rule), so no node is reached
// twice; a file whose nodes would instance more than kMaxInstancedGltfVertices vertices is refused
// before anything is built. Time and memory are bounded by the guarded read (model_file.h), which
// is the only door user files come through.
// Thread safety: no shared state; each call parses its own document.
// Ownership: the returned node is a new graph owned by the caller.
#pragma once

#include <osg/Node>
#include <osg/ref_ptr>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace nestwalk {

/// The most vertices a glTF file's node trees may instance (each node's mesh counted once per
/// node): 64 M, about 1.5 GB of drawn vertices; a larger claim is refused rather than built.
inline constexpr std::uint64_t kMaxInstancedGltfVertices = 64ull << 20;

/// A glTF file read into a scene graph: the node, or why there is none, and what was skipped.
struct GltfModel {
  osg::ref_ptr<osg::Node> node;
  std::string problem;             // "" when the node was built; else the reason, naming the glTF object
  std::vector<std::string> notes;  // what was skipped ("meshes[1].primitives[0]: LINES skipped ...")
};

/// True when `path` ends in .gltf or .glb (any case): the files this reader takes.
bool isGltfPath(const std::string& path);

/// Reads a .gltf or .glb file (told apart by the binary container's magic, not by the name);
/// external buffers and images resolve against the file's folder.
GltfModel readGltfModel(const std::string& path);

/// The same from the file's bytes (the fuzz target's door); external URIs resolve against
/// `folder`.
GltfModel gltfModelFromBytes(std::string_view bytes, const std::string& folder);

}  // namespace nestwalk
