#include "tools/bench/bench_process.h"

#include <cstdlib>
#include <fstream>

namespace nestwalk::bench {

std::string sharedDataFolder() {
  const char* env = std::getenv("NESTWALK_SHARED_DATA");
  return env && *env ? std::string(env) : std::string(NESTWALK_SHARED_DATA_DIR);
}

ScopedEnvironment::ScopedEnvironment(std::string name, const std::string& value, bool active)
    : name_(std::move(name)), active_(active) {
  if (!active_) return;
  if (const char* v = std::getenv(name_.c_str())) saved_ = v;
  set(value);
}

ScopedEnvironment::~ScopedEnvironment() {
  if (active_ && saved_) ::setenv(name_.c_str(), saved_->c_str(), 1);
  if (active_ && !saved_) ::unsetenv(name_.c_str());
}

void ScopedEnvironment::set(const std::string& value) const {
  if (active_) ::setenv(name_.c_str(), value.c_str(), 1);
}

std::optional<double> processStatusMiB(const std::string& key) {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind(key + ":", 0) == 0) return std::stod(line.substr(key.size() + 1)) / 1024.0;
  return std::nullopt;
}

}  // namespace nestwalk::bench
