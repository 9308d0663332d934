#include "nestwalk/core/angles.h"

#include <cmath>

namespace nestwalk {

double wrapDegrees360(double degrees) {
  double w = std::fmod(degrees, 360.0);  // exact, sign of the argument; NaN for NaN and infinity
  if (w < 0.0) w += 360.0;               // may round up to 360 for a tiny negative w
  return w >= 360.0 ? 0.0 : w;
}

double wrapDegrees180(double degrees) {
  double w = std::fmod(degrees, 360.0);  // (-360, 360)
  if (w > 180.0) w -= 360.0;
  else if (w <= -180.0) w += 360.0;
  return w;
}

double headingOf(double east, double north) {
  if (east == 0.0 && north == 0.0) return 0.0;
  return wrapDegrees360(degrees(std::atan2(east, north)));
}

}  // namespace nestwalk
