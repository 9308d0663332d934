// The pairs CSV of `nestwalk query overlap`: columns id, then box A as acx,acy,acz (centre),
// aux,auy,auz / avx,avy,avz / awx,awy,awz (unit axes u, v, w), aex,aey,aez (half extents), then
// box B with the same columns prefixed 'b' (any order, other columns allowed). Axes within
// kAxesTolerance of orthonormal are used as given, within kAxesRefuseTolerance re-orthonormalised
// (a CSV printed with four decimals), further off refused. BoxPairsReader reads the pairs a chunk
// at a time (a caller tests each chunk while it is in the cache), readBoxPairs all at once.
// Ownership: a BoxPairsReader keeps a reference to its stream, which must outlive it.
// Thread safety: readBoxPairs is pure; a BoxPairsReader is used by one thread at a time.
#pragma once

#include "nestwalk/core/csv_reader.h"
#include "nestwalk/geometry/volumes.h"

#include <istream>
#include <string>
#include <vector>

namespace nestwalk {

/// Axes further than this from orthonormal (|A^T A - I|) are refused rather than repaired: they do
/// not describe a box. 1e-3 accepts axes printed with four or more decimals.
inline constexpr double kAxesRefuseTolerance = 1e-3;

struct BoxPair {
  std::string id;  // as written
  Obb<double> a, b;
};

/// The pairs of a CSV, read in order a chunk at a time.
class BoxPairsReader {
 public:
  /// Reads the header; InputError naming `name` when it lacks a column.
  BoxPairsReader(std::istream& in, const std::string& name);
  /// Reads the next pairs, at most `most`, into `out` (resized to their count, its ids' storage
  /// reused); false when no pair was left. InputError as readBoxPairs.
  bool read(std::vector<BoxPair>& out, std::size_t most);

 private:
  struct BoxColumns {
    int centre[3], axes[3][3], halfExtents[3];
  };
  static BoxColumns boxColumns(const CsvReader& csv, char prefix);
  Obb<double> box(const BoxColumns& columns, char name) const;

  CsvReader csv_;
  int id_;
  BoxColumns a_, b_;
  std::vector<std::string> fields_;
};

/// The pairs of a CSV (csv_reader.h rules); InputError naming `name` and the line for a missing
/// column, a field that is not a finite number, a negative half extent or axes that are not
/// orthonormal.
std::vector<BoxPair> readBoxPairs(std::istream& in, const std::string& name);

}  // namespace nestwalk
