// The methods report (method_report.h): the plays of every contact method over the flythroughs
// (timing, and accuracy against the exact reference with the stop gaps), the aggregates and the
// targets; then the files (report_writer.cpp).
#include "nestwalk/report/method_report.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/core/machine.h"
#include "nestwalk/core/statistics.h"
#include "nestwalk/core/stopwatch.h"
#include "nestwalk/report/method_report_files.h"
#include "nestwalk/report/reference_comparison.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/walker/flythrough.h"
#include "nestwalk/walker/script_file.h"
#include "nestwalk/walker/script_player.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <ostream>
#include <set>
#include <utility>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Where to look for the nearest triangles after a step blocked by no named unit, metres.
constexpr double kGapSearchRadius = 5.0;
/// The nearest-unit search widens the gap found so far by this fraction (unitless) plus this much
/// (metres): the box query compares rounded box corners, and a unit exactly at the gap must not be
/// left out by a last-bit difference (1e-9 is 1 nm at 1 m, a millionth of the report's precision).
constexpr double kNearSearchRelative = 1e-9;
constexpr double kNearSearchAbsolute = 1e-9;

struct Settings {
  int timingPlays;            // timing plays per method and flythrough (each frame: the least)
  std::size_t terrainPoints;  // random map points of the terrain table
  int terrainRepetitions;     // timed loops per level
  int fitterRepetitions;      // fits per model and fitter
};
constexpr Settings kFull{25, 1'000'000, 3, 10};
constexpr Settings kQuick{5, 20'000, 3, 3};

/// The exact distance from the body box to the nearest unit's triangles: first to the unit that
/// blocked (an upper bound), then to every unit whose outer AABB comes within that distance of the
/// body's (a unit's triangles lie inside its outer AABB, so no closer one is left out).
double stopGap(const CollisionWorld& world, const MeshWorld& meshes, const NestedVolume<double>& body,
               std::int32_t blockedUnit, std::vector<std::uint32_t>& near) {
  MeshQueryCounters counters;
  double gap = blockedUnit >= 0 ? meshes.distance(std::uint32_t(blockedUnit), body.inner, counters)
                                : kGapSearchRadius;
  const Vec3<double> grow = Vec3<double>::Constant(gap * (1 + kNearSearchRelative) + kNearSearchAbsolute);
  near.clear();
  world.tree().query(Aabb<double>{body.outer.min - grow, body.outer.max + grow}, near);
  bool found = blockedUnit >= 0;
  for (std::uint32_t u : near) {
    gap = std::min(gap, meshes.distance(u, body.inner, counters));
    found = true;
  }
  return found ? gap : kNaN;
}

/// A timing play: the walker's own µs per step; each frame keeps the least over the plays.
void timingPlay(const Scene& scene, const CollisionWorld& world, const Script& script, const WalkerOptions& options,
                PlayStats& s) {
  const FlythroughResult r = runFlythrough(scene, world, script, options);
  const bool first = s.totalMicros.empty();
  if (!first && r.records.size() != s.totalMicros.size())
    throw std::logic_error("report: a timing play of " + script.path + " took a different number of steps");
  s.frames = r.records.size();
  s.totalMicros.resize(r.records.size());
  s.collisionMicros.resize(r.records.size());
  for (std::size_t i = 0; i < r.records.size(); ++i) {
    const auto& us = r.records[i].micros;
    const double total = us[StepPart::Total];
    const double collision = us[StepPart::BroadPhase] + us[StepPart::Narrow];
    s.totalMicros[i] = first ? total : std::min(s.totalMicros[i], total);
    s.collisionMicros[i] = first ? collision : std::min(s.collisionMicros[i], collision);
  }
}

/// Watches the accuracy play's sweeps: compares each with the reference, and keeps the triangles
/// of the heaviest unit the frame's sweeps reached (the reference's broad phase over the outer
/// AABBs, the same for every method).
class AccuracyWatch : public SweepObserver {
 public:
  AccuracyWatch(const CollisionWorld& reference, const MeshWorld& meshes)
      : comparison_(reference), reference_(reference), meshes_(meshes) {}
  void onSweep(const NestedVolume<double>& viewer, const Vec3<double>& d, const SweepHit& hit) override {
    comparison_.onSweep(viewer, d, hit);
    Aabb<double> swept = viewer.outer;
    swept.extend(Aabb<double>{viewer.outer.min + d, viewer.outer.max + d});
    near_.clear();
    reference_.tree().query(swept, near_);
    for (std::uint32_t u : near_) heaviest_ = std::max(heaviest_, meshes_.triangles(u));
  }
  /// The heaviest unit's triangles since the last call (0: none reached).
  std::size_t takeHeaviest() { return std::exchange(heaviest_, 0); }
  const ReferenceTally& tally() const { return comparison_.tally(); }

 private:
  ReferenceComparison comparison_;
  const CollisionWorld& reference_;
  const MeshWorld& meshes_;
  std::vector<std::uint32_t> near_;
  std::size_t heaviest_ = 0;
};

/// The accuracy play: every sweep compared with the reference's, counters, stop gaps, the weight
/// of the units each step reached.
void accuracyPlay(const Scene& scene, CollisionWorld& world, const CollisionWorld& reference, const MeshWorld& meshes,
                  const Script& script, const WalkerOptions& options, PlayStats& s) {
  AccuracyWatch watch(reference, meshes);
  const ObservedSweeps observed(world, watch);
  Walker walker(*scene.terrain, world, scene.origin, options);
  ScriptPlayer player(script, walker);
  std::vector<std::uint32_t> near;
  std::vector<FrameRecord> records;
  player.run([&](const Walker& w, const StepReport& report) {
    records.push_back(makeFrameRecord(w, report));
    s.nearTriangles.push_back(watch.takeHeaviest());
    s.bvTests += report.counters.nodeTests;
    for (std::uint64_t n : report.counters.stageTests) s.bvTests += n;
    s.triangleTests += report.counters.primitiveTests;
    const WalkerState& st = w.state();
    if (!st.blocked || st.reason != BlockReason::Equipment || st.blockedUnit < 0) return;
    ++s.equipmentBlocks;
    const double gap = stopGap(world, meshes, w.bodyVolume(st.feet, st.bodyYawDeg), st.blockedUnit, near);
    if (std::isfinite(gap)) s.gapsMm.push_back(1000.0 * gap);
  });
  s.tally = watch.tally();
  // The blocking events are the contacts' (one per run of steps blocked by one thing), equipment's.
  s.contacts = runContacts(scene, records, &meshes);
  for (const RunContact& c : s.contacts)
    if (const int u = c.kind == "terrain" ? -1 : scene.findUnit(c.unit); u >= 0) s.blockingEvents.push_back(std::uint32_t(u));
}

/// Auto's choices, by the kind of unit (units without a kind under "(none)").
std::vector<AutoChoiceRow> autoChoiceRows(const Scene& scene, const CollisionWorld& autoWorld) {
  std::map<std::string, AutoChoiceRow> byKind;
  const std::vector<GapVerdict>& choices = autoWorld.contactChoices();
  for (std::size_t u = 0; u < choices.size(); ++u) {
    const std::string kind = scene.units[u].kind.empty() ? "(none)" : scene.units[u].kind;
    AutoChoiceRow& r = byKind[kind];
    r.kind = kind;
    ++r.units;
    const ExactStageCost& cost = autoWorld.exactStageCosts()[u];
    if (!choices[u].tight) r.mostTests = std::max(r.mostTests, cost.maxTests);
    if (choices[u].tight) {
      r.tightGapMaxMm = std::max(r.tightGapMaxMm, 1000.0 * choices[u].lowerBound);
    } else if (!cost.affordable()) {
      ++r.costly;
    } else {
      ++r.exact;
      r.exactGapMinMm = std::isnan(r.exactGapMinMm) ? 1000.0 * choices[u].lowerBound
                                                    : std::min(r.exactGapMinMm, 1000.0 * choices[u].lowerBound);
    }
  }
  std::vector<AutoChoiceRow> rows;
  for (auto& [kind, r] : byKind) rows.push_back(r);
  return rows;
}

/// The blocking events of the exact method's plays, by kind.
std::vector<BlockingKindRow> blockingKindRows(const Scene& scene, const MethodResult& exact) {
  std::map<std::string, BlockingKindRow> byKind;
  std::map<std::string, std::set<std::uint32_t>> units;
  for (const PlayStats& p : exact.plays)
    for (std::uint32_t u : p.blockingEvents) {
      const std::string kind = scene.units[u].kind.empty() ? "(none)" : scene.units[u].kind;
      byKind[kind].kind = kind;
      ++byKind[kind].events;
      units[kind].insert(u);
    }
  std::vector<BlockingKindRow> rows;
  for (auto& [kind, r] : byKind) {
    r.units = units[kind].size();
    rows.push_back(r);
  }
  return rows;
}

}  // namespace

