// The points CSV of `nestwalk query ground`: a header with columns x and y (others allowed, in any
// order), then one point a row, map coordinates in the terrain's CRS (longitude and latitude in
// degrees for a geographic one). Read whole before anything is answered, so bad input produces
// no partial output. Thread safety: pure (the stream is the caller's).
#pragma once

#include <istream>
#include <string>
#include <vector>

namespace nestwalk {

struct MapPoint {
  std::string xText, yText;  // the fields as written (echoed in the output)
  double x = 0, y = 0;
};

/// The points of a CSV (csv_reader.h rules); InputError naming `name` and the line for a missing
/// column, a field that is not a finite number, or a malformed row.
std::vector<MapPoint> readMapPoints(std::istream& in, const std::string& name);

}  // namespace nestwalk
