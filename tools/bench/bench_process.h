// What a benchmark sets or reads of its own process: an environment variable it sets for a while
// (the kernel testBoxPairs picks, the model cache's folder), its resident memory as Linux
// reports it (/proc/self/status), and where the shared real data lies.
// Thread safety: ScopedEnvironment calls setenv: not while other threads read the environment.
#pragma once

#include <optional>
#include <string>

namespace nestwalk::bench {

/// The shared real data (models, DEMs): NESTWALK_SHARED_DATA, else ../shared/data beside the
/// source tree. It may not exist.
std::string sharedDataFolder();

/// Sets the environment variable `name` to `value` while it lives (when `active`), then restores
/// what was there (or removes it).
class ScopedEnvironment {
 public:
  ScopedEnvironment(std::string name, const std::string& value, bool active = true);
  ~ScopedEnvironment();
  ScopedEnvironment(const ScopedEnvironment&) = delete;
  ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;

  /// Changes the value while it lives.
  void set(const std::string& value) const;

 private:
  std::string name_;
  bool active_;
  std::optional<std::string> saved_;
};

/// A line "KEY: N kB" of /proc/self/status (VmRSS: resident now, VmHWM: the peak), in MiB; nullopt
/// where there is none.
std::optional<double> processStatusMiB(const std::string& key);

}  // namespace nestwalk::bench
