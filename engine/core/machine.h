// What the machine is, for the header of every benchmark and report (speed figures mean little
// without it).
// Thread safety: reads /proc/cpuinfo on every call and keeps nothing; safe from any thread.
#pragma once

#include <string>

namespace nestwalk {

/// The processor's model name from /proc/cpuinfo, "unknown" where there is none.
std::string cpuModelName();

}  // namespace nestwalk
