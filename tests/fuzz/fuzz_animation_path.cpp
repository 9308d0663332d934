// Fuzz target: osgviewer AnimationPath files (walker/animation_path.h: scriptFromAnimationPath).
#include "nestwalk/walker/animation_path.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  nestwalk::fuzz::expectInputErrorOnly(
      [&] { nestwalk::scriptFromAnimationPath(nestwalk::fuzz::text(data, size), "fuzz.path"); });
  return 0;
}
