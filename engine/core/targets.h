// Targets: what an issue asked a measurement to reach, and whether a run reached it. The report
// and every benchmark print them the same way (a "targets:" block, and a JSON array). Reported,
// not enforced: a missed target is a finding, not a failure of the program.
// Thread safety: pure functions; printTargets writes to the caller's stream.
#pragma once

#include <nlohmann/json.hpp>

#include <iosfwd>
#include <string>
#include <vector>

namespace nestwalk {

struct Target {
  std::string name;  // what was measured, e.g. "nested+mesh max stop gap (mm)"
  std::string what;  // the target, e.g. "<= 1"
  double value;      // what this run measured
  bool met;
};

/// The targets as a JSON array of {name, target, value, met} (NaN values as null).
nlohmann::ordered_json targetsJson(const std::vector<Target>& targets);

/// Prints "targets:" and one line a target (name and what in columns of the given widths, the
/// name's widened to the longest name), after an empty line; nothing when there are none.
void printTargets(std::ostream& out, const std::vector<Target>& targets, int nameWidth, int whatWidth);

}  // namespace nestwalk
