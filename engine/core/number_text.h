// Numbers as the reports and benchmarks print them: fixed-point text with "-" for a missing value
// (NaN), and JSON numbers with null for it; and as scripts and paths write them, exactly.
// Thread safety: pure functions.
// Locale: fixedText and shortText format through std::ostringstream, so they follow the global C++
// locale (std::locale::global); nestwalk never changes it, and under the default classic locale the
// decimal mark is '.'.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace nestwalk {

/// Fixed-point with `decimals` digits after the point ("12.35"), "-" for NaN.
std::string fixedText(double value, int decimals = 2);

/// About 3 significant digits: whole numbers above 100 in full, small values (below 1e-4) in
/// scientific notation; "0" for zero, "-" for NaN.
std::string shortText(double value);

/// The shortest text that reads back to exactly the same double (std::to_chars: locale-independent),
/// "0" for either zero: what scripts and camera paths are written with, so that they replay to the
/// bit.
std::string exactText(double value);

/// The number, or JSON null for NaN.
nlohmann::ordered_json jsonNumber(double value);

}  // namespace nestwalk
