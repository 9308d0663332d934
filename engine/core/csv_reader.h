// A reader for the simple CSV files the tools take (a header row, then rows of numbers): comma
// separated, no quoting, blank lines skipped, CR LF accepted. Every problem is an InputError that
// names the file and the line.
#pragma once

#include "nestwalk/core/input_error.h"

#include <istream>
#include <string>
#include <vector>

namespace nestwalk {

class CsvReader {
 public:
  /// Reads the header row. `name` is the file's name for messages.
  CsvReader(std::istream& in, std::string name);

  const std::vector<std::string>& header() const { return header_; }
  /// The column index of a header name; throws InputError naming the file when it is missing.
  int column(const std::string& name) const;

  /// Reads the next data row into `fields`; false at the end. A row whose field count differs from
  /// the header's is an InputError naming the line.
  bool next(std::vector<std::string>& fields);
  /// The line number (1-based) of the row last read.
  std::size_t line() const { return line_; }

  /// The field as a finite double; throws InputError naming the file, line and column otherwise.
  double number(const std::vector<std::string>& fields, int column) const;
  /// An InputError naming the file and the current line.
  InputError errorAtLine(const std::string& what) const;

 private:
  std::istream& in_;
  std::string name_;
  std::vector<std::string> header_;
  std::size_t line_ = 0;
};

}  // namespace nestwalk
