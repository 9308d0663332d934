#include "nestwalk/core/map_points_csv.h"

#include "nestwalk/core/csv_reader.h"

namespace nestwalk {

std::vector<MapPoint> readMapPoints(std::istream& in, const std::string& name) {
  CsvReader csv(in, name);
  const int cx = csv.column("x"), cy = csv.column("y");
  std::vector<MapPoint> points;
  std::vector<std::string> fields;
  while (csv.next(fields))
    points.push_back({fields[std::size_t(cx)], fields[std::size_t(cy)], csv.number(fields, cx), csv.number(fields, cy)});
  return points;
}

}  // namespace nestwalk
