// Fuzz target: the model catalog (scene/model_catalog.h: parseModelCatalog), types and their
// units, axes, origins and line settings.
#include "nestwalk/scene/model_catalog.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  nestwalk::fuzz::expectInputErrorOnly(
      [&] { nestwalk::parseModelCatalog(nestwalk::fuzz::text(data, size), "/fuzz/catalog.json"); });
  return 0;
}
