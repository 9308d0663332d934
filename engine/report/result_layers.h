// A run's results as GIS layers, for QGIS, ogrinfo and web maps: results.gpkg in the scene's CRS and
// results.geojson (RFC 7946: WGS 84 longitude, latitude, in plan; no crs member; the path,
// simplified within 1 cm, and the contacts, told apart by their "feature" field).
//
// results.gpkg, one layer each (positions: the eye, map frame):
//  - path: the walked line, LineStringZM (M: seconds from the start), one feature with the run's
//    summary fields (scene, script, method, frames, seconds, length_m, blocked_frames, contacts,
//    expectations_met, expectations_failed);
//  - contacts: a PointZ per blocking event (run_contacts.h): frame, time_s, unit, kind, group,
//    method, stop_gap_m, approach_deg (null where NaN);
//  - blocked: a LineStringZ per stretch of records blocked by one thing (the eye's positions; a
//    one-record stretch repeats its point): blocked_by, start_s, end_s, duration_s (records x dt),
//    frames;
//  - expectations: a PointZ per `expect` line where it was checked: script, line, text, met,
//    frame, detail;
//  - frames: a PointZ every `frameEvery` records (and the last), with frames.csv's columns as
//    fields (frame_csv.h: the same cells), for styling by speed or time per step.
// A scene whose terrain has no CRS gets results.gpkg without one and no results.geojson.
//
// Files are written under temporary names beside their targets and renamed (core/output_file.h).
// Errors: InputError naming the file. Thread safety: GDAL objects of its own; one writer per path.
#pragma once

#include "nestwalk/report/render_record.h"
#include "nestwalk/report/run_contacts.h"
#include "nestwalk/report/run_summary.h"
#include "nestwalk/walker/frame_record.h"

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace nestwalk {

inline constexpr std::size_t kDefaultFrameLayerEvery = 10;  // records per point of the frames layer

struct ResultLayerFiles {
  std::string gpkg;     // "" : not written
  std::string geojson;  // "" : not written (or the scene has no CRS)
};

/// Writes the layers (see above) as `base`.gpkg and `base`.geojson (a run: DIR/results; a walk
/// recorded in the window: walk_NNN); `crsWkt` is the scene's (its terrain's). Returns what was
/// written.
ResultLayerFiles writeResultLayers(const std::string& base, const std::string& crsWkt, const RunSummaryInfo& info,
                                   const std::vector<FrameRecord>& records,
                                   const std::vector<ExpectationResult>& expectations,
                                   const std::vector<RunContact>& contacts, std::span<const RenderRecord> renders = {},
                                   std::size_t frameEvery = kDefaultFrameLayerEvery);

/// Contacts of several plays in one layer (the methods report's contacts.gpkg, layer `contacts`):
/// the fields of results.gpkg's contacts plus `script`, `method` the set's.
struct ContactSet {
  std::string method, script;
  const std::vector<RunContact>* contacts = nullptr;
};
void writeContactsLayer(const std::string& path, const std::string& crsWkt, const std::vector<ContactSet>& sets);

}  // namespace nestwalk
