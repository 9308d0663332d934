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
//
// Surfaces: the generator also records, per sample, which of its parts set the height there
// (DumpSurface): the synthetic orthophoto (mining_dump_ortho.h) colours the dump by it. The rule,
// in the order the heights are built (a later part overrides an earlier one where it changes the
// height): natural Ground; inside the toe outline where the bench profile stands above the ground,
// Face (on a face's run: the first faceRun metres of each bench period, inset from the toe), Berm
// (the rest of the period) or Top (beyond the last face's crest); Ditch where the drainage ditch's V lowers
// the ground (2 m either side of its axis, 8 m outside the toe); Ramp on the haul ramp's running
// surface (within its half width and between its ends), RampSide where its cut or fill slopes
// change the height; Pit inside a pit's rim. The centimetre roughness changes no surface.
// Thread safety: generateMiningDump is a pure function; a MiningDumpGenerator is immutable once
// constructed (generateRows may run on several threads at once).
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
  /// Relief down to the cell (the drone case: stones, ruts): value-noise octaves from 2 m wavelength
  /// (kFineReliefAmplitudeM) down to two cells, each half the last's amplitude. Off: the smooth
  /// centimetre roughness alone.
  bool fineRelief = false;
};

/// Fine relief (MiningDumpParams::fineRelief): the longest octave's wavelength and amplitude, metres.
inline constexpr double kFineReliefLongestM = 2.0;
inline constexpr double kFineReliefAmplitudeM = 0.04;
/// generateMiningDump holds at most this many samples (1.6 GB of heights); MiningDumpGenerator
/// streams any size up to kMaxMiningDumpCellsPerSide a side.
inline constexpr double kMaxHeldMiningDumpSamples = 4.0e8;
inline constexpr int kMaxMiningDumpCellsPerSide = 65536;

/// Where the dump lies (for the summary and for tests that measure it).
struct MiningDumpLayout {
  double centreE = 0, centreN = 0;  // dump centre
  double azimuthDeg = 0;            // long axis, degrees clockwise from north
  double halfLength = 0, halfWidth = 0;
  double baseHeight = 0;  // level of the dump's toe; bench k's berm is at baseHeight + k * benchHeight
  double topHeight = 0;
  /// The haul ramp's running surface: across the long axis (v, azimuth + 90 degrees, metres from the
  /// centre) its axis lies at rampV and it is 2 rampHalfWidth wide; along the long axis (u) it runs
  /// from rampStartU (on the ground beyond the dump's end) to rampEndU (on the top).
  double rampV = 0, rampHalfWidth = 0, rampStartU = 0, rampEndU = 0;
};

/// What set the height at a sample (see "Surfaces" above).
enum class DumpSurface : std::uint8_t { Ground, Ditch, Pit, Face, Berm, Top, Ramp, RampSide };
inline constexpr int kDumpSurfaceCount = 8;

/// The surface's name for messages and tests ("ground", "ditch", "pit", "face", "berm", "top",
/// "ramp", "ramp side").
const char* dumpSurfaceName(DumpSurface surface);

struct MiningDump {
  int cols = 0, rows = 0;
  double originX = 0, originY = 0;  // centre of sample (0, 0), row 0 north
  double cell = 1.0;
  std::vector<float> heights;  // row-major, metres
  std::vector<DumpSurface> surfaces;  // row-major like heights: what set each sample's height
  MiningDumpLayout layout;
};

inline constexpr const char* kMiningDumpCrs = "EPSG:32651";

/// The dump's heights row by row, for grids too large to hold (make-terrain streams them into the
/// terrain file). The same heights as generateMiningDump, bit for bit.
class MiningDumpGenerator {
 public:
  /// std::invalid_argument for a non-positive size or cell, fewer than 16 or more than
  /// kMaxMiningDumpCellsPerSide cells a side.
  explicit MiningDumpGenerator(const MiningDumpParams& params);
  int cols() const { return n_; }
  int rows() const { return n_; }
  double originX() const { return originX_; }  // centre of sample (0, 0), row 0 north
  double originY() const { return originY_; }
  const MiningDumpLayout& layout() const { return layout_; }
  /// Rows [r0, r0 + count): count * cols() heights, and as many surfaces when `surfaces` is not null.
  void generateRows(int r0, int count, float* heights, DumpSurface* surfaces = nullptr) const;

 private:
  struct Pit {
    double e, n, radius, depth;
  };
  double ground(double e, double n) const;
  MiningDumpParams p_;
  int n_ = 0;
  double side_ = 0, originX_ = 0, originY_ = 0;
  MiningDumpLayout layout_;
  double baseLevel_ = 0, planeAz_ = 0, planeGrade_ = 0;
  std::uint64_t groundSeed_ = 0, roughSeed_ = 0;
  double faceRun_ = 0, period_ = 0, radius_ = 0;
  int benches_ = 1;
  double ae_ = 0, an_ = 0, be_ = 0, bn_ = 0;
  double rampV_ = 0, rampStart_ = 0, rampEnd_ = 0, rampGrade_ = 0, sideTan_ = 0;
  std::vector<Pit> pits_;
  int fineOctaves_ = 0;
};

/// Generates the grid (std::invalid_argument for a non-positive size or cell, too few cells or more
/// than kMaxHeldMiningDumpSamples).
MiningDump generateMiningDump(const MiningDumpParams& params);

}  // namespace nestwalk::terrain
