// Fuzz target: glTF 2.0 models (scene/gltf_model.h: gltfModelFromBytes), both containers (.glb and
// .gltf JSON, with data URIs), then the mesh collection every model goes through
// (scene/node_geometry.h). A bad file must end in a problem (the reader's answer) or an InputError
// (the collector's), never in a crash, a hang or another exception. External URIs resolve against
// a folder that does not exist, so a fuzzed file reads no file of the machine's.
#include "nestwalk/scene/gltf_model.h"
#include "nestwalk/scene/node_geometry.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nestwalk::GltfModel model =
      nestwalk::gltfModelFromBytes(nestwalk::fuzz::text(data, size), "/nonexistent-nestwalk-fuzz-folder");
  if (model.node)
    nestwalk::fuzz::expectInputErrorOnly([&] { nestwalk::collectModelGeometry(*model.node, "fuzz.glb"); });
  return 0;
}
