// A reader for the CSV files the tools take and write (RFC 4180): a header row, then rows of
// fields separated by commas. A field may be quoted ("...") and then hold commas, line breaks and
// quotes (doubled: ""); spaces and tabs around an unquoted field are trimmed, a quoted field is
// kept as written. Lines that are empty or hold only spaces are skipped; CR LF and LF both end a
// row; a UTF-8 byte order mark before the header is dropped. Every problem is an InputError that
// names the file and the line (the line where the row starts).
// Ownership: the reader keeps a reference to the stream `in`, which must outlive it. It reads the
// stream in blocks of kReadBlockBytes and copies runs of plain bytes at once (reading a 1 M-row,
// 469 MB pairs CSV took 3.7 s a character at a time through std::istream, 1.4 s so), so it may
// consume the stream past the CSV's end.
// Thread safety: one thread at a time per reader (next() advances the stream and the line count);
// different readers on different streams are independent.
#pragma once

#include "nestwalk/core/input_error.h"

#include <istream>
#include <string>
#include <vector>

namespace nestwalk {

class CsvReader {
 public:
  /// Reads the header row. `name` is the file's name for messages. Throws InputError for an empty
  /// file or a malformed header.
  CsvReader(std::istream& in, std::string name);

  const std::vector<std::string>& header() const { return header_; }
  /// The column index of a header name; throws InputError naming the file when it is missing.
  int column(const std::string& name) const;

  /// Reads the next data row into `fields`; false at the end. A row whose field count differs from
  /// the header's, or a quote left open at the end of the file, is an InputError naming the line.
  bool next(std::vector<std::string>& fields);
  /// The line number (1-based) where the row last read starts.
  std::size_t line() const { return line_; }

  /// The field as a finite double; throws InputError naming the file, line and column otherwise.
  double number(const std::vector<std::string>& fields, int column) const;
  /// An InputError naming the file and the current line.
  InputError errorAtLine(const std::string& what) const;

 private:
  /// Reads one row (skipping blank lines) into `fields`; false at the end of the input.
  bool readRow(std::vector<std::string>& fields);
  /// The next byte of the stream (consumed), or the byte get() returns next, or EOF.
  int get();
  int peek();
  /// Reads the next block into the buffer; false at the end of the stream.
  bool refill();

  static constexpr std::size_t kReadBlockBytes = 1 << 16;  // bytes read from the stream at a time

  std::istream& in_;
  std::vector<char> buffer_;  // the block being read: [pos_, end_) not yet consumed
  std::size_t pos_ = 0, end_ = 0;
  std::string name_;
  std::vector<std::string> header_;
  std::size_t line_ = 0;      // where the last row started
  std::size_t nextLine_ = 1;  // the line the reader is at
};

}  // namespace nestwalk
