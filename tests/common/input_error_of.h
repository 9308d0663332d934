// The message of the InputError a call throws, for tests of bad input (scene files, DEMs, imagery).
#pragma once

#include "nestwalk/core/input_error.h"

#include <gtest/gtest.h>

#include <string>

namespace nestwalk::test {

/// The message of the InputError `f` throws ("" and a test failure when it throws none).
template <class F>
std::string inputError(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return {};
}

}  // namespace nestwalk::test
