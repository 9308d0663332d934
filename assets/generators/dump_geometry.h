// Where the generated mining dump's benches, berms and haul ramp lie, in the dump's own frame:
//   u along the long axis (azimuth layout.azimuthDeg, clockwise from north), v across it (azimuth
//   + 90), metres from the dump centre; map = centre + u * uAxis + v * vAxis.
// A berm is described by its inset s: the horizontal distance inside the dump's toe outline (a
// rounded rectangle, halfLength x halfWidth, corner radius cornerRadius). Bench k (1 .. benches-1)
// has its flat berm at level baseHeight + k * benchHeight for s in [crestInset(k), crestInset(k) +
// bermWidth]: from the crest of the face below to the toe of the face above. "Bench" `benches` is
// the flat top, at topHeight, for s >= crestInset(benches).
// The haul ramp runs along u at v = rampV (half width rampHalfWidth, metres), from u = rampStart
// (its toe, on the natural ground beyond the dump's end, at baseHeight) up to u = rampEnd on the
// top, at a constant grade.
// terrain/mining_dump.h publishes the layout but not the ramp and bench sizes: they are recomputed
// here with the generator's own formulas (terrain/mining_dump.cpp), and the assets tests check them
// against the generated heights.
#pragma once

#include "nestwalk/terrain/mining_dump.h"

#include <Eigen/Core>

namespace nestwalk::assets {

struct DumpGeometry {
  terrain::MiningDumpLayout layout;
  int benches = 0;            // number of benches; bench `benches` is the top
  double benchHeight = 0;     // metres
  double faceRun = 0;         // horizontal run of one face, metres
  double period = 0;          // faceRun + bermWidth
  double bermWidth = 0;
  double cornerRadius = 0;    // of the toe outline
  double rampV = 0, rampHalfWidth = 0, rampStart = 0, rampEnd = 0, rampGrade = 0;

  Eigen::Vector2d uAxis() const;  // unit map vectors of +u and +v
  Eigen::Vector2d vAxis() const;
  Eigen::Vector2d toMap(double u, double v) const;
  Eigen::Vector2d toDump(const Eigen::Vector2d& map) const;
  double bermLevel(int k) const { return layout.baseHeight + k * benchHeight; }
  double crestInset(int k) const { return (k - 1) * period + faceRun; }
  double rampHeight(double u) const;  // ground height on the ramp's surface at u (clamped to its ends)
};

DumpGeometry dumpGeometry(const terrain::MiningDumpParams& params, const terrain::MiningDumpLayout& layout);

}  // namespace nestwalk::assets
