// A loaded scene written as glTF 2.0, as `nestwalk export` and `nestwalk publish` write it: the
// scene graph the renderer draws (scene_graph.h) with the scene's imagery draped on the terrain's
// cut as textures (terrain/terrain_imagery.h, as the renderer drapes it), the terrain unlit (its
// colours carry their shading) and single-sided (the renderer culls its back faces), the parts in
// the local frame, and the map origin and CRS in the
// asset's extras (gltf_scene_writer.h).
// Thread safety: builds and writes on the calling thread (OSG's image plugins, GDAL for imagery).
#pragma once

#include "nestwalk/render/gltf_scene_writer.h"
#include "nestwalk/render/scene_graph.h"
#include "nestwalk/scene/scene.h"

#include <string>

namespace nestwalk {

struct SceneGltf {
  GltfWriteStats gltf;
  SceneGraphParts parts;  // what was built (the terrain cut's figures)
};

/// Writes `scene` drawn with `options` (terrain, equipment, volumes, the cut's error) to `path`, a
/// .glb (`binary`) or a .gltf with its buffer embedded, directly (callers write to a temporary name);
/// with `instancing`, each model's instances as EXT_mesh_gpu_instancing (gltf_scene_writer.h).
/// Throws what buildSceneGraph throws, InputError for imagery that cannot be read, and
/// std::runtime_error when the file cannot be written.
SceneGltf writeSceneGltf(const Scene& scene, SceneGraphOptions options, const std::string& path, bool binary,
                         bool instancing = false);

}  // namespace nestwalk
