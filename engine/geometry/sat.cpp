#include "nestwalk/geometry/sat.h"

namespace nestwalk {

const char* satAxisName(int axis) {
  static const char* const names[15] = {"A0",    "A1",    "A2",    "B0",    "B1",
                                        "B2",    "A0xB0", "A0xB1", "A0xB2", "A1xB0",
                                        "A1xB1", "A1xB2", "A2xB0", "A2xB1", "A2xB2"};
  return axis >= 0 && axis < 15 ? names[axis] : "";
}

const char* aabbAxisName(int axis) {
  static const char* const names[3] = {"x", "y", "z"};
  return axis >= 0 && axis < 3 ? names[axis] : "";
}

}  // namespace nestwalk
