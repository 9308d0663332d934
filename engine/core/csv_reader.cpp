#include "nestwalk/core/csv_reader.h"

#include <charconv>
#include <cmath>

namespace nestwalk {
namespace {

bool isBlank(char c) { return c == ' ' || c == '\t'; }

/// A byte that only adds itself to an unquoted field (blanks included: they are trimmed at its end).
bool isPlain(char c) { return c != ',' && c != '\n' && c != '\r' && c != '"'; }

bool onlyBlanks(const std::string& s) { return s.find_first_not_of(" \t") == std::string::npos; }

/// Drops the spaces and tabs around `s`, in place.
void trimBlanks(std::string& s) {
  if (!s.empty() && !isBlank(s.front()) && !isBlank(s.back())) return;
  const auto e = s.find_last_not_of(" \t");
  if (e == std::string::npos) {
    s.clear();
    return;
  }
  s.erase(e + 1);
  s.erase(0, s.find_first_not_of(" \t"));
}

}  // namespace

CsvReader::CsvReader(std::istream& in, std::string name) : in_(in), name_(std::move(name)) {
  // A UTF-8 byte order mark (EF BB BF) before the header is dropped; a file that starts with only
  // part of one is not text.
  for (int bomByte : {0xEF, 0xBB, 0xBF}) {
    if (peek() != bomByte) {
      if (bomByte != 0xEF) throw InputError(name_ + ": starts with a broken UTF-8 byte order mark; not a CSV file");
      break;
    }
    get();
  }
  if (!readRow(header_)) throw InputError(name_ + ": empty file, expected a header row");
}

int CsvReader::get() {
  if (pos_ == end_ && !refill()) return std::char_traits<char>::eof();
  return static_cast<unsigned char>(buffer_[pos_++]);
}

int CsvReader::peek() {
  if (pos_ == end_ && !refill()) return std::char_traits<char>::eof();
  return static_cast<unsigned char>(buffer_[pos_]);
}

bool CsvReader::refill() {
  if (buffer_.empty()) buffer_.resize(kReadBlockBytes);
  in_.read(buffer_.data(), std::streamsize(buffer_.size()));
  pos_ = 0;
  end_ = std::size_t(in_.gcount());
  return end_ > 0;
}

bool CsvReader::readRow(std::vector<std::string>& fields) {
  for (;;) {
    // Fields are written over the strings `fields` already holds, so a reader that passes the same
    // vector row after row reuses their storage.
    std::size_t count = 0;
    const auto nextField = [&]() -> std::string& {
      if (count == fields.size()) fields.emplace_back();
      std::string& f = fields[count++];
      f.clear();
      return f;
    };
    line_ = nextLine_;
    int c = get();
    if (c == std::char_traits<char>::eof()) {
      fields.clear();
      return false;
    }
    std::string* field = &nextField();
    bool quoted = false;       // inside a quoted field
    bool wasQuoted = false;    // the current field was quoted (kept as written)
    bool any = false;          // the row holds something other than blanks
    for (;; c = get()) {
      if (c == std::char_traits<char>::eof()) {
        if (quoted) throw errorAtLine("a quoted field is not closed before the end of the file");
        break;
      }
      const char ch = char(c);
      if (quoted) {
        if (ch == '"') {
          if (peek() == '"') {
            get();
            field->push_back('"');
          } else {
            quoted = false;
          }
        } else {
          if (ch == '\n') ++nextLine_;
          field->push_back(ch);
        }
        continue;
      }
      if (ch == '\n' || ch == '\r') {
        if (ch == '\r' && peek() == '\n') get();
        ++nextLine_;
        break;
      }
      if (ch == ',') {
        if (!wasQuoted) trimBlanks(*field);
        field = &nextField();
        wasQuoted = false;
        any = true;
        continue;
      }
      if (ch == '"' && !wasQuoted && onlyBlanks(*field)) {
        field->clear();  // blanks before the opening quote
        quoted = wasQuoted = any = true;
        continue;
      }
      if (wasQuoted) {
        if (isBlank(ch)) continue;  // blanks after the closing quote
        throw errorAtLine("text after a quoted field's closing quote");
      }
      field->push_back(ch);
      if (isBlank(ch)) continue;
      any = true;
      // The rest of the field's run of plain bytes in the buffer, at once (what a number is).
      std::size_t run = pos_;
      while (run < end_ && isPlain(buffer_[run])) ++run;
      field->append(buffer_.data() + pos_, run - pos_);
      pos_ = run;
    }
    if (!any) continue;  // a blank line
    if (!wasQuoted) trimBlanks(*field);
    fields.resize(count);
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
