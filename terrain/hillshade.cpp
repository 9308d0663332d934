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
  const double centre = hf.sample(col, row);
  auto usable = [&](int c, int r) { return c >= 0 && r >= 0 && c < hf.cols() && r < hf.rows() && hf.valid(c, r); };
  // Neighbour (col + dc, row + dr); a missing one extrapolated through the centre.
  auto z = [&](int dc, int dr) -> double {
    dc *= step;
    dr *= step;
    if (usable(col + dc, row + dr)) return hf.sample(col + dc, row + dr);
    if (usable(col - dc, row - dr)) return 2 * centre - hf.sample(col - dc, row - dr);
    return centre;
  };
  // Rows run south: dr = -1 is the northern neighbour.
  const double dzdx = ((z(1, -1) + 2 * z(1, 0) + z(1, 1)) - (z(-1, -1) + 2 * z(-1, 0) + z(-1, 1))) / (8 * step * hf.dx());
  const double dzdy = ((z(-1, -1) + 2 * z(0, -1) + z(1, -1)) - (z(-1, 1) + 2 * z(0, 1) + z(1, 1))) / (8 * step * hf.dy());
  return std::max(0.0, Eigen::Vector3d(-dzdx, -dzdy, 1).normalized().dot(sun));
}

}  // namespace nestwalk::terrain
