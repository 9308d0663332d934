#include "nestwalk/geometry/box_pairs_csv.h"

#include "nestwalk/core/csv_reader.h"

namespace nestwalk {
namespace {

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
  if (!(err <= kAxesRefuseTolerance))  // NaN included
    throw csv.errorAtLine(std::string("the axes of box ") + name + " are not orthonormal (|A^T A - I| = " +
                          std::to_string(err) + ")");
  if (err > kAxesTolerance<double>) box.axes = orthonormalized(box.axes);
  return box;
}

}  // namespace

std::vector<BoxPair> readBoxPairs(std::istream& in, const std::string& name) {
  CsvReader csv(in, name);
  const int id = csv.column("id");
  const BoxColumns a = boxColumns(csv, 'a'), b = boxColumns(csv, 'b');
  std::vector<BoxPair> pairs;
  std::vector<std::string> fields;
  while (csv.next(fields)) pairs.push_back({fields[std::size_t(id)], readBox(csv, fields, a, 'A'), readBox(csv, fields, b, 'B')});
  return pairs;
}

}  // namespace nestwalk
