// Fuzz target: the scene file (scene/scene_file.h: parseSceneJson), JSON with its fields checked.
#include "nestwalk/scene/scene_file.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  nestwalk::fuzz::expectInputErrorOnly([&] { nestwalk::parseSceneJson(nestwalk::fuzz::text(data, size), "/fuzz/scene.json"); });
  return 0;
}
