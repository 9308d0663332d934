// Fuzz target: the pairs CSV of query overlap (geometry/box_pairs_csv.h), each pair then tested
// with the nested three-stage test, as the command does.
#include "nestwalk/geometry/box_pairs_csv.h"
#include "nestwalk/geometry/nested.h"
#include "tests/fuzz/fuzz_input.h"

#include <sstream>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(nestwalk::fuzz::text(data, size));
  nestwalk::fuzz::expectInputErrorOnly([&] {
    for (const nestwalk::BoxPair& p : nestwalk::readBoxPairs(in, "fuzz.csv")) nestwalk::testBoxPair(p.a, p.b);
  });
  return 0;
}
