#include "nestwalk/core/csv_reader.h"

#include <charconv>
#include <cmath>

namespace nestwalk {
namespace {

bool isBlank(char c) { return c == ' ' || c == '\t'; }

std::string trimmed(const std::string& s) {
  const auto b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

}  // namespace

CsvReader::CsvReader(std::istream& in, std::string name) : in_(in), name_(std::move(name)) {
  // A UTF-8 byte order mark (EF BB BF) before the header is dropped; a file that starts with only
  // part of one is not text.
  for (int bomByte : {0xEF, 0xBB, 0xBF}) {
    if (in_.peek() != bomByte) {
      if (bomByte != 0xEF) throw InputError(name_ + ": starts with a broken UTF-8 byte order mark; not a CSV file");
      break;
    }
    in_.get();
  }
  if (!readRow(header_)) throw InputError(name_ + ": empty file, expected a header row");
}

bool CsvReader::readRow(std::vector<std::string>& fields) {
  for (;;) {
    fields.clear();
    line_ = nextLine_;
    std::string field;
    bool quoted = false;       // inside a quoted field
    bool wasQuoted = false;    // the current field was quoted (kept as written)
    bool any = false;          // the row holds something other than blanks
    int c = in_.get();
    if (c == std::char_traits<char>::eof()) return false;
    for (;; c = in_.get()) {
      if (c == std::char_traits<char>::eof()) {
        if (quoted) throw errorAtLine("a quoted field is not closed before the end of the file");
        break;
      }
      const char ch = char(c);
      if (quoted) {
        if (ch == '"') {
          if (in_.peek() == '"') {
            in_.get();
            field += '"';
          } else {
            quoted = false;
          }
        } else {
          if (ch == '\n') ++nextLine_;
          field += ch;
        }
        continue;
      }
      if (ch == '\n' || ch == '\r') {
        if (ch == '\r' && in_.peek() == '\n') in_.get();
        ++nextLine_;
        break;
      }
      if (ch == ',') {
        fields.push_back(wasQuoted ? field : trimmed(field));
        field.clear();
        wasQuoted = false;
        any = true;
        continue;
      }
      if (ch == '"' && trimmed(field).empty() && !wasQuoted) {
        field.clear();  // blanks before the opening quote
        quoted = wasQuoted = any = true;
        continue;
      }
      if (wasQuoted) {
        if (isBlank(ch)) continue;  // blanks after the closing quote
        throw errorAtLine("text after a quoted field's closing quote");
      }
      if (!isBlank(ch)) any = true;
      field += ch;
    }
    if (!any) continue;  // a blank line
    fields.push_back(wasQuoted ? field : trimmed(field));
    return true;
  }
}

int CsvReader::column(const std::string& name) const {
  for (std::size_t i = 0; i < header_.size(); ++i)
    if (header_[i] == name) return int(i);
  throw InputError(name_ + ": the header has no column '" + name + "'");
}

bool CsvReader::next(std::vector<std::string>& fields) {
  if (!readRow(fields)) return false;
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
