// The blocking events of a run, read from its records: where the walker was stopped, by what, how
// it came at it and how far it stopped from the real surface. What the results layers map
// (result_layers.h) and what a reader compares methods by (an early stop shows as a large gap).
//
// An event starts at a blocked record whose previous record was free or blocked by something else.
// Its position is the eye's at that record. For equipment:
//  - approach_deg: the angle between the horizontal direction the walker last moved in (before or
//    at the event; its heading when it had not moved) and the horizontal direction from the body
//    box's centre to the nearest point of the unit's inner box: 0 head-on, 90 grazing;
//  - stop_gap_m: the exact distance from the body box to the unit's triangles: through the
//    caller's MeshWorld (a mesh method's trees) when given, else by a scan of the unit's triangles
//    that skips those whose box is already farther than the best so far (exact; about 10 ns a
//    triangle, so a run pays for the models it met, not for building their trees).
// Terrain blocks ("terrain:step", ...) have kind "terrain" and NaN angle and gap.
//
// Units: metres, seconds, degrees; positions in the map frame. Thread safety: pure.
#pragma once

#include "nestwalk/scene/scene.h"
#include "nestwalk/walker/frame_record.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace nestwalk {

class MeshWorld;

struct RunContact {
  std::uint64_t frame = 0;
  double time = 0;
  Eigen::Vector3d eye = Eigen::Vector3d::Zero();  // map frame
  std::string unit, kind, group;                  // unit: its name, or the terrain reason
  double approachDeg = 0;                         // NaN for the terrain
  double stopGapM = 0;                            // NaN for the terrain
};

std::vector<RunContact> runContacts(const Scene& scene, const std::vector<FrameRecord>& records,
                                    const MeshWorld* meshes = nullptr);

}  // namespace nestwalk