Aggregate aggregate(const std::vector<const PlayStats*>& plays) {
  Aggregate a;
  std::vector<double> total, collision;
  for (const PlayStats* p : plays) {
    if (!p->error.empty()) continue;
    a.frames += p->frames;
    total.insert(total.end(), p->totalMicros.begin(), p->totalMicros.end());
    collision.insert(collision.end(), p->collisionMicros.begin(), p->collisionMicros.end());
    a.sweeps += p->tally.sweeps;
    a.blockedSweeps += p->tally.contacts;
    a.referenceContacts += p->tally.referenceContacts;
    a.missed += p->tally.missed;
    a.earlyStops += p->tally.earlyStops;
    a.falseBlocks += p->tally.falseBlocks;
    a.earlyStopMaxMm = std::max(a.earlyStopMaxMm, p->tally.earlyStopMaxMm);
    a.earlyStopMeanMm += p->tally.earlyStopSumMm;
    a.blockingEvents += p->blockingEvents.size();
    a.equipmentBlocks += p->equipmentBlocks;
    a.bvTests += p->bvTests;
    a.triangleTests += p->triangleTests;
    for (double g : p->gapsMm) {
      a.gapMeanMm += g;
      a.gapMaxMm = std::max(a.gapMaxMm, g);
      ++a.gaps;
    }
  }
  a.p50 = total.empty() ? kNaN : percentile(total, 50);
  a.p99 = total.empty() ? kNaN : percentile(total, 99);
  double sum = 0;
  for (double us : total) sum += us;
  a.mean = total.empty() ? kNaN : sum / double(total.size());
  a.collisionP50 = collision.empty() ? kNaN : percentile(collision, 50);
  a.gapMeanMm = a.gaps ? a.gapMeanMm / double(a.gaps) : kNaN;
  if (!a.gaps) a.gapMaxMm = kNaN;
  a.earlyStopMeanMm = a.earlyStops ? a.earlyStopMeanMm / double(a.earlyStops) : kNaN;
  if (!a.earlyStops) a.earlyStopMaxMm = kNaN;
  a.falseBlockPercent = a.blockedSweeps ? 100.0 * double(a.falseBlocks) / double(a.blockedSweeps) : 0.0;
  a.earlyStopPercent = a.blockedSweeps ? 100.0 * double(a.earlyStops) / double(a.blockedSweeps) : 0.0;
  a.bvPerFrame = a.frames ? double(a.bvTests) / double(a.frames) : kNaN;
  a.trianglesPerFrame = a.frames ? double(a.triangleTests) / double(a.frames) : kNaN;
  return a;
}

