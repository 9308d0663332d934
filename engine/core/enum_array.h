// A fixed array indexed by an enum's values (0 .. N-1), so that code names the part it means
// (times[StepPart::Ground]) instead of a number.
// Thread safety: a plain value type, as std::array.
#pragma once

#include <array>
#include <cstddef>

namespace nestwalk {

template <class Enum, std::size_t N, class T = double>
struct EnumArray {
  std::array<T, N> values{};

  T& operator[](Enum e) { return values[std::size_t(e)]; }
  const T& operator[](Enum e) const { return values[std::size_t(e)]; }
  static constexpr std::size_t size() { return N; }
  auto begin() { return values.begin(); }
  auto end() { return values.end(); }
  auto begin() const { return values.begin(); }
  auto end() const { return values.end(); }
  bool operator==(const EnumArray&) const = default;
};

}  // namespace nestwalk
