// The renderer's projection rule for the terrain's level of detail: a surface whose exact vertical
// error is E metres may be drawn where the eye is at least distanceFor(E) from every point of it,
// so that E projects to at most maxPixels on a screen screenHeightPx high with vertical field of
// view fovYDegrees: pixels = E * screenHeightPx / (2 tan(fovY / 2)) / distance.
// Units: degrees, pixels, metres. Thread safety: a plain value type.
#pragma once

#include <cmath>
#include <numbers>

namespace nestwalk::terrain {

struct LodRule {
  double fovYDegrees = 60.0;
  double screenHeightPx = 720.0;  // 1280 x 720
  double maxPixels = 1.0;
  /// Pixels per metre of error at distance 1 m (about 623.5 for the defaults).
  double pixelsPerRadian() const {
    return screenHeightPx / (2.0 * std::tan(0.5 * fovYDegrees * std::numbers::pi / 180.0));
  }
  /// The smallest distance at which an error of `error` metres projects to at most maxPixels.
  double distanceFor(double error) const { return error > 0 ? error * pixelsPerRadian() / maxPixels : 0.0; }
};

}  // namespace nestwalk::terrain
