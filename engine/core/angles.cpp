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

std::pair<double, double> sinCosDegrees(double degrees) {
  const double reduced = std::fmod(degrees, 360.0);  // exact
  if (reduced == std::trunc(reduced) && std::fmod(reduced, 90.0) == 0.0) {
    switch ((int(reduced) / 90 + 4) % 4) {
      case 0: return {0.0, 1.0};
      case 1: return {1.0, 0.0};
      case 2: return {0.0, -1.0};
      default: return {-1.0, 0.0};
    }
  }
  const double r = radians(reduced);
  return {std::sin(r), std::cos(r)};
}

double headingOf(double east, double north) {
  if (east == 0.0 && north == 0.0) return 0.0;
  return wrapDegrees360(degrees(std::atan2(east, north)));
}

}  // namespace nestwalk
