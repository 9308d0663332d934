// Horn's hillshade at a sample (hillshade.h). Horn, B. K. P. (1981), "Hill shading and the
// reflectance map", Proc. IEEE 69(1): the slope from the 3 x 3 neighbourhood with weights 1-2-1.
#include "nestwalk/terrain/hillshade.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace nestwalk::terrain {

Eigen::Vector3d sunDirection(double azimuthDeg, double altitudeDeg) {
  const double az = azimuthDeg * std::numbers::pi / 180, alt = altitudeDeg * std::numbers::pi / 180;
  return {std::cos(alt) * std::sin(az), std::cos(alt) * std::cos(az), std::sin(alt)};
}

double hornShade(const Heightfield& hf, int col, int row, const Eigen::Vector3d& sun, int step) {
  return hornShadeOf(
      [&](int c, int r) { return hf.valid(c, r) ? hf.sample(c, r) : std::numeric_limits<float>::quiet_NaN(); },
      hf.cols(), hf.rows(), hf.dx(), hf.dy(), col, row, sun, step);
}

}  // namespace nestwalk::terrain
