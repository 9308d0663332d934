// The equipment tours of the bundled scene: two flythroughs that brush every kind of equipment,
// so that the methods report's figures (early stops, false blocks, stop gaps) rest on many
// blocking events on many kinds instead of one mast.
//
//   equipment_walk.txt  on foot at walking speed: for each target, fly high to a start a few
//                       metres from it, land, turn, walk at it at an angle to its face, expect to
//                       be blocked by its group, step back, expect to be free, take off;
//   equipment_fly.txt   in flight at 8 m/s, the body's bottom 0.6 m above the ground: the same
//                       approach from further off.
//
// Targets: for each kind (pole, piezometer, solar panel, logger box, weather-station mast, fence
// of barriers, container, pickup, drill rig) the first pieces in the scene's order that have a clear approach:
// a start on flat ground (walking: the berm's level within the generator's flat tolerance), from
// which the straight corridor to the piece (as wide as the body, with a margin) meets no other
// piece's footprint (for a fence, no piece of another group), approaching one of the piece's faces
// at the first of a few angles (0, 30, -45, 60, -20 degrees from its normal) that works. Targets
// are visited nearest first from the previous one. Everything follows from the placements, so the
// same seed gives the same tours.
#pragma once

#include "assets/generators/scene_generator.h"
#include "nestwalk/terrain/heightfield.h"

#include <string>
#include <vector>

namespace nestwalk::assets {

struct TourEvent {
  std::string group, kind;  // the group the script expects to be blocked by, and the piece's kind
  double angleDeg = 0;      // of the approach to the face's normal
};

struct Tour {
  std::string file;  // "equipment_walk.txt"
  std::string text;
  std::vector<TourEvent> events;
};

/// The two tours (see above); `header` starts each file. `topLevel`: the top's height, metres.
std::vector<Tour> equipmentTours(const terrain::Heightfield& hf, const std::vector<Placement>& equipment,
                                 double topLevel, const std::string& header);

}  // namespace nestwalk::assets
