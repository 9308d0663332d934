// Fuzz target: flythrough scripts (walker/script.h: parseScript), line by line commands.
#include "nestwalk/walker/script.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  nestwalk::fuzz::expectInputErrorOnly([&] { nestwalk::parseScript(nestwalk::fuzz::text(data, size), "fuzz.txt"); });
  return 0;
}
