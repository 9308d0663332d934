// The error every loader and parser throws for bad input: its message names the file (and line or
// field where there is one) and the problem, ready to be shown to the user as it is.
// Thread safety: an immutable value, as std::runtime_error.
#pragma once

#include <stdexcept>
#include <string>

namespace nestwalk {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace nestwalk
