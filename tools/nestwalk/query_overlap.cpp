// nestwalk query overlap PAIRS.csv: the nested three-stage verdict for pairs of boxes.
// Input columns: id, then a box A as acx,acy,acz (centre), aux,auy,auz / avx,avy,avz / awx,awy,awz
// (unit axes u, v, w), aex,aey,aez (half extents), then box B with the same columns prefixed 'b'.
// Output: id,overlap,stage,axis (see testBoxPair in engine/geometry/nested.h).
#include "nestwalk/core/csv_reader.h"
#include "nestwalk/geometry/nested.h"
#include "tools/nestwalk/commands.h"

#include <cstdio>
#include <fstream>
#include <memory>

namespace nestwalk::tools {
namespace {

/// Axes further than this from orthonormal are refused rather than repaired: they do not describe
/// a box. 1e-3 accepts axes printed with four or more decimals.
constexpr double kAxesRefuseTolerance = 1e-3;

struct BoxColumns {
  int c[3], axes[3][3], e[3];
};

BoxColumns boxColumns(const CsvReader& csv, char prefix) {
  BoxColumns cols;
  const std::string p(1, prefix);
  const char* xyz[3] = {"x", "y", "z"};
  const char* uvw[3] = {"u", "v", "w"};
  // Looked up in the order the columns are documented, so the first missing one is named.
  for (int k = 0; k < 3; ++k) cols.c[k] = csv.column(p + "c" + xyz[k]);
  for (int a = 0; a < 3; ++a)
    for (int k = 0; k < 3; ++k) cols.axes[a][k] = csv.column(p + uvw[a] + xyz[k]);
  for (int k = 0; k < 3; ++k) cols.e[k] = csv.column(p + "e" + xyz[k]);
  return cols;
}

Obb<double> readBox(const CsvReader& csv, const std::vector<std::string>& fields, const BoxColumns& cols, char name) {
  Obb<double> box;
  for (int k = 0; k < 3; ++k) {
    box.center[k] = csv.number(fields, cols.c[k]);
    box.halfExtents[k] = csv.number(fields, cols.e[k]);
    for (int a = 0; a < 3; ++a) box.axes(k, a) = csv.number(fields, cols.axes[a][k]);
  }
  if ((box.halfExtents.array() < 0.0).any())
    throw csv.errorAtLine(std::string("box ") + name + " has a negative half extent");
  const double err = axesError(box.axes);
  if (err > kAxesRefuseTolerance)
    throw csv.errorAtLine(std::string("the axes of box ") + name + " are not orthonormal (|A^T A - I| = " +
                          std::to_string(err) + ")");
  if (err > kAxesTolerance<double>) box.axes = orthonormalized(box.axes);
  return box;
}

void runQueryOverlap(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw InputError(path + ": cannot open the file");
  CsvReader csv(file, path);
  const int id = csv.column("id");
  const BoxColumns a = boxColumns(csv, 'a'), b = boxColumns(csv, 'b');

  std::vector<std::string> fields;
  std::string out = "id,overlap,stage,axis\n";
  while (csv.next(fields)) {
    const NestedResult r = testBoxPair(readBox(csv, fields, a, 'A'), readBox(csv, fields, b, 'B'));
    const char* axis = r.stage == OverlapStage::AabbAabb ? aabbAxisName(r.axis) : satAxisName(r.axis);
    out += fields[std::size_t(id)] + (r.overlap ? ",1," : ",0,") + stageName(r.stage) + "," + axis + "\n";
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
