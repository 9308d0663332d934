// Fuzz target: the points CSV of query ground (core/map_points_csv.h), through the CSV reader.
#include "nestwalk/core/map_points_csv.h"
#include "tests/fuzz/fuzz_input.h"

#include <sstream>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(nestwalk::fuzz::text(data, size));
  nestwalk::fuzz::expectInputErrorOnly([&] { nestwalk::readMapPoints(in, "fuzz.csv"); });
  return 0;
}
