// The SIMD path of the float batches (engine/geometry/obb_batch.h) for a test's scope.
#pragma once

#include <array>
#include <cstdlib>
#include <optional>
#include <string>

namespace nestwalk {

/// Selects the SIMD path of the batches for the scope: "portable" forces SSE, "avx2" caps it at
/// AVX2 + FMA; null lets the library choose (the widest the processor has).
class ScopedSimd {
 public:
  explicit ScopedSimd(const char* value) {
    if (const char* old = std::getenv("NESTWALK_SIMD")) old_ = old;
    if (value)
      setenv("NESTWALK_SIMD", value, 1);
    else
      unsetenv("NESTWALK_SIMD");
  }
  ~ScopedSimd() {
    if (old_)
      setenv("NESTWALK_SIMD", old_->c_str(), 1);
    else
      unsetenv("NESTWALK_SIMD");
  }

 private:
  std::optional<std::string> old_;
};

/// Every path: the library's choice (the widest the processor has), at most AVX2 + FMA, then the
/// portable one (on a processor without AVX-512 the first two are the same kernel).
inline const std::array<const char*, 3> kSimdPaths = {nullptr, "avx2", "portable"};

}  // namespace nestwalk
