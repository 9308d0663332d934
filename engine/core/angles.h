// Angles in degrees, the unit of every heading, pitch and turn nestwalk reads or writes: headings
// are clockwise from north (map +y), seen from above; pitch is positive up. One home for the
// conversions and the wrapping, so that every module wraps the same way at the edges.
// Thread safety: pure functions.
#pragma once

#include <numbers>
#include <utility>

namespace nestwalk {

inline constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;
inline constexpr double kDegreesPerRadian = 180.0 / std::numbers::pi;

constexpr double radians(double degrees) { return degrees * kRadiansPerDegree; }
constexpr double degrees(double radians) { return radians * kDegreesPerRadian; }

/// The angle wrapped into [0, 360): -90 -> 270, 360 -> 0, 725 -> 5. Never returns 360: a tiny
/// negative angle (-1e-15), whose wrap rounds up to 360, gives 0. NaN and infinities give NaN.
double wrapDegrees360(double degrees);

/// The angle wrapped into (-180, 180]: 270 -> -90, -180 -> 180, 540 -> 180. NaN and infinities give
/// NaN.
double wrapDegrees180(double degrees);

/// The signed smallest turn from heading `from` to heading `to`, in (-180, 180] degrees (positive:
/// clockwise, to the right).
inline double turnBetween(double from, double to) { return wrapDegrees180(to - from); }

/// {sin, cos} of an angle in degrees, exact (0, +-1) at whole multiples of 90 degrees (so heading
/// 90 gives an exactly axis-aligned rotation); elsewhere std::sin and std::cos of the angle reduced
/// to (-360, 360) and converted to radians.
std::pair<double, double> sinCosDegrees(double degrees);

/// The heading (degrees clockwise from north, in [0, 360)) of the horizontal direction (east,
/// north); 0 for the zero vector.
double headingOf(double east, double north);

}  // namespace nestwalk
