// A model file's geometry (model_geometry.h): the guarded read, then the node's mesh.
#include "nestwalk/scene/model_geometry.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/scene/model_file.h"
#include "nestwalk/scene/node_geometry.h"

namespace nestwalk {

TriangleMesh loadModelGeometry(const std::string& path) {
  const ModelFile file = readModelFile(path);
  if (!file.node) throw InputError(modelFileError(path, file.problem));
  return collectModelGeometry(*file.node, path);
}

}  // namespace nestwalk
