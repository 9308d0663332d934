#include "nestwalk/report/method_report_files.h"

#include "nestwalk/core/output_file.h"
#include "nestwalk/core/number_text.h"
#include "nestwalk/plot/charts.h"
#include "nestwalk/report/result_layers.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <filesystem>
#include <iomanip>
#include <ostream>
#include <sstream>

namespace nestwalk {
namespace {

using Json = nlohmann::ordered_json;
using Table = std::vector<std::vector<std::string>>;  // header row first

Rgb methodColour(VolumeMethod m) {
  switch (m) {
    case VolumeMethod::Nested: return {31, 119, 180};      // blue
    case VolumeMethod::Aabb: return {255, 127, 14};        // orange
    case VolumeMethod::Obb: return {44, 160, 44};          // green
    case VolumeMethod::NestedMesh: return {214, 39, 40};   // red
    case VolumeMethod::Kdop18: return {148, 103, 189};     // purple
    case VolumeMethod::Auto: return {23, 190, 207};        // cyan
  }
  return {0, 0, 0};
}

std::string count(std::uint64_t n) { return std::to_string(n); }

/// "12 (3.4 %)": a count and its share of the blocked sweeps.
std::string ofBlocked(std::uint64_t n, double percent) { return count(n) + " (" + fixedText(percent, 1) + " %)"; }

std::string gap(const Aggregate& a) {
  return a.gaps ? fixedText(a.gapMeanMm, 3) + " / " + fixedText(a.gapMaxMm, 3) : "- (no block)";
}

Table methodTable(const ReportData& d) {
  Table t{{"method", "us/frame p50", "p99", "mean", "x nested", "missed", "blocked sweeps", "early stops (%)",
           "longest early stop mm", "false blocks (%)", "stop gap mean / max mm", "BV tests/frame",
           "triangle tests/frame"}};
  const MethodResult* nested = d.find(VolumeMethod::Nested);
  const double base = nested ? nested->overall().p50 : std::nan("");
  for (const MethodResult& m : d.methods) {
    const Aggregate a = m.overall();
    t.push_back({std::string(volumeMethodName(m.method)) + (m.complete() ? "" : " (incomplete)"), fixedText(a.p50, 2),
                 fixedText(a.p99, 2), fixedText(a.mean, 2), fixedText(a.p50 / base, 2), count(a.missed), count(a.blockedSweeps),
                 ofBlocked(a.earlyStops, a.earlyStopPercent), a.earlyStops ? fixedText(a.earlyStopMaxMm, 2) : "-",
                 ofBlocked(a.falseBlocks, a.falseBlockPercent), gap(a),
                 fixedText(a.bvPerFrame, 1), fixedText(a.trianglesPerFrame, 1)});
  }
  return t;
}

Table flythroughTable(const ReportData& d) {
  Table t{{"flythrough", "method", "frames", "us/frame p50", "p99", "collision us p50", "missed", "blocked sweeps",
           "early stops", "false blocks", "blocked steps", "stop gap mean / max mm", "BV tests/frame"}};
  for (std::size_t s = 0; s < d.scripts.size(); ++s)
    for (const MethodResult& m : d.methods) {
      const PlayStats& p = m.plays[s];
      if (!p.error.empty()) {
        std::vector<std::string> row(t[0].size(), "-");
        row[0] = d.scripts[s];
        row[1] = volumeMethodName(m.method);
        row[2] = "not played: " + p.error;
        t.push_back(row);
        continue;
      }
      const Aggregate a = aggregate({&p});
      t.push_back({d.scripts[s], volumeMethodName(m.method), count(a.frames), fixedText(a.p50, 2), fixedText(a.p99, 2),
                   fixedText(a.collisionP50, 2), count(a.missed), count(a.blockedSweeps), count(a.earlyStops),
                   count(a.falseBlocks), count(a.equipmentBlocks), gap(a), fixedText(a.bvPerFrame, 1)});
    }
  return t;
}

Table nestedTable(const ReportData& d) {
  Table t{{"flythrough", "blocked sweeps", "early stops", "false blocks", "false-block rate",
           "stopped-short rate (early stops + false blocks)", "steps blocked by equipment", "stop gap mean mm",
           "stop gap max mm"}};
  const MethodResult* nested = d.find(VolumeMethod::Nested);
  if (!nested) return t;
  for (std::size_t s = 0; s < d.scripts.size(); ++s) {
    const Aggregate a = aggregate({&nested->plays[s]});
    const bool blocked = a.blockedSweeps > 0;
    t.push_back({d.scripts[s], count(a.blockedSweeps), count(a.earlyStops), count(a.falseBlocks),
                 blocked ? fixedText(a.falseBlockPercent, 1) + " %" : "- (no blocked sweep)",
                 blocked ? fixedText(a.falseBlockPercent + a.earlyStopPercent, 1) + " %" : "-", count(a.equipmentBlocks),
                 fixedText(a.gapMeanMm, 3), fixedText(a.gapMaxMm, 3)});
  }
  return t;
}

Table autoTable(const ReportData& d) {
  Table t{{"kind", "units", "nested only", "exact stage", "nested only: largest gap found mm",
           "exact stage: smallest gap found mm", "too costly for the exact stage", "most tests a sample sweep made"}};
  for (const AutoChoiceRow& r : d.autoChoices)
    t.push_back({r.kind, count(r.units), count(r.units - r.exact), count(r.exact),
                 r.units > r.exact + r.costly ? fixedText(r.tightGapMaxMm, 3) : "-",
                 r.exact ? fixedText(r.exactGapMinMm, 1) : "-", count(r.costly), count(r.mostTests)});
  return t;
}

Table weightTable(const ReportData& d) {
  Table t{{"heaviest unit the step reached", "method", "frames", "us/frame p50", "p99", "mean"}};
  for (const WeightClass& c : kWeightClasses)
    for (const WeightRow& r : d.byWeight)
      if (r.weight == c.name)
        t.push_back({r.weight, volumeMethodName(r.method), count(r.frames), fixedText(r.p50, 2), fixedText(r.p99, 2),
                     fixedText(r.mean, 2)});
  return t;
}

Table blockingTable(const ReportData& d) {
  Table t{{"kind", "blocking events", "units that blocked"}};
  for (const BlockingKindRow& r : d.blockingKinds) t.push_back({r.kind, count(r.events), count(r.units)});
  return t;
}

Table lodTable(const ReportData& d) {
  Table t{{"level", "step", "chunks", "max error m (table)", "measured max m", "measured mean m", "points",
           "ns/query"}};
  for (const TerrainLodRow& r : d.lod)
    t.push_back({r.level < 0 ? "full resolution (Heightfield::groundHeight)" : r.name, std::to_string(r.step),
                 r.level < 0 ? "-" : count(r.chunks), r.level < 0 ? "0" : shortText(r.tableMaxError), shortText(r.maxError),
                 shortText(r.meanError), count(r.points), fixedText(r.nsPerQuery, 1)});
  return t;
}

Table fitterTable(const ReportData& d) {
  Table t{{"model", "triangles", "vertices", "hull points", "covariance m3", "hull-search m3", "CGAL optimal m3",
           "covariance / optimal", "hull-search / optimal", "covariance us", "hull-search us", "CGAL us"}};
  for (const FitterRow& r : d.fitters)
    t.push_back({r.model, count(r.triangles), count(r.vertices), count(r.hullPoints), shortText(r.covarianceVolume),
                 shortText(r.hullSearchVolume), shortText(r.optimalVolume), fixedText(r.covarianceVolume / r.optimalVolume, 4),
                 fixedText(r.hullSearchVolume / r.optimalVolume, 4), fixedText(r.covarianceMicros, 0), fixedText(r.hullSearchMicros, 0),
                 fixedText(r.optimalMicros, 0)});
  return t;
}

/// A Markdown table; columns after the first `textColumns` are right-aligned.
std::string markdown(const Table& t, std::size_t textColumns = 1) {
  std::ostringstream s;
  for (std::size_t r = 0; r < t.size(); ++r) {
    s << "|";
    for (const std::string& cell : t[r]) s << " " << cell << " |";
    s << "\n";
    if (r == 0) {
      s << "|";
      for (std::size_t c = 0; c < t[0].size(); ++c) s << (c < textColumns ? "---|" : "---:|");
      s << "\n";
    }
  }
  return s.str();
}

/// A plain-text table with padded columns.
std::string plain(const Table& t) {
  std::vector<std::size_t> w;
  for (const auto& row : t)
    for (std::size_t c = 0; c < row.size(); ++c) {
      if (w.size() <= c) w.push_back(0);
      w[c] = std::max(w[c], row[c].size());
    }
  std::ostringstream s;
  for (const auto& row : t) {
    for (std::size_t c = 0; c < row.size(); ++c)
      s << (c ? "  " : "") << (c ? std::right : std::left) << std::setw(int(w[c])) << row[c];
    s << "\n";
  }
  return s.str();
}

std::string targetLines(const std::vector<Target>& targets) {
  std::ostringstream s;
  for (const Target& x : targets)
    s << "- " << x.name << ": "
      << (std::isnan(x.value)                ? "none (no step blocked by equipment)"
          : x.value == std::floor(x.value) ? fixedText(x.value, 0)
                                           : shortText(x.value))
      << " (target " << x.what << "): **" << (x.met ? "met" : "NOT met") << "**\n";
  return s.str();
}

std::string reportMarkdown(const ReportData& d) {
  std::ostringstream s;
  s << "# nestwalk methods report\n\n";
  s << "- scene: `" << d.scene << "` (" << d.units << " collision units, " << d.instances << " instances; method "
    << "settings of the scene: " << d.hierarchy << ")\n";
  s << "- flythroughs:";
  const MethodResult* nested = d.find(VolumeMethod::Nested);
  for (std::size_t i = 0; i < d.scripts.size(); ++i)
    s << (i ? ", " : " ") << "`" << d.scripts[i] << "` (" << (nested ? count(nested->plays[i].frames) : "?")
      << " frames)";
  s << " with nested (the frame counts of the other methods differ where they stop elsewhere), fixed step at "
    << fixedText(d.hz, 0) << " Hz\n";
  s << "- settings: " << (d.quick ? "quick" : "full") << ": " << d.timingPlays
    << " timing play(s) per method and flythrough (each frame's time is the least over the plays), " << d.terrainPoints
    << " terrain points, " << d.fitterRepetitions << " fit(s) per model and fitter\n";
  s << "- cpu: " << d.cpu << "\n";
  s << "- run time: timing " << fixedText(d.seconds.timing, 1) << " s, accuracy " << fixedText(d.seconds.accuracy, 1)
    << " s, terrain " << fixedText(d.seconds.terrain, 1) << " s, fitters " << fixedText(d.seconds.fitters, 1) << " s, total "
    << fixedText(d.seconds.total, 1) << " s\n\n";

  s << "## Contact methods\n\n"
    << "Every method plays every flythrough in timing plays and one accuracy play. The timing plays measure the "
       "walker's own µs per step (ground following, broad and narrow phase; each frame's time is the least over "
       "the plays, which step alike). The accuracy play runs every sweep also on the exact "
       "reference (nested+mesh: the body box against the models' real triangles, its contacts found by "
       "conservative advancement on exact distances, independent of the swept tests the methods use) and "
       "compares: a contact is *missed* when the reference touches the real geometry before the method's "
       "contact (or the method finds none). A sweep the method stops while its path touches no triangle is an *early stop* when the real "
       "geometry lies further along the same direction (within "
    << shortText(kEarlyStopHorizon) << " m: the volumes stop the body short of it) and a "
       "*false block* when it does not (the body is stopped where nothing real is in the way); percentages are of "
       "the method's blocked sweeps. The *stop gap* is "
       "the exact distance from the body box to the nearest triangles after each step that ended blocked by "
       "equipment. BV tests: the hierarchy's nodes, the three nested stages and the mesh trees' nodes; triangle "
       "tests: the mesh methods' box-triangle tests. `x nested`: p50 µs per frame over nested's, same run. Most "
       "frames are far from any equipment, where a step is mostly ground following and every method costs the "
       "same: differences of a few hundredths of a µs in p50 are the timer's and the machine's noise; the mean "
       "and p99 show the frames near equipment.\n\n";
  s << markdown(methodTable(d)) << "\n";
  s << "### Targets\n\n" << targetLines(d.targets) << "\n";
  s << "### What the figures rest on\n\n"
    << "The blocking events of the exact reference's plays (a run of steps blocked by one unit is one event), by "
       "the kind of the unit:\n\n"
    << markdown(blockingTable(d)) << "\n";
  s << "### Auto: the test chosen per unit\n\n"
    << "`auto` keeps the nested test alone for a unit whose inner OBB is tight around its triangles (the largest "
       "distance from the box's surface to them at most "
    << shortText(1000.0 * kTightObbGap)
    << " mm: walker/contact_choice.h) and adds the exact mesh stage for the others, unless the stage would cost "
       "more than "
    << kMaxExactStageTests
    << " bounding-volume and triangle tests on a sample sweep of the body into the unit "
       "(walker/exact_stage_cost.h). Per kind: how many units got which, the largest distance found on a tight box, "
       "the smallest gap that ruled a box out, the units left to the nested test for their cost, and the most tests a "
       "sample sweep made.\n\n"
    << markdown(autoTable(d)) << "\n";
  s << "### Nested: false-block rate and stop gap per flythrough\n\n" << markdown(nestedTable(d)) << "\n";
  s << "### Every method per flythrough\n\n" << markdown(flythroughTable(d), 2) << "\n";
  s << "### Cost by model weight\n\n"
    << "µs per frame over the frames whose sweep reached a unit (its outer AABB met by the body's swept outer "
    << "AABB), by the triangles of the heaviest unit reached: where the exact stage starts to cost.\n\n"
    << markdown(weightTable(d), 2) << "\n![µs per frame by model weight](model_weight.png)\n\n";
  s << "### Time against stop gap\n\n"
    << "Mean µs per frame (over all frames of all flythroughs: the cost of the frames near equipment shows, "
       "where the median is mostly the ground following's) against the mean stop gap (log scales); the grey "
       "line joins the Pareto front "
       "(no other method is both faster and closer). A method that was never blocked has no gap and no point.\n\n"
    << "![time against stop gap](pareto.png)\n\n![µs per frame per method](methods.png)\n\n";

  s << "## Ground following: terrain levels of detail\n\n"
    << "The terrain's chunk quadtree in chunks of " << kReportChunkCells
    << " cells as the renderer cuts them (terrain/terrain_chunk.h; each level's grid, before the renderer "
       "simplifies it within a fraction of that grid's error); at " << d.terrainPoints
    << " random map points (those with ground) the height of each level's surface against the full-resolution "
       "surface (Heightfield::groundHeight; a paged terrain's points lie in its central " << kPagedLodWindowCells
    << " x " << kPagedLodWindowCells << " cells). The table's maximum error is the level's exact error (from the "
       "terrain's pyramid when it has one: rounded up to float, and its chunks those with a valid sample, an upper "
       "bound where the DEM has holes); ns per query is the least over the timed loops.\n\n"
    << markdown(lodTable(d)) << "\n![height error against ns per query](terrain_lod.png)\n\n";

  s << "## OBB fitters\n\n"
    << "Per model of the scene, the boxes fitted to all of its vertices (convex hull included in the time), "
       "against CGAL's optimal oriented bounding box (CGAL::oriented_bounding_box, fixed seed). Volumes in the "
       "model's units cubed; times are the least over the fits.\n\n"
    << markdown(fitterTable(d)) << "\n";
  return s.str();
}

Json aggregateJson(const Aggregate& a) {
  Json j;
  j["frames"] = a.frames;
  j["us_per_frame"] = {{"p50", jsonNumber(a.p50)}, {"p99", jsonNumber(a.p99)}, {"mean", jsonNumber(a.mean)}};
  j["collision_us_p50"] = jsonNumber(a.collisionP50);
  j["sweeps"] = a.sweeps;
  j["blocked_sweeps"] = a.blockedSweeps;
  j["reference_contacts"] = a.referenceContacts;
  j["missed"] = a.missed;
  j["early_stops"] = a.earlyStops;
  j["early_stop_mm"] = {{"max", jsonNumber(a.earlyStopMaxMm)}, {"mean", jsonNumber(a.earlyStopMeanMm)}};
  j["blocking_events"] = a.blockingEvents;
  j["early_stop_percent"] = a.earlyStopPercent;
  j["false_blocks"] = a.falseBlocks;
  j["false_block_percent"] = a.falseBlockPercent;
  j["steps_blocked_by_equipment"] = a.equipmentBlocks;
  j["stop_gap_mm"] = {{"samples", a.gaps}, {"mean", jsonNumber(a.gapMeanMm)}, {"max", jsonNumber(a.gapMaxMm)}};
  j["bv_tests_per_frame"] = jsonNumber(a.bvPerFrame);
  j["triangle_tests_per_frame"] = jsonNumber(a.trianglesPerFrame);
  return j;
}

Json reportJson(const ReportData& d) {
  Json j;
  j["scene"] = d.scene;
  j["scripts"] = d.scripts;
  j["quick"] = d.quick;
  j["cpu"] = d.cpu;
  j["hz"] = d.hz;
  j["units"] = d.units;
  j["timing_plays"] = d.timingPlays;
  j["seconds"] = {{"timing", d.seconds.timing}, {"accuracy", d.seconds.accuracy}, {"terrain", d.seconds.terrain},
                  {"fitters", d.seconds.fitters}, {"total", d.seconds.total}};
  const MethodResult* nested = d.find(VolumeMethod::Nested);
  Json methods = Json::array();
  for (const MethodResult& m : d.methods) {
    Json jm = {{"method", volumeMethodName(m.method)}, {"complete", m.complete()}};
    jm.update(aggregateJson(m.overall()));
    jm["ratio_to_nested_p50"] = nested ? jsonNumber(m.overall().p50 / nested->overall().p50) : Json(nullptr);
    Json plays = Json::array();
    for (const PlayStats& p : m.plays) {
      Json jp = {{"script", p.script}};
      if (!p.error.empty()) jp["error"] = p.error;
      else jp.update(aggregateJson(aggregate({&p})));
      plays.push_back(jp);
    }
    jm["flythroughs"] = plays;
    methods.push_back(jm);
  }
  j["methods"] = methods;
  Json lod = Json::array();
  for (const TerrainLodRow& r : d.lod)
    lod.push_back({{"name", r.name}, {"level", r.level}, {"step", r.step}, {"chunks", r.chunks},
                   {"table_max_error_m", r.tableMaxError}, {"points", r.points}, {"max_error_m", r.maxError},
                   {"mean_error_m", r.meanError}, {"ns_per_query", jsonNumber(r.nsPerQuery)}});
  j["terrain_lod"] = {{"points", d.terrainPoints}, {"levels", lod}};
  Json fitters = Json::array();
  for (const FitterRow& r : d.fitters)
    fitters.push_back({{"model", r.model}, {"triangles", r.triangles}, {"vertices", r.vertices},
                       {"hull_points", r.hullPoints},
                       {"volume", {{"covariance", r.covarianceVolume}, {"hull_search", r.hullSearchVolume},
                                   {"cgal_optimal", r.optimalVolume}}},
                       {"fit_us", {{"covariance", r.covarianceMicros}, {"hull_search", r.hullSearchMicros},
                                   {"cgal_optimal", r.optimalMicros}}}});
  j["fitters"] = {{"repetitions", d.fitterRepetitions}, {"models", fitters}};
  Json choices = Json::array();
  for (const AutoChoiceRow& r : d.autoChoices)
    choices.push_back({{"kind", r.kind}, {"units", r.units}, {"exact_stage", r.exact}, {"too_costly", r.costly},
                       {"most_sample_tests", r.mostTests},
                       {"tight_gap_max_mm", r.tightGapMaxMm}, {"exact_gap_min_mm", jsonNumber(r.exactGapMinMm)}});
  j["auto"] = {{"tight_obb_gap_mm", 1000.0 * kTightObbGap}, {"max_exact_stage_tests", kMaxExactStageTests},
               {"kinds", choices}};
  Json kinds = Json::array();
  for (const BlockingKindRow& r : d.blockingKinds)
    kinds.push_back({{"kind", r.kind}, {"events", r.events}, {"units", r.units}});
  j["blocking_events"] = kinds;
  Json weights = Json::array();
  for (const WeightRow& r : d.byWeight)
    weights.push_back({{"weight", r.weight}, {"method", volumeMethodName(r.method)}, {"frames", r.frames},
                       {"us_per_frame", {{"p50", jsonNumber(r.p50)}, {"p99", jsonNumber(r.p99)}, {"mean", jsonNumber(r.mean)}}}});
  j["by_model_weight"] = weights;
  j["targets"] = targetsJson(d.targets);
  return j;
}

void writePareto(const ReportData& d, const std::string& path) {
  std::vector<PlotSeries> series;
  std::vector<PlotPoint> points;
  for (const MethodResult& m : d.methods) {
    const Aggregate a = m.overall();
    PlotSeries s{volumeMethodName(m.method), methodColour(m.method), {}};
    if (a.gaps && std::isfinite(a.mean)) {
      s.points.push_back({a.mean, a.gapMeanMm, volumeMethodName(m.method)});
      points.push_back(s.points.back());
    }
    series.push_back(s);
  }
  // The front: by time, each point closer than every faster one.
  std::sort(points.begin(), points.end(), [](const PlotPoint& a, const PlotPoint& b) { return a.x < b.x; });
  PlotSeries front{"", {160, 160, 160}, {}, true, false};
  for (const PlotPoint& p : points)
    if (front.points.empty() || p.y < front.points.back().y) front.points.push_back({p.x, p.y, ""});
  series.insert(series.begin(), front);
  writeScatterPlot(path, "time per frame against stop gap (" + std::string(d.quick ? "quick" : "full") + ")",
                   {"mean time per frame", true, 0, "µs"}, {"mean stop gap", true, 0, "mm"}, series);
}

void writeMethodBars(const ReportData& d, const std::string& path) {
  std::vector<PlotBarGroup> groups;
  for (const MethodResult& m : d.methods) {
    const Aggregate a = m.overall();
    groups.push_back({volumeMethodName(m.method), {a.p50, a.mean, a.p99}});
  }
  writeBarPlot(path, "time per frame of each method over the flythroughs",
               {{"p50", {31, 119, 180}}, {"mean", {255, 127, 14}}, {"p99", {214, 39, 40}}},
               {"time per frame", true, 0, "µs"}, groups);
}

void writeWeightBars(const ReportData& d, const std::string& path) {
  std::vector<std::pair<std::string, Rgb>> series;
  for (const MethodResult& m : d.methods) series.push_back({volumeMethodName(m.method), methodColour(m.method)});
  std::vector<PlotBarGroup> groups;
  for (const WeightClass& c : kWeightClasses)
    for (const char* statistic : {"mean", "p99"}) {
      PlotBarGroup g{std::string(c.name) + ", " + statistic, {}};
      bool any = false;
      for (const MethodResult& m : d.methods) {
        double value = std::numeric_limits<double>::quiet_NaN();
        for (const WeightRow& r : d.byWeight)
          if (r.method == m.method && r.weight == c.name) value = statistic[0] == 'm' ? r.mean : r.p99;
        any = any || !std::isnan(value);
        g.values.push_back(value);
      }
      if (any) groups.push_back(g);
    }
  writeBarPlot(path, "time per frame by the heaviest unit the step reached", series,
               {"time per frame", true, 0, "µs"}, groups, 1200, 500);
}

void writeTerrainPlot(const ReportData& d, const std::string& path) {
  PlotSeries maxError{"measured max error", {214, 39, 40}, {}, true};
  PlotSeries meanError{"measured mean error", {31, 119, 180}, {}, true};
  PlotSeries full{"full resolution", {0, 0, 0}, {}};
  for (const TerrainLodRow& r : d.lod) {
    if (r.level < 0) {
      full.points.push_back({r.nsPerQuery, 0.0, "full"});
      continue;
    }
    maxError.points.push_back({r.nsPerQuery, r.maxError, r.name});
    meanError.points.push_back({r.nsPerQuery, r.meanError, ""});
  }
  writeScatterPlot(path, "terrain levels: height error against time per query (below 0.1 mm on the floor)",
                   {"time per query", true, 0, "ns"}, {"height error", true, 1e-4, "m"}, {maxError, meanError, full});
}

}  // namespace

void writeReportFiles(const ReportData& d, const std::string& folder) {
  const std::filesystem::path dir(folder);
  writeFileAtomically((dir / "report.json").string(), reportJson(d).dump(2) + "\n");
  writePareto(d, (dir / "pareto.png").string());
  writeMethodBars(d, (dir / "methods.png").string());
  writeTerrainPlot(d, (dir / "terrain_lod.png").string());
  writeWeightBars(d, (dir / "model_weight.png").string());
  std::vector<ContactSet> contacts;
  for (const MethodResult& m : d.methods)
    for (std::size_t s = 0; s < m.plays.size(); ++s)
      contacts.push_back({volumeMethodName(m.method), d.scripts[s], &m.plays[s].contacts});
  writeContactsLayer((dir / "contacts.gpkg").string(), d.crsWkt, contacts);
  writeFileAtomically((dir / "report.md").string(), reportMarkdown(d));
}

void printReportSummary(const ReportData& d, const std::string& folder, std::ostream& out) {
  out << "methods over " << d.scripts.size() << " flythroughs of " << d.scene << " (" << (d.quick ? "quick" : "full")
      << ", " << fixedText(d.seconds.total, 1) << " s):\n"
      << plain(methodTable(d));
  printTargets(out, d.targets, 50, 6);
  out << "\nwrote " << folder << "/{";
  for (std::size_t i = 0; i < reportFiles().size(); ++i) out << (i ? ", " : "") << reportFiles()[i];
  out << "}\n";
}

}  // namespace nestwalk
