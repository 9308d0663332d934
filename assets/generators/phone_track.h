// A GPS track as a phone app records a walk (GPX 1.1): a fix every second along a walked line,
// each with a little position noise (normal, `noiseSigma` metres in each axis), the ground's
// height rounded to 0.1 m as `ele`, a UTC time, and a pause where the walker stood still (its fixes
// jitter about the same place). Waypoints (the instruments to look at) go in as <wpt>. Positions
// are written in WGS 84 with 8 decimals (about 1 mm). Deterministic for a seed.
// Units: metres, seconds, map coordinates of `crs`. Errors: std::runtime_error when a point
// cannot be transformed or has no ground. Thread safety: pure.
#pragma once

#include "nestwalk/terrain/heightfield.h"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace nestwalk::assets {

struct PhoneTrack {
  std::string name;
  std::vector<Eigen::Vector2d> legs;  // map points, walked in order at `speed`
  double speed = 1.3;                 // m/s
  std::size_t pauseAt = std::numeric_limits<std::size_t>::max();  // stands still on reaching legs[pauseAt]
  double pauseSeconds = 0;
  double noiseSigma = 0.05;                                        // m
  std::int64_t startUnixTime = 1777879800;                         // 2026-05-04T07:30:00Z
  std::vector<std::pair<std::string, Eigen::Vector2d>> waypoints;  // name, map point
};

std::string phoneTrackGpx(const PhoneTrack& track, const terrain::Heightfield& ground, const char* crs,
                          std::uint64_t seed);

}  // namespace nestwalk::assets
