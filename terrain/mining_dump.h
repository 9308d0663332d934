// The bundled mining-dump DEM behind `nestwalk make-terrain`: a terraced waste dump on gently
// undulating natural ground, in UTM zone 51N (EPSG:32651) around E 550 km, N 4650 km.
//
// The dump is a rounded rectangle (long axis at a seed-chosen azimuth) built of benches: each bench
// rises benchHeight (10 m) on a face of faceSlopeDeg (35 degrees) measured along the true horizontal
// distance to the footprint (an exact signed distance, so the face slope is the same everywhere,
// corners included), then a flat berm of bermWidth, up to a flat top. A straight haul ramp (10 %
// grade, 20 m wide, 35-degree side slopes where it cuts into or stands out of the dump) climbs from
// the ground to the top; conical pits and a V-shaped drainage ditch along the toe are cut into the
// natural ground; small smooth roughness (centimetres) covers everything. Same seed, same heights:
// every random choice comes from a std::mt19937_64 whose raw output is turned into numbers here (no
// library distributions), so the result does not depend on the standard library.
// Thread safety: a pure function (its generator is local to the call).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace nestwalk::terrain {

struct MiningDumpParams {
  std::uint64_t seed = 1;
  double size = 1000.0;       // side of the square area, metres
  double cell = 1.0;          // cell size, metres
  double centreE = 550000.0;  // UTM 51N easting of the area's centre
  double centreN = 4650000.0;
  double benchHeight = 10.0;
  double faceSlopeDeg = 35.0;
  double bermWidth = 8.0;
  int benches = 4;
};

/// Where the dump lies (for the summary and for tests that measure it).
struct MiningDumpLayout {
  double centreE = 0, centreN = 0;  // dump centre
  double azimuthDeg = 0;            // long axis, degrees clockwise from north
  double halfLength = 0, halfWidth = 0;
  double baseHeight = 0;  // level of the dump's toe; bench k's berm is at baseHeight + k * benchHeight
  double topHeight = 0;
};

struct MiningDump {
  int cols = 0, rows = 0;
  double originX = 0, originY = 0;  // centre of sample (0, 0), row 0 north
  double cell = 1.0;
  std::vector<float> heights;  // row-major, metres
  MiningDumpLayout layout;
};

inline constexpr const char* kMiningDumpCrs = "EPSG:32651";

/// Generates the grid (std::invalid_argument for a non-positive size or cell, or too few cells).
MiningDump generateMiningDump(const MiningDumpParams& params);

}  // namespace nestwalk::terrain
