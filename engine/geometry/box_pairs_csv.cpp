#include "nestwalk/geometry/box_pairs_csv.h"

#include <limits>

namespace nestwalk {

BoxPairsReader::BoxColumns BoxPairsReader::boxColumns(const CsvReader& csv, char prefix) {
  BoxColumns cols;
  const std::string p(1, prefix);
  const char* xyz[3] = {"x", "y", "z"};
  const char* uvw[3] = {"u", "v", "w"};
  // Looked up in the order the columns are documented, so the first missing one is named.
  for (int k = 0; k < 3; ++k) cols.centre[k] = csv.column(p + "c" + xyz[k]);
  for (int a = 0; a < 3; ++a)
    for (int k = 0; k < 3; ++k) cols.axes[a][k] = csv.column(p + uvw[a] + xyz[k]);
  for (int k = 0; k < 3; ++k) cols.halfExtents[k] = csv.column(p + "e" + xyz[k]);
  return cols;
}

BoxPairsReader::BoxPairsReader(std::istream& in, const std::string& name)
    : csv_(in, name), id_(csv_.column("id")), a_(boxColumns(csv_, 'a')), b_(boxColumns(csv_, 'b')) {}

Obb<double> BoxPairsReader::box(const BoxColumns& cols, char name) const {
  Obb<double> box;
  for (int k = 0; k < 3; ++k) {
    box.center[k] = csv_.number(fields_, cols.centre[k]);
    box.halfExtents[k] = csv_.number(fields_, cols.halfExtents[k]);
    for (int a = 0; a < 3; ++a) box.axes(k, a) = csv_.number(fields_, cols.axes[a][k]);
  }
  if ((box.halfExtents.array() < 0.0).any())
    throw csv_.errorAtLine(std::string("box ") + name + " has a negative half extent");
  const double err = axesError(box.axes);
  if (!(err <= kAxesRefuseTolerance))  // NaN included
    throw csv_.errorAtLine(std::string("the axes of box ") + name + " are not orthonormal (|A^T A - I| = " +
                           std::to_string(err) + ")");
  if (err > kAxesTolerance<double>) box.axes = orthonormalized(box.axes);
  return box;
}

bool BoxPairsReader::read(std::vector<BoxPair>& out, std::size_t most) {
  std::size_t count = 0;
  for (; count < most && csv_.next(fields_); ++count) {
    if (count == out.size()) out.emplace_back();
    BoxPair& pair = out[count];
    pair.id = fields_[std::size_t(id_)];
    pair.a = box(a_, 'A');
    pair.b = box(b_, 'B');
  }
  out.resize(count);
  return count > 0;
}

std::vector<BoxPair> readBoxPairs(std::istream& in, const std::string& name) {
  BoxPairsReader reader(in, name);
  std::vector<BoxPair> pairs;
  reader.read(pairs, std::numeric_limits<std::size_t>::max());
  return pairs;
}

}  // namespace nestwalk
