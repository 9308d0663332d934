#include "nestwalk/core/csv_reader.h"

#include <charconv>
#include <cmath>

namespace nestwalk {
namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::string::size_type start = 0;
  while (true) {
    const auto comma = line.find(',', start);
    std::string f = line.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const auto b = f.find_first_not_of(" \t"), e = f.find_last_not_of(" \t");
    fields.push_back(b == std::string::npos ? std::string() : f.substr(b, e - b + 1));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return fields;
}

bool readLine(std::istream& in, std::string& line, std::size_t& count) {
  while (std::getline(in, line)) {
    ++count;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") != std::string::npos) return true;
  }
  return false;
}

}  // namespace

CsvReader::CsvReader(std::istream& in, std::string name) : in_(in), name_(std::move(name)) {
  std::string line;
  if (!readLine(in_, line, line_)) throw InputError(name_ + ": empty file, expected a header row");
  if (line.size() >= 3 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);  // UTF-8 BOM
  header_ = split(line);
}

int CsvReader::column(const std::string& name) const {
  for (std::size_t i = 0; i < header_.size(); ++i)
    if (header_[i] == name) return int(i);
  throw InputError(name_ + ": the header has no column '" + name + "'");
}

bool CsvReader::next(std::vector<std::string>& fields) {
  std::string line;
  if (!readLine(in_, line, line_)) return false;
  fields = split(line);
  if (fields.size() != header_.size())
    throw errorAtLine(std::to_string(fields.size()) + " fields, but the header has " + std::to_string(header_.size()));
  return true;
}

double CsvReader::number(const std::vector<std::string>& fields, int column) const {
  const std::string& f = fields[std::size_t(column)];
  double value = 0.0;
  const char* first = f.data();
  if (!f.empty() && f[0] == '+') ++first;
  const auto [end, ec] = std::from_chars(first, f.data() + f.size(), value);
  if (f.empty() || ec != std::errc() || end != f.data() + f.size())
    throw errorAtLine("column '" + header_[std::size_t(column)] + "': '" + f + "' is not a number");
  if (!std::isfinite(value))
    throw errorAtLine("column '" + header_[std::size_t(column)] + "': '" + f + "' is not finite");
  return value;
}

InputError CsvReader::errorAtLine(const std::string& what) const {
  return InputError(name_ + ":" + std::to_string(line_) + ": " + what);
}

}  // namespace nestwalk
