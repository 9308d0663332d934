#include "nestwalk/core/targets.h"

#include "nestwalk/core/number_text.h"

#include <algorithm>
#include <iomanip>
#include <ostream>

namespace nestwalk {

nlohmann::ordered_json targetsJson(const std::vector<Target>& targets) {
  nlohmann::ordered_json t = nlohmann::ordered_json::array();
  for (const Target& x : targets)
    t.push_back({{"name", x.name}, {"target", x.what}, {"value", jsonNumber(x.value)}, {"met", x.met}});
  return t;
}

void printTargets(std::ostream& out, const std::vector<Target>& targets, int nameWidth, int whatWidth) {
  if (targets.empty()) return;
  out << "\ntargets:\n";
  for (const Target& x : targets) nameWidth = std::max(nameWidth, int(x.name.size()) + 2);  // a long name still aligns
  for (const Target& x : targets)
    out << "  " << std::left << std::setw(nameWidth) << x.name << std::setw(whatWidth) << x.what << std::right
        << std::setw(8) << fixedText(x.value) << "  " << (x.met ? "met" : "NOT met") << "\n";
}

}  // namespace nestwalk
