// Options shared by the commands that walk a scene (`run`, `view`): the frame size and the
// contact-method overrides of the scene's own. Errors are InputError naming the option.
#pragma once

#include "nestwalk/scene/method_spec.h"

#include <string>
#include <utility>

namespace nestwalk::tools {

// WIDTHxHEIGHT, each 16 to 8192 pixels.
std::pair<int, int> parseFrameSize(const std::string& text);

// --method, --hierarchy, --degree, --split-axis, --split-point as given (empty or 0: the scene's).
struct MethodOverrides {
  std::string volumes, hierarchy, splitAxis, splitPoint;
  int degree = 0;
};
MethodSpec applyMethodOverrides(const MethodOverrides& o, MethodSpec m);

}  // namespace nestwalk::tools
