#include "nestwalk/core/number_text.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iomanip>
#include <locale>
#include <sstream>

namespace nestwalk {
namespace {

/// Below this magnitude shortText switches to scientific notation (3 fixed decimals would show
/// only zeros).
constexpr double kScientificBelow = 1e-4;

}  // namespace

std::string fixedText(double value, int decimals) {
  if (std::isnan(value)) return "-";
  std::ostringstream s;
  s.imbue(std::locale::classic());  // a point, whatever locale the program set
  s << std::fixed << std::setprecision(decimals) << value;
  return s.str();
}

std::string shortText(double value) {
  if (std::isnan(value)) return "-";
  const double a = std::abs(value);
  if (a == 0) return "0";
  if (a < kScientificBelow) {
    std::ostringstream s;
    s.imbue(std::locale::classic());
    s << std::setprecision(2) << std::scientific << value;
    return s.str();
  }
  return fixedText(value, std::max(0, 2 - int(std::floor(std::log10(a)))));
}

nlohmann::ordered_json jsonNumber(double value) {
  return std::isnan(value) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(value);
}

std::string exactText(double value) {
  if (value == 0) return "0";  // no "-0"
  char buf[32];                // holds any double's shortest form
  const auto r = std::to_chars(buf, buf + sizeof buf, value);
  return std::string(buf, r.ptr);
}

}  // namespace nestwalk
