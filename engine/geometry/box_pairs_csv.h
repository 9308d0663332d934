// The pairs CSV of `nestwalk query overlap`: columns id, then box A as acx,acy,acz (centre),
// aux,auy,auz / avx,avy,avz / awx,awy,awz (unit axes u, v, w), aex,aey,aez (half extents), then
// box B with the same columns prefixed 'b' (any order, other columns allowed). Axes within
// kAxesTolerance of orthonormal are used as given, within kAxesRefuseTolerance re-orthonormalised
// (a CSV printed with four decimals), further off refused. Read whole before anything is answered.
// Thread safety: pure (the stream is the caller's).
#pragma once

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

/// The pairs of a CSV (csv_reader.h rules); InputError naming `name` and the line for a missing
/// column, a field that is not a finite number, a negative half extent or axes that are not
/// orthonormal.
std::vector<BoxPair> readBoxPairs(std::istream& in, const std::string& name);

}  // namespace nestwalk
