// The bundled GIS sample behind `nestwalk make-scene DIR --gis-inputs`: the files a user of
// `nestwalk build-scene` brings, made from a generated dump the way a survey office would have
// them, so that the build can make a second bundled scene through the user's path
// (build/assets/gis_dump, from build/assets/gis_dump_inputs).
//
// The site: a dump generated as the bundled one (scene_generator.h) but at 62.5 N in UTM 33N
// (kGisSampleSite), 60 km east of the zone's central meridian, where grid north is about 1 degree
// off true north (the grid convergence), so a heading left unconverted is visibly wrong.
// Files written into DIR:
//   dem.tif            the heights as a plain GeoTIFF (float32, deflate, strips, not the engine's
//                      terrain format: build-scene imports it), in the site's UTM CRS
//   equipment.gpkg     EPSG:4326, longitude and latitude, written with OGR:
//                        layer "equipment": every piece that is not a barrier, a point with fields
//                          name, type (a catalog type), heading (azimuth from true north, clockwise,
//                          degrees: the generated grid heading plus the convergence, by PROJ's
//                          geodesic between points 0.5 m either side along the grid heading) and
//                          group;
//                        layer "fences": each run of barriers end to end, a line from its first
//                          piece's back end to its last piece's front end, fields name (the fence's
//                          group) and type
//   catalog.json       a type per model (scene/model_catalog.h): the generated models in metres,
//                      z up, except the pickup, written in millimetres, y up, with its origin mid-
//                      body (as a CAD export might be); the barrier a 3 m piece, use_only
//   models/            the models the catalog names
//   scripts/*.txt      the generated scene's flythroughs (map coordinates of the site): the patrol,
//                      the ramp descent, the low flight and the two equipment tours
//   routes/*.gpx       the generated scene's GPS tracks (phone_track.h): the patrol as a phone
//                      records it, for `nestwalk route` or `run --route` on the built scene
#pragma once

#include "assets/generators/scene_generator.h"

#include <string>

namespace nestwalk::assets {

inline constexpr SceneSite kGisSampleSite{560000.0, 6930000.0, "EPSG:32633"};

/// Writes the GIS inputs of `scene` (generated at kGisSampleSite) into `dir`, built under a
/// temporary name and renamed at the end; an existing `dir` is replaced only when `overwrite`.
void writeGisInputs(const GeneratedScene& scene, const std::string& dir, bool overwrite);

}  // namespace nestwalk::assets
