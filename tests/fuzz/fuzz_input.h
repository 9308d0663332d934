// What every fuzz target shares: the input as text, and the rule that bad input must end in an
// InputError (which the target catches) and nothing else. Any other exception escapes and is a
// finding (the program would report it as an internal error); so are crashes, hangs, leaks and
// sanitizer reports. Each target is built twice: with libFuzzer (tools/fuzz.sh, clang) and, in
// the normal build, with replay_main.cpp, which runs its committed corpus as a test.
#pragma once

#include "nestwalk/core/input_error.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace nestwalk::fuzz {

inline std::string text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// Runs `parse`; an InputError is the expected answer to bad input.
template <class F>
void expectInputErrorOnly(F&& parse) {
  try {
    parse();
  } catch (const InputError&) {
  }
}

}  // namespace nestwalk::fuzz