std::vector<WeightRow> weightRows(const std::vector<MethodResult>& methods) {
  std::vector<WeightRow> rows;
  const std::size_t classes = std::size(kWeightClasses);
  for (const MethodResult& m : methods) {
    std::vector<std::vector<double>> micros(classes);
    for (const PlayStats& p : m.plays) {
      if (!p.error.empty() || p.nearTriangles.size() != p.totalMicros.size()) continue;
      for (std::size_t f = 0; f < p.totalMicros.size(); ++f) {
        std::size_t c = classes - 1;
        while (c > 0 && p.nearTriangles[f] < kWeightClasses[c].fromTriangles) --c;
        micros[c].push_back(p.totalMicros[f]);
      }
    }
    for (std::size_t c = 0; c < classes; ++c) {
      if (micros[c].empty()) continue;
      rows.push_back({m.method, kWeightClasses[c].name, micros[c].size(), percentile(micros[c], 50),
                      percentile(micros[c], 99), mean(micros[c])});
    }
  }
  return rows;
}

Aggregate MethodResult::overall() const {
  std::vector<const PlayStats*> all;
  for (const PlayStats& p : plays) all.push_back(&p);
  return aggregate(all);
}

std::vector<Target> reportTargets(const ReportData& d) {
  std::vector<Target> targets;
  const MethodResult* nested = d.find(VolumeMethod::Nested);
  const MethodResult* exact = d.find(VolumeMethod::NestedMesh);
  for (const MethodResult& m : d.methods) {
    const Aggregate a = m.overall();
    // A flythrough a method could not play (it cannot land where the script starts) cannot count
    // as free of misses: the target is then not met, and its name says why.
    std::size_t unplayed = 0;
    for (const PlayStats& p : m.plays) unplayed += !p.error.empty();
    std::string name = std::string("missed contacts, ") + volumeMethodName(m.method);
    if (unplayed > 0)
      name += " (" + std::to_string(unplayed) + " of " + std::to_string(m.plays.size()) + " flythroughs not played)";
    targets.push_back({name, "= 0", double(a.missed), a.missed == 0 && m.complete()});
  }
  if (exact) {
    const Aggregate a = exact->overall();
    targets.push_back({"nested+mesh false blocks (early stops included)", "= 0", double(a.falseBlocks + a.earlyStops),
                       a.falseBlocks + a.earlyStops == 0 && exact->complete()});
    targets.push_back({"nested+mesh max stop gap (mm)", "<= 1", a.gapMaxMm, !(a.gapMaxMm > 1.0) && exact->complete()});
    if (nested) {
      const double ratio = a.p50 / nested->overall().p50;
      targets.push_back({"nested+mesh us per frame p50 / nested's", "<= 2", ratio, ratio <= 2.0});
    }
  }
  if (const MethodResult* autoMethod = d.find(VolumeMethod::Auto)) {
    const Aggregate a = autoMethod->overall();
    const double longest = a.earlyStops ? a.earlyStopMaxMm : 0.0;
    targets.push_back({"auto longest early stop (mm)", "<= 10", longest, longest <= 10.0 && autoMethod->complete()});
    targets.push_back({"auto false blocks", "= 0", double(a.falseBlocks), a.falseBlocks == 0 && autoMethod->complete()});
    if (nested) {
      const double ratio = a.mean / nested->overall().mean;
      targets.push_back({"auto us per frame mean / nested's", "<= 1.2", ratio, ratio <= 1.2});
    }
  }
  std::size_t events = 0;
  for (const BlockingKindRow& k : d.blockingKinds) events += k.events;
  targets.push_back({"blocking events under the figures", ">= 20", double(events), events >= 20});
  targets.push_back({"kinds of equipment that blocked", ">= 5", double(d.blockingKinds.size()), d.blockingKinds.size() >= 5});
  return targets;
}

