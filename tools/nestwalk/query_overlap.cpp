// nestwalk query overlap PAIRS.csv: the nested three-stage verdict for pairs of boxes.
// Input: geometry/box_pairs_csv.h (id, box A's centre, axes and half extents, then box B's).
// Output: id,overlap,stage,axis (see testBoxPair in engine/geometry/nested.h).
// The pairs are read kChunkPairs at a time and each chunk is answered by testBoxPairs (obb_batch.h:
// float SIMD lanes, the lanes it cannot vouch for answered by testBoxPair itself; the answers are
// testBoxPair's) while it is still in the cache; --scalar tests them one at a time with testBoxPair
// instead (the timing reference). Nothing is printed before the last row has been read and checked.
#include "nestwalk/core/input_error.h"
#include "nestwalk/core/stopwatch.h"
#include "nestwalk/geometry/box_pairs_csv.h"
#include "nestwalk/geometry/nested.h"
#include "nestwalk/geometry/obb_batch.h"
#include "tools/nestwalk/commands.h"

#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace nestwalk::tools {
namespace {

// Pairs read, then tested, at a time: 1024 pairs hold about 280 KB, which stay in a core's L2
// cache between the reading and the testing. Measured on 1 M pairs (tools/data/make_box_pairs.py),
// testBoxPairs costs 15-16 ns a pair this way with AVX-512 (25 with AVX2) and testBoxPair one pair
// at a time (--scalar) 80-82 ns; chunks of 256 and 512 pairs measured the same. Read whole first,
// the pairs come back from memory (about 25 ns a pair only to stream their 240 bytes, bench
// volumes). The resident memory is the output text's (72 MB) instead of every pair's (360 MB).
constexpr std::size_t kChunkPairs = 1024;

struct QueryOverlapOptions {
  std::string path;
  bool timing = false;
  bool scalar = false;
};

void runQueryOverlap(const QueryOverlapOptions& options) {
  std::ifstream file(options.path);
  if (!file) throw InputError(options.path + ": cannot open the file");
  double testSeconds = 0;
  std::size_t count = 0, uncertain = 0;
  const auto start = std::chrono::steady_clock::now();
  BoxPairsReader reader(file, options.path);
  std::vector<BoxPair> pairs;
  std::vector<NestedResult> results;
  std::string out = "id,overlap,stage,axis\n";
  while (reader.read(pairs, kChunkPairs)) {
    const auto read = std::chrono::steady_clock::now();
    results.resize(pairs.size());
    if (options.scalar)
      for (std::size_t k = 0; k < pairs.size(); ++k) results[k] = testBoxPair(pairs[k].a, pairs[k].b);
    else
      // The reader's boxes are orthonormal to kAxesTolerance (box_pairs_csv.h).
      uncertain += testBoxPairs(
          {.a = &pairs[0].a, .b = &pairs[0].b, .count = pairs.size(), .stride = sizeof(BoxPair), .orthonormalAxes = true},
          results.data());
    const auto tested = std::chrono::steady_clock::now();
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const NestedResult& r = results[k];
      const char* axis = r.stage == OverlapStage::AabbAabb ? aabbAxisName(r.axis) : satAxisName(r.axis);
      out += pairs[k].id + (r.overlap ? ",1," : ",0,") + stageName(r.stage) + "," + axis + "\n";
    }
    testSeconds += microsBetween(read, tested) * 1e-6;
    count += pairs.size();
  }
  std::fwrite(out.data(), 1, out.size(), stdout);
  if (options.timing)
    std::fprintf(stderr,
                 "query overlap: %zu pairs; reading and writing %.3f s, testing %.3f s (%.1f ns a pair, %s)\n",
                 count, secondsSince(start) - testSeconds, testSeconds, count ? testSeconds * 1e9 / double(count) : 0.0,
                 options.scalar ? "testBoxPair one at a time"
                                : (std::string(batchKernelName(obbBatchKernel())) + ", " + std::to_string(uncertain) +
                                   " decided in double")
                                      .c_str());
}

}  // namespace

void registerQueryOverlap(CLI::App& query) {
  auto options = std::make_shared<QueryOverlapOptions>();
  CLI::App* cmd = query.add_subcommand(
      "overlap",
      "Test pairs of boxes from a CSV (id, box A, box B) with the nested AABB/OBB test; prints "
      "id,overlap,stage,axis");
  cmd->add_option("PAIRS", options->path, "CSV file with header id,acx,...,aez,bcx,...,bez")->required();
  cmd->add_flag("--timing", options->timing,
                "Also print to standard error the time spent reading and writing and the time spent testing");
  cmd->add_flag("--scalar", options->scalar,
                "Test the pairs one at a time with the scalar double test instead of the SIMD batch (the same "
                "answers; to time one against the other)");
  cmd->callback([options] { runQueryOverlap(*options); });
}

}  // namespace nestwalk::tools
