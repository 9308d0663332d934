// nestwalk query overlap PAIRS.csv: the nested three-stage verdict for pairs of boxes.
// Input: geometry/box_pairs_csv.h (id, box A's centre, axes and half extents, then box B's).
// Output: id,overlap,stage,axis (see testBoxPair in engine/geometry/nested.h).
// The pairs are read whole, then answered together by testBoxPairs (obb_batch.h: float SIMD lanes,
// the lanes it cannot vouch for answered by testBoxPair itself; the answers are testBoxPair's).
#include "nestwalk/core/input_error.h"
#include "nestwalk/geometry/box_pairs_csv.h"
#include "nestwalk/geometry/nested.h"
#include "nestwalk/geometry/obb_batch.h"
#include "tools/nestwalk/commands.h"

#include <cstdio>
#include <fstream>
#include <memory>
#include <vector>

namespace nestwalk::tools {
namespace {

void runQueryOverlap(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw InputError(path + ": cannot open the file");
  const std::vector<BoxPair> pairs = readBoxPairs(file, path);
  std::vector<NestedResult> results(pairs.size());
  if (!pairs.empty()) testBoxPairs({&pairs[0].a, &pairs[0].b, pairs.size(), sizeof(BoxPair)}, results.data());
  std::string out = "id,overlap,stage,axis\n";
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const NestedResult& r = results[k];
    const char* axis = r.stage == OverlapStage::AabbAabb ? aabbAxisName(r.axis) : satAxisName(r.axis);
    out += pairs[k].id + (r.overlap ? ",1," : ",0,") + stageName(r.stage) + "," + axis + "\n";
  }
  // Written only once every row has been read and checked: bad input produces no partial output.
  std::fwrite(out.data(), 1, out.size(), stdout);
}

}  // namespace

void registerQueryOverlap(CLI::App& query) {
  auto path = std::make_shared<std::string>();
  CLI::App* cmd = query.add_subcommand(
      "overlap",
      "Test pairs of boxes from a CSV (id, box A, box B) with the nested AABB/OBB test; prints "
      "id,overlap,stage,axis");
  cmd->add_option("PAIRS", *path, "CSV file with header id,acx,...,aez,bcx,...,bez")->required();
  cmd->callback([path] { runQueryOverlap(*path); });
}

}  // namespace nestwalk::tools