const MethodResult* ReportData::find(VolumeMethod m) const {
  for (const MethodResult& r : methods)
    if (r.method == m) return &r;
  return nullptr;
}

int runMethodReport(const MethodReportOptions& o, std::ostream& log) {
  const fs::path out(o.out);
  if (!o.overwrite)
    for (const std::string& f : reportFiles())
      if (fs::exists(out / f))
        throw InputError((out / f).string() + ": exists; pass --overwrite to replace the report's files");
  if (o.scripts.empty()) throw InputError("--scripts: give the flythroughs to run the methods over");
  const Settings settings = o.quick ? kQuick : kFull;
  const auto start = std::chrono::steady_clock::now();

  ReportData d;
  d.scene = o.scene;
  d.quick = o.quick;
  d.cpu = cpuModelName();
  d.timingPlays = settings.timingPlays;
  std::vector<Script> scripts;
  for (const std::string& s : o.scripts) {
    scripts.push_back(readScript(s));
    d.scripts.push_back(fs::path(s).filename().string());
  }
  const Scene scene = loadScene(o.scene);
  d.units = scene.units.size();
  d.instances = scene.instances.size();
  d.hierarchy = describe(scene.spec.method);
  d.crsWkt = scene.terrain->crsWkt();
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw InputError(out.string() + ": cannot create the folder: " + ec.message());

  // One MeshWorld for every mesh method and the reference; one world per method.
  const std::shared_ptr<const MeshWorld> meshes = MeshWorld::fromScene(scene);
  auto worldFor = [&](VolumeMethod m) {
    MethodSpec spec = scene.spec.method;
    spec.volumes = m;
    return std::make_unique<CollisionWorld>(CollisionWorld::fromScene(scene, spec, meshes));
  };
  // The reference: nested+mesh by conservative advancement on exact distances, independent of
  // the swept tests the methods themselves use (mesh_world.h).
  const std::unique_ptr<CollisionWorld> reference = worldFor(VolumeMethod::NestedMesh);
  reference->setMeshContactSearch(MeshContactSearch::Advancement);
  std::vector<std::unique_ptr<CollisionWorld>> worlds;
  for (VolumeMethod m : kReportMethods) {
    worlds.push_back(worldFor(m));
    MethodResult r;
    r.method = m;
    r.plays.resize(scripts.size());
    for (std::size_t s = 0; s < scripts.size(); ++s) r.plays[s].script = d.scripts[s];
    d.methods.push_back(std::move(r));
  }
  WalkerOptions options;
  options.viewer = scene.spec.viewer;
  d.hz = 1.0 / options.dt;

  // Timing plays, interleaved (repeat, flythrough, method) so that a slow spell of the machine
  // falls on every method alike.
  auto t0 = std::chrono::steady_clock::now();
  options.timeParts = true;
  for (auto& w : worlds) w->setTiming(true);
  for (int rep = 0; rep < settings.timingPlays; ++rep)
    for (std::size_t s = 0; s < scripts.size(); ++s)
      for (std::size_t m = 0; m < worlds.size(); ++m) {
        PlayStats& p = d.methods[m].plays[s];
        if (!p.error.empty()) continue;
        try {
          timingPlay(scene, *worlds[m], scripts[s], options, p);
        } catch (const InputError& e) {  // e.g. a start inside a unit's AABB for this method
          p.error = e.what();
        }
      }
  d.seconds.timing = secondsSince(t0);

  // Accuracy plays against the exact reference.
  t0 = std::chrono::steady_clock::now();
  options.timeParts = false;
  for (auto& w : worlds) w->setTiming(false);
  for (std::size_t m = 0; m < worlds.size(); ++m)
    for (std::size_t s = 0; s < scripts.size(); ++s) {
      PlayStats& p = d.methods[m].plays[s];
      if (p.error.empty()) accuracyPlay(scene, *worlds[m], *reference, *meshes, scripts[s], options, p);
    }
  d.seconds.accuracy = secondsSince(t0);
  for (std::size_t m = 0; m < worlds.size(); ++m)
    if (kReportMethods[m] == VolumeMethod::Auto) d.autoChoices = autoChoiceRows(scene, *worlds[m]);
  if (const MethodResult* exact = d.find(VolumeMethod::NestedMesh)) d.blockingKinds = blockingKindRows(scene, *exact);
  d.byWeight = weightRows(d.methods);

  t0 = std::chrono::steady_clock::now();
  d.terrainPoints = settings.terrainPoints;
  d.lod = measureTerrainLod(*scene.terrain, scene.terrainPyramid.get(), settings.terrainPoints, settings.terrainRepetitions);
  d.seconds.terrain = secondsSince(t0);

  t0 = std::chrono::steady_clock::now();
  d.fitterRepetitions = settings.fitterRepetitions;
  d.fitters = measureFitters(scene, settings.fitterRepetitions);
  d.seconds.fitters = secondsSince(t0);

  d.targets = reportTargets(d);
  d.seconds.total = secondsSince(start);
  writeReportFiles(d, out.string());
  printReportSummary(d, out.string(), log);
  return 0;
}

}  // namespace nestwalk
