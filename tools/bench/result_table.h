// A benchmark's results as rows of named values, printed as an aligned table and written as JSON
// from the same rows. A row is a JSON object; a column names the JSON pointer of its value in the
// row ("/ns_per_op/fcl"), its title and how the value prints. Ratio columns (peer / nestwalk) are
// computed from two other values of the row when the row is added and stored in it, so the table
// and the JSON carry the same ratio.
//
// How a value prints: absent from the row, as blanks (and absent from the JSON); null, as "-"
// (null in the JSON: not measured); a string as it is; an integer in full; a floating-point value
// with the column's decimals; a boolean as yes / no.
#pragma once

#include <nlohmann/json.hpp>

#include <iosfwd>
#include <string>
#include <vector>

namespace nestwalk::bench {

using Json = nlohmann::ordered_json;

struct Column {
  Column(std::string title, std::string path, int width = 10, int decimals = 2, bool left = false,
         bool tableOnly = false, std::string suffix = "")
      : title(std::move(title)), path(std::move(path)), width(width), decimals(decimals), left(left),
        tableOnly(tableOnly), suffix(std::move(suffix)) {}

  std::string title;
  std::string path;  // JSON pointer of the value in a row
  int width;         // characters, the title's and the values' (right-aligned unless left)
  int decimals;      // of floating-point values
  bool left;
  bool tableOnly;      // printed, left out of the JSON (a value another row carries)
  std::string suffix;  // printed after a number, e.g. "%"
};

/// A count held as a double (a fact, bench_runner.h) as a JSON integer; NaN (not counted) as null.
Json countJson(double count);

/// A peer of nestwalk in a table: its key in the JSON and its column title.
struct Peer {
  std::string key;    // "fcl"
  std::string title;  // "FCL"
};

class Table {
 public:
  /// Adds a column, printed after the ones before it.
  Table& column(Column c);
  /// Adds a ratio column: the row's value at `numerator` / its value at `denominator`, stored at
  /// c.path when the row has both (null when either is null).
  Table& ratio(Column c, std::string numerator, std::string denominator);

  /// The table of nestwalk against its peers: `test` and `set` (left-aligned, at "/test" and
  /// "/set"), the row's own `columns`, nestwalk's time at "/<group>/nestwalk", then per peer its time
  /// at "/<group>/<key>" and the ratio to nestwalk's, stored at "/ratio/<key>" (> 1: nestwalk
  /// faster). Times are `width` characters with `decimals`.
  static Table againstPeers(Column test, Column set, std::vector<Column> columns, const std::string& group,
                            const std::vector<Peer>& peers, int width, int decimals, int ratioDecimals);

  /// Adds a row; the ratio columns' values are computed and stored in it.
  void add(Json row);
  /// Adds the row when one of its values at "/<group>/..." is a number (a method that ran).
  void addMeasured(Json row, const std::string& group);
  const std::vector<Json>& rows() const { return rows_; }

  /// The title line, then one line a row, each after `indent`.
  void print(std::ostream& out, const std::string& indent = "") const;
  /// The rows as a JSON array, without the table-only values.
  Json json() const;

 private:
  struct Ratio {
    std::string path, numerator, denominator;
  };
  std::vector<Column> columns_;
  std::vector<Ratio> ratios_;
  std::vector<Json> rows_;
};

}  // namespace nestwalk::bench
