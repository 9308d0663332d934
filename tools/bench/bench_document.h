// One benchmark's output, built once and written either as text or as one JSON document: a title
// line, the machine and build it ran on (a speed figure means little without them), the
// benchmark's tables and notes in order, the targets of the issue (core/targets.h) and the errors
// of benchmarks that failed. Every table goes to both forms from the same rows (result_table.h).
#pragma once

#include "tools/bench/result_table.h"

#include "nestwalk/core/targets.h"

#include <iosfwd>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace nestwalk::bench {

/// The machine and the build: CPU model, count, MHz, frequency scaling, caches, load, the
/// instruction sets compiled for and those the CPU supports, compiler, NDEBUG, and the versions of
/// the peer libraries linked (peers/peer_versions.h) as "libraries".
Json machineJson();

/// A limit or size as the text shows it: up to 10 significant digits, no trailing zeros ("1.25").
std::string limitText(double value);

class Document {
 public:
  /// `title`: the text's first line, e.g. "nestwalk bench volumes: ns per test (CPU time); ...".
  /// json["machine"] is machineJson().
  explicit Document(std::string title);

  /// The JSON document; the benchmark adds its sections (tables() stores the tables' rows here).
  Json json;
  /// The text after the title and the machine lines: the benchmark's tables and notes.
  std::ostringstream text;
  std::vector<Target> targets;
  /// Benchmark name -> message, for the benchmarks that failed; they make write() return 1.
  std::map<std::string, std::string> errors;

  /// Adds the target `name` when `value` is a number (null or NaN: not measured): met when value
  /// `op` (">=", "<=" or "<") `limit`, and never when not `comparable` (the run measured something
  /// other than the target's figure); its text "WHAT OP LIMIT UNIT" (limitText), e.g. "Embree /
  /// nestwalk >= 15" or, with no `what`, "<= 2 us". One statement of each limit, text and check.
  void target(const std::string& name, const std::string& what, const Json& value, const std::string& op,
              double limit, const std::string& unit = "", bool comparable = true);

  /// Records a Google Benchmark suite's run settings in json["machine"] (min_time_s, quick,
  /// repetitions) and returns them as text: "min time per benchmark: 0.02 s (quick)", with
  /// "; median of N repetitions" when N > 1.
  std::string runSettings(double minTime, bool quick, std::size_t repetitions);

  /// Prints `table` into the text (after `indent` on each line) and stores its rows at json[key].
  void table(const std::string& key, const Table& table, const std::string& indent = "");

  const std::string& title() const { return title_; }
  /// The title and machine lines.
  std::string header() const;
  /// The JSON document with "targets" and, when there are any, "errors".
  Json finalJson() const;
  /// Writes finalJson() (asJson), or the header, the text, the targets block and the errors.
  /// Returns 0, or 1 when a benchmark failed.
  int write(std::ostream& out, bool asJson) const;

 private:
  std::string title_;
};

}  // namespace nestwalk::bench
