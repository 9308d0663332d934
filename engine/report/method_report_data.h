// What the methods report (method_report.h) measured, between the plays (method_report.cpp) and
// the files written from it (method_report_files.h).
// Thread safety: plain values; aggregate() and reportTargets() are pure.
#pragma once

#include "nestwalk/core/targets.h"
#include "nestwalk/report/fitter_table.h"
#include "nestwalk/report/reference_comparison.h"
#include "nestwalk/report/run_contacts.h"
#include "nestwalk/report/terrain_lod_table.h"
#include "nestwalk/scene/method_spec.h"

#include <cmath>
#include <cstdint>
#include <iosfwd>
#include <limits>
#include <string>
#include <vector>

namespace nestwalk {

/// The methods in the report's order.
inline constexpr VolumeMethod kReportMethods[] = {VolumeMethod::Nested,     VolumeMethod::Aabb,   VolumeMethod::Obb,
                                                  VolumeMethod::NestedMesh, VolumeMethod::Kdop18, VolumeMethod::Auto};

/// One method on one flythrough.
struct PlayStats {
  std::string script;                               // file name
  std::size_t frames = 0;
  std::vector<double> totalMicros, collisionMicros;  // per frame, least over the timing plays
                                                    // (collision: broad + narrow phase)
  std::uint64_t bvTests = 0, triangleTests = 0;     // accuracy play: summed over its frames
  ReferenceTally tally;                             // accuracy play against the exact reference
  std::size_t equipmentBlocks = 0;                  // steps that ended blocked by equipment
  std::vector<double> gapsMm;                       // the stop gap after each of them
  std::vector<std::uint32_t> blockingEvents;        // the unit of each blocking event: a run of steps
                                                    // blocked by one unit (accuracy play)
  std::vector<RunContact> contacts;                 // the accuracy play's blocking events, terrain
                                                    // included, with exact stop gaps (contacts.gpkg)
  std::vector<std::size_t> nearTriangles;           // per frame (accuracy play): the triangles of the
                                                    // heaviest unit the step's sweep reached (the
                                                    // units whose outer AABB the body's swept outer
                                                    // AABB meets); 0: none
  std::string error;                                // why the flythrough could not be played ("": it was)
};

/// Plays summed up (one flythrough, or all of a method's).
struct Aggregate {
  std::size_t frames = 0;
  double p50 = 0, p99 = 0, mean = 0, collisionP50 = 0;  // µs per frame
  std::uint64_t sweeps = 0, blockedSweeps = 0, referenceContacts = 0, missed = 0;
  std::uint64_t earlyStops = 0, falseBlocks = 0;  // ReferenceTally's: blocked, the real geometry not
                                                  // touched, but (early stop) or not within
                                                  // kEarlyStopHorizon further on
  double falseBlockPercent = 0, earlyStopPercent = 0;  // of the blocked sweeps
  double earlyStopMaxMm = 0, earlyStopMeanMm = 0;      // how far short the early stops were (NaN: none)
  std::size_t blockingEvents = 0;
  std::size_t equipmentBlocks = 0, gaps = 0;
  double gapMeanMm = 0, gapMaxMm = 0;         // NaN without a gap
  std::uint64_t bvTests = 0, triangleTests = 0;
  double bvPerFrame = 0, trianglesPerFrame = 0;
};
Aggregate aggregate(const std::vector<const PlayStats*>& plays);

struct MethodResult {
  VolumeMethod method = VolumeMethod::Nested;
  std::vector<PlayStats> plays;  // one per flythrough, in the scripts' order
  Aggregate overall() const;
  bool complete() const {
    for (const PlayStats& p : plays)
      if (!p.error.empty()) return false;
    return true;
  }
};

/// A method's µs per step over the frames whose sweep reached a unit of one weight class (the
/// heaviest unit reached: kWeightClasses), timing plays against the accuracy play's frames.
struct WeightRow {
  VolumeMethod method = VolumeMethod::Nested;
  std::string weight;  // the class's name
  std::size_t frames = 0;
  double p50 = 0, p99 = 0, mean = 0;
};
/// The weight classes: the heaviest unit a step's sweep reached has at least `fromTriangles`
/// triangles (and fewer than the next class's); "none reached" below the first.
struct WeightClass {
  const char* name;
  std::size_t fromTriangles;
};
inline constexpr WeightClass kWeightClasses[] = {{"no unit reached", 0},    {"1-999 triangles", 1},
                                                 {"1k-9.9k triangles", 1000}, {"10k-99k triangles", 10000},
                                                 {"100k+ triangles", 100000}};
std::vector<WeightRow> weightRows(const std::vector<MethodResult>& methods);

/// Auto's choice for the units of one kind (walker/contact_choice.h).
struct AutoChoiceRow {
  std::string kind;
  std::size_t units = 0, exact = 0;  // units, and those that got the exact mesh stage
  std::size_t costly = 0;            // not tight, but the exact stage costs too much: nested only
  std::uint64_t mostTests = 0;       // the most tests a sample sweep made on a unit that is not tight
  double tightGapMaxMm = 0;          // nested-only units: the largest distance found from the box to
                                     // the triangles (all within kTightObbGap)
  double exactGapMinMm = NAN;        // exact-stage units: the smallest gap found that exceeded it
};

/// The blocking events of the exact reference's plays, per kind of the unit that blocked.
struct BlockingKindRow {
  std::string kind;
  std::size_t events = 0, units = 0;
};

struct ReportData {
  std::string scene, cpu, hierarchy;
  std::string crsWkt;  // the scene's (its terrain's): contacts.gpkg's CRS
  std::vector<std::string> scripts;  // file names
  bool quick = false;
  double hz = 60;
  std::size_t units = 0, instances = 0;
  int timingPlays = 1, fitterRepetitions = 1;
  std::size_t terrainPoints = 0;
  std::vector<MethodResult> methods;  // kReportMethods' order
  std::vector<AutoChoiceRow> autoChoices;
  std::vector<WeightRow> byWeight;
  std::vector<BlockingKindRow> blockingKinds;  // of the reference (nested+mesh) plays
  std::vector<TerrainLodRow> lod;
  std::vector<FitterRow> fitters;
  std::vector<Target> targets;
  struct {
    double timing = 0, accuracy = 0, terrain = 0, fitters = 0, total = 0;
  } seconds;
  const MethodResult* find(VolumeMethod m) const;
};

/// The issues' targets: no missed contact for any method; nested+mesh: no false block, stop gap
/// at most 1 mm, p50 µs per frame at most twice nested's (the same run); auto: no early stop longer
/// than 10 mm, no false block, mean µs per frame at most 1.2 times nested's; the figures resting
/// on at least 20 blocking events on at least 5 kinds.
std::vector<Target> reportTargets(const ReportData& d);


}  // namespace nestwalk
