// The bundled mining-dump scene behind `nestwalk make-scene`: the terrain (terrain/mining_dump.h,
// 1 km at 1 m), its synthetic orthophoto (terrain/mining_dump_ortho.h), the equipment models (equipment_models.h), scene.json (schema:
// engine/scene/scene_file.h) and five flythrough scripts (format: engine/walker/script.h) that
// use the scene's own coordinates: a patrol blocked by a mast, the ramp's descent, a low flight,
// and the two equipment tours (equipment_tours.h). Everything follows from the seed (same seed, byte-identical
// scene.json, models and scripts); random numbers come from std::mt19937_64's raw output, not from
// library distributions.
//
// Placement (dump frame and berm insets: dump_geometry.h). On every berm and along the top's edge,
// across the berm from its crest (w metres inside the crest):
//   w = kFenceLineW   fence lines of jersey barriers end to end (groups bench{k}/fence{j}, the
//                     segments `use_only`: one obstacle per line);
//   w = kLaneW        the walking lane, kept free ...
//   w = kInnerLineW   ... of the monitoring stations (groups bench{k}/station{j}: a mast, a logger
//                     box and a solar panel), sensor poles and piezometers on the inner line;
// except one station whose mast stands on the lane of bench 2 (patrolStation) for the patrol
// script. Only the straight parts of each berm are used. The top also holds a container yard
// (bench{top}/yard0) and two pickups (bench{top}/vehicle{j}). Every piece stands on flat berm: its
// footprint's corners and centre lie within kFlatTolerance of the berm level on the generated
// grid; pieces of different groups keep kGroupGap between their footprints; nothing is placed on
// the haul ramp's corridor or at its head.
#pragma once

#include "assets/generators/dump_geometry.h"
#include "assets/generators/equipment_models.h"
#include "nestwalk/terrain/mining_dump.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace nestwalk::assets {

inline constexpr double kFenceLineW = 2.0;   // metres inside the crest: barrier centre line
inline constexpr double kLaneW = 4.0;        // walking lane centre line
inline constexpr double kInnerLineW = 6.3;   // inner equipment line (1.7 m short of the face above)
inline constexpr double kFlatTolerance = 0.2;  // metres: footprint heights vs berm level (roughness is 5 cm)
inline constexpr double kGroupGap = 1.0;     // metres between footprints of different groups
inline constexpr double kRampMargin = 5.0;   // metres kept clear on each side of the ramp's corridor
inline constexpr double kRampHeadClear = 40.0;  // metres kept clear on the top beyond the ramp's end

struct Placement {
  std::string name;   // "<group>/<part>", unique
  std::string group;  // "bench2/station3"
  ModelKind model = ModelKind::SensorPole;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  // map, rounded to the millimetre
  double headingDeg = 0;  // clockwise from north, rounded to 1e-3 degrees
  bool useOnly = false;
  int bench = 0;       // the berm it stands on (benches = the top)
  double level = 0;    // that berm's level, metres
};

/// Key points of the scripts (map coordinates), for reports and tests.
struct ScriptPoints {
  std::string patrolStation;  // group of the station standing in the lane
  Eigen::Vector2d patrolStart, patrolTarget, patrolBlockedAt, patrolEnd, patrolMast;
  double patrolHeading = 0;
  Eigen::Vector2d rampTop, rampToe;
  double rampHeading = 0;
  Eigen::Vector2d flightStart, flightOverYard, flightEnd;
  double flightHeading = 0;
};

/// Where the dump lies: its area's centre in a projected CRS (metres, x east, y north) and that CRS.
/// The default is the bundled scene's (terrain/mining_dump.h: UTM 51N).
struct SceneSite {
  double centreE = 550000.0, centreN = 4650000.0;
  const char* crs = terrain::kMiningDumpCrs;
};

struct GeneratedScene {
  std::uint64_t seed = 1;
  SceneSite site;
  terrain::MiningDumpParams params;
  terrain::MiningDump dump;
  DumpGeometry geometry;
  std::vector<Placement> equipment;
  ScriptPoints points;
  std::string sceneJson;                                      // scene.json's text
  std::vector<std::pair<std::string, std::string>> scripts;  // file name (in scripts/), text
  std::vector<std::pair<std::string, std::string>> routes;   // file name (in routes/), GPX text
  std::vector<std::pair<std::string, std::vector<std::pair<std::string, std::string>>>> tourEvents;
      // per equipment tour (equipment_tours.h): its file and the (group, kind) of each blocking event
};

/// Generates the scene in memory (terrain grid, placements, JSON, scripts). Takes about a second.
GeneratedScene generateScene(std::uint64_t seed, const SceneSite& site = {});

/// Writes the scene into `dir`: terrain.tif, ortho.tif (the synthetic orthophoto, its noise seeded
/// with the scene's seed; scene.json names it as the "imagery": on the terrain's grid when
/// orthoPixel is 0 or the terrain's cell, terrain/mining_dump_ortho.h, else a drone's orthophoto at
/// orthoPixel metres, finer than the cell, with the ground's texture, writeFineMiningDumpOrtho), models/*.osgt, scene.json, scripts/*.txt, routes/*.gpx (GPS tracks for
/// `nestwalk route` and `run --route`, phone_track.h). `dir` is
/// built under a temporary name beside it and renamed to `dir` at the end; an existing `dir` is
/// replaced only when `overwrite` (else InputError, and it is left as it was).
void writeScene(const GeneratedScene& scene, const std::string& dir, bool overwrite, double orthoPixel = 0);

}  // namespace nestwalk::assets
