#include "tools/bench/bench_document.h"

#include "tools/bench/peers/peer_versions.h"

#include "nestwalk/core/machine.h"
#include "nestwalk/core/number_text.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>

// "1" where the predefined macro x is defined (as 1), else the macro's own name.
#define NESTWALK_MACRO_TEXT(x) #x
#define NESTWALK_MACRO_VALUE(x) NESTWALK_MACRO_TEXT(x)

namespace nestwalk::bench {
namespace {

struct Isa {
  const char* name;
  bool compiled;  // the build targets it (-march)
  bool cpu;       // the processor has it
};

std::vector<Isa> instructionSets() {
  __builtin_cpu_init();
  auto on = [](const char* macroValue) { return std::string(macroValue) == "1"; };
  return {{"sse4_2", on(NESTWALK_MACRO_VALUE(__SSE4_2__)), bool(__builtin_cpu_supports("sse4.2"))},
          {"avx", on(NESTWALK_MACRO_VALUE(__AVX__)), bool(__builtin_cpu_supports("avx"))},
          {"avx2", on(NESTWALK_MACRO_VALUE(__AVX2__)), bool(__builtin_cpu_supports("avx2"))},
          {"fma", on(NESTWALK_MACRO_VALUE(__FMA__)), bool(__builtin_cpu_supports("fma"))},
          {"avx512f", on(NESTWALK_MACRO_VALUE(__AVX512F__)), bool(__builtin_cpu_supports("avx512f"))}};
}

/// "avx avx2" from {"avx": true, ...}; "-" when none.
std::string flagList(const Json& flags) {
  std::string out;
  for (const auto& [name, on] : flags.items())
    if (on.get<bool>()) out += (out.empty() ? "" : " ") + name;
  return out.empty() ? "-" : out;
}

}  // namespace

Json machineJson() {
  const benchmark::CPUInfo& cpu = benchmark::CPUInfo::Get();
  Json m;
  m["cpu_model"] = cpuModelName();
  m["num_cpus"] = cpu.num_cpus;
  m["mhz_per_cpu"] = cpu.cycles_per_second / 1e6;
  m["cpu_scaling"] = cpu.scaling == benchmark::CPUInfo::ENABLED    ? "enabled"
                     : cpu.scaling == benchmark::CPUInfo::DISABLED ? "disabled"
                                                                   : "unknown";
  Json caches = Json::array();
  for (const auto& c : cpu.caches)
    caches.push_back({{"type", c.type}, {"level", c.level}, {"size", c.size}, {"num_sharing", c.num_sharing}});
  m["caches"] = caches;
  m["load_avg"] = cpu.load_avg;
  for (const Isa& i : instructionSets()) {
    m["compiled_isa"][i.name] = i.compiled;
    m["cpu_supports"][i.name] = i.cpu;
  }
  m["compiler"] = __VERSION__;
#ifdef NDEBUG
  m["ndebug"] = true;
#else
  m["ndebug"] = false;
#endif
  m["libraries"] = peerVersions();
  return m;
}

std::string limitText(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", value);
  return buf;
}

Document::Document(std::string title) : title_(std::move(title)) { json["machine"] = machineJson(); }

void Document::target(const std::string& name, const std::string& what, const Json& value, const std::string& op,
                      double limit, const std::string& unit, bool comparable) {
  if (!value.is_number() || std::isnan(value.get<double>())) return;
  const double v = value.get<double>();
  const bool met = comparable && (op == ">=" ? v >= limit : op == "<=" ? v <= limit : v < limit);
  targets.push_back({name, (what.empty() ? "" : what + " ") + op + " " + limitText(limit) + unit, v, met});
}

std::string Document::runSettings(double minTime, bool quick, std::size_t repetitions) {
  Json& m = json["machine"];
  m["min_time_s"] = minTime;
  m["quick"] = quick;
  m["repetitions"] = repetitions;
  std::ostringstream s;
  s << "min time per benchmark: " << minTime << " s" << (quick ? " (quick)" : "");
  if (repetitions > 1) s << "; median of " << repetitions << " repetitions";
  return s.str();
}

void Document::table(const std::string& key, const Table& table, const std::string& indent) {
  table.print(text, indent);
  json[key] = table.json();
}

std::string Document::header() const {
  const Json& m = json["machine"];
  std::ostringstream s;
  s << title_ << "\ncpu: " << m["cpu_model"].get<std::string>() << ", " << m["num_cpus"] << " CPUs @ "
    << fixedText(m["mhz_per_cpu"].get<double>(), 0) << " MHz, scaling " << m["cpu_scaling"].get<std::string>()
    << "\nbuild: compiled for: " << flagList(m["compiled_isa"]) << "; CPU supports: " << flagList(m["cpu_supports"])
    << " (AVX2 " << (m["compiled_isa"]["avx2"].get<bool>() ? "compiled in" : "not compiled in")
    << (m["cpu_supports"]["avx2"].get<bool>() ? ", available at run time)" : ", not available at run time)")
    << (m["ndebug"].get<bool>() ? "" : "; ASSERTIONS ON (not a release build)") << "\n";
  return s.str();
}

Json Document::finalJson() const {
  Json j = json;
  j["targets"] = targetsJson(targets);
  for (const auto& [name, message] : errors) j["errors"][name] = message;
  return j;
}

int Document::write(std::ostream& out, bool asJson) const {
  if (asJson) {
    out << finalJson().dump(2) << "\n";
  } else {
    std::size_t whatWidth = 0;
    for (const Target& t : targets) whatWidth = std::max(whatWidth, t.what.size());
    out << header() << text.str();
    printTargets(out, targets, 0, int(whatWidth) + 2);  // it widens the names' column to the longest
    for (const auto& [name, message] : errors) out << "error: " << name << ": " << message << "\n";
  }
  return errors.empty() ? 0 : 1;
}

}  // namespace nestwalk::bench
