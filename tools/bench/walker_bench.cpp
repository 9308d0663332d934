// The walker benchmark (see walker_bench.h).
#include "tools/bench/walker_bench.h"

#include "tools/bench/bench_document.h"
#include "tools/bench/broadphase_bench.h"
#include "tools/bench/record_statistics.h"

#include "nestwalk/core/angles.h"
#include "nestwalk/core/random.h"
#include "nestwalk/core/statistics.h"
#include "nestwalk/core/stopwatch.h"
#include "nestwalk/geometry/obb_batch.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/gis/route_plan.h"
#include "nestwalk/session/recorded_run.h"
#include "nestwalk/walker/flythrough.h"
#include "nestwalk/walker/script_file.h"
#include "assets/generators/phone_track.h"
#include "nestwalk/core/output_file.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>
#include <ostream>

namespace nestwalk::bench {
namespace {

constexpr double kSide = 10000.0;  // metres
constexpr double kCell = 5.0;
constexpr double kOriginX = 550000.0, kOriginY = 4650000.0;
constexpr std::size_t kTargetInstances = 1'000'000;  // the target is for steps among this many instances
constexpr double kTargetP99Us = 2.0;                 // target: p99 µs per walker step at most
constexpr double kTargetLayersPercent = 5.0;   // target: the results layers' share of a headless run, %
constexpr double kTargetRouteSeconds = 1.0;    // target: a 10,000-fix GPX track into a script, s ("well under")
constexpr std::size_t kRouteFixes = 10'000;
constexpr const char* kStageKeys[3] = {"aabb_aabb_per_script", "aabb_obb_per_script", "obb_obb_per_script"};
constexpr const char* kStageTitles[3] = {"aabb-aabb", "aabb-obb", "obb-obb"};

/// Rolling hills, slopes below 10 degrees: the walker is never stopped by the terrain here.
std::shared_ptr<terrain::Heightfield> rollingTerrain() {
  const int n = int(kSide / kCell) + 1;
  std::vector<float> h(std::size_t(n) * std::size_t(n));
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      const double x = c * kCell, y = kSide - r * kCell;
      h[std::size_t(r) * std::size_t(n) + std::size_t(c)] =
          float(100.0 + 25.0 * std::sin(x / 900.0) * std::cos(y / 1300.0) + 6.0 * std::sin((x + 2 * y) / 310.0));
    }
  return std::make_shared<terrain::Heightfield>(n, n, std::move(h), kOriginX, kOriginY + kSide, kCell, kCell);
}

struct Kind {
  const char* name;
  double hx, hy, hz, weight;
};
constexpr Kind kKinds[] = {
    {"pole", 0.025, 0.025, 1.5, 0.35},        {"piezometer", 0.3, 0.3, 0.45, 0.2},
    {"station", 0.6, 0.4, 1.6, 0.15},        {"panel", 0.8, 0.6, 0.7, 0.15},
    {"container", 3.03, 1.22, 1.3, 0.1},     {"vehicle", 2.65, 0.95, 0.9, 0.05},
};

struct World {
  std::shared_ptr<terrain::Heightfield> hf;
  std::unique_ptr<CollisionWorld> world;
  Eigen::Vector3d origin{kOriginX, kOriginY, 0};
  double buildSeconds = 0;
};

World scatter(const std::shared_ptr<terrain::Heightfield>& hf, std::size_t n, std::uint64_t seed) {
  SplitMix64 rng(seed);
  std::vector<NestedVolume<double>> units;
  std::vector<std::string> names, groups;
  units.reserve(n);
  names.reserve(n);
  groups.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    double pick = rng.uniform(), acc = 0;
    const Kind* k = &kKinds[0];
    for (const Kind& kk : kKinds) {
      acc += kk.weight;
      if (pick < acc) {
        k = &kk;
        break;
      }
    }
    const double x = rng.uniform(20, kSide - 20), y = rng.uniform(20, kSide - 20);
    const double z = *hf->groundHeight(kOriginX + x, kOriginY + y);
    Obb<double> b;
    b.center = Vec3<double>(x, y, z + k->hz);
    b.axes = Eigen::AngleAxisd(rng.uniform(0, 2 * std::numbers::pi), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    b.halfExtents = Vec3<double>(k->hx, k->hy, k->hz);
    units.push_back(NestedVolume<double>::fromObb(b));
    names.push_back(k->name);
    groups.push_back("cell" + std::to_string(int(x / 1000)) + "_" + std::to_string(int(y / 1000)));
  }
  World w;
  w.hf = hf;
  const auto t0 = std::chrono::steady_clock::now();
  w.world = std::make_unique<CollisionWorld>(std::move(units), std::move(names), std::move(groups), MethodSpec{});
  w.buildSeconds = secondsSince(t0);
  return w;
}

/// Walks the viewer at 5 m/s between random waypoints 50-500 m apart (a new one when reached or
/// after 10 blocked steps) and times every step. The row of the steps table: µs per step (p50, p99,
/// max, mean), contacts per 1000 steps, hierarchy node and stage tests per step.
Json timeSteps(const World& w, std::size_t steps, std::uint64_t seed) {
  WalkerOptions opts;
  opts.timeParts = false;
  Walker walker(*w.hf, *w.world, w.origin, opts);
  SplitMix64 rng(seed);
  auto free = [&](double x, double y) {
    return walker.place(Eigen::Vector3d(kOriginX + x, kOriginY + y, 0), false, 0, false, 2.0).empty();
  };
  double x = kSide / 2, y = kSide / 2;
  while (!free(x, y)) x += 1.0;
  Eigen::Vector2d target;
  auto newTarget = [&] {
    const double a = rng.uniform(0, 2 * std::numbers::pi), dist = rng.uniform(50, 500);
    const Eigen::Vector2d p = walker.state().feet.head<2>() + dist * Eigen::Vector2d(std::cos(a), std::sin(a));
    target = p.cwiseMax(Eigen::Vector2d(kOriginX + 50, kOriginY + 50))
                 .cwiseMin(Eigen::Vector2d(kOriginX + kSide - 50, kOriginY + kSide - 50));
  };
  newTarget();
  const std::size_t warmup = std::min<std::size_t>(1000, steps / 10);
  struct Step {
    double us;
    bool blocked;
    CollisionCounters counters;
  };
  std::vector<Step> timed;
  timed.reserve(steps);
  int blockedRun = 0;
  for (std::size_t i = 0; i < steps + warmup; ++i) {
    Eigen::Vector2d d = target - walker.state().feet.head<2>();
    if (d.norm() < 0.1 || blockedRun >= 10) {
      newTarget();
      blockedRun = 0;
      d = target - walker.state().feet.head<2>();
    }
    StepInput in;
    in.move = Eigen::Vector3d(d.x(), d.y(), 0).normalized() * (5.0 / 60.0);
    in.headingDeg = headingOf(d.x(), d.y());
    const auto t0 = std::chrono::steady_clock::now();
    const StepReport r = walker.step(in);
    const double seconds = secondsSince(t0);
    blockedRun = walker.state().blocked ? blockedRun + 1 : 0;
    if (i >= warmup) timed.push_back({1e6 * seconds, walker.state().blocked, r.counters});
  }
  auto stage = [](std::size_t k) { return [k](const Step& s) { return s.counters.stageTests.values[k]; }; };
  return {{"instances", w.world->size()},
          {"steps", timed.size()},
          {"p50_us", percentileOf(timed, 50, &Step::us)},
          {"p99_us", percentileOf(timed, 99, &Step::us)},
          {"max_us", percentileOf(timed, 100, &Step::us)},
          {"mean_us", meanOf(timed, &Step::us)},
          {"contacts_per_1000", meanOf(timed, [](const Step& s) { return s.blocked ? 1000.0 : 0.0; })},
          {"node_tests_per_step", meanOf(timed, [](const Step& s) { return s.counters.nodeTests; })},
          {"stage_tests_per_step", {meanOf(timed, stage(0)), meanOf(timed, stage(1)), meanOf(timed, stage(2))}},
          {"build_s", w.buildSeconds}};
}

/// Part 1: the steps table.
void walkerSteps(Document& doc, const WalkerBenchOptions& o) {
  const std::vector<std::size_t> sizes = o.orDefault(o.sizes, {1000, 10000}, {1000, 100000, 1000000});
  const std::size_t steps = o.orDefault(o.steps, 5000, 200000);
  Table table;
  table.column({"instances", "/instances", 10});
  for (const char* p : {"p50", "p99", "max", "mean"})  // µs per step
    table.column({std::string(p) + " us", "/" + std::string(p) + "_us", 10, std::string(p) == "max" ? 1 : 3});
  table.column({"contacts/k", "/contacts_per_1000", 12, 1}).column({"node tests", "/node_tests_per_step", 12, 1});
  for (int k = 0; k < 3; ++k)  // tests per step of each stage
    table.column({kStageTitles[k], "/stage_tests_per_step/" + std::to_string(k), 10, 2});
  table.column({"build s", "/build_s", 10, 3});
  const auto hf = rollingTerrain();
  for (std::size_t n : sizes) table.add(timeSteps(scatter(hf, n, 42 + n), steps, 7));
  doc.text << "\nwalker step without rendering (10 km x 10 km, auto delta=8 longest/median, " << steps
           << " timed steps at 5 m/s)\n";
  doc.table("walker_steps", table);
  const Json& last = table.rows().back();
  if (last["instances"].get<std::size_t>() >= kTargetInstances)
    doc.target("walker step p99 at 1M instances", "", last["p99_us"], "<=", kTargetP99Us, " us");
}

/// The hierarchies of Table 2: the scene's template hierarchy, then every automatic one.
std::vector<std::pair<std::string, MethodSpec>> hierarchies(const MethodSpec& base) {
  MethodSpec t = base;
  t.templateHierarchy = true;
  std::vector<std::pair<std::string, MethodSpec>> out = {{"template", t}};
  for (int degree : {2, 4, 8})
    for (SplitAxis axis : {SplitAxis::LongestSide, SplitAxis::Splatter})
      for (SplitPoint point : {SplitPoint::Mean, SplitPoint::Median}) {
        MethodSpec m = base;
        m.templateHierarchy = false;
        m.autoTree = {degree, axis, point};
        out.emplace_back(
            "delta=" + std::to_string(degree) + " " + splitAxisName(axis) + "/" + splitPointName(point), m);
      }
  return out;
}

/// Parts 3 to 5's scene and flythroughs, each read once, and the walker's options for playing them
/// (the scene's viewer, no timing of the step's parts).
struct Flythroughs {
  explicit Flythroughs(const WalkerBenchOptions& o) : scene(loadScene(o.scene)) {
    for (const std::string& p : o.scripts) scripts.push_back(readScript(p));
    walker.viewer = scene.spec.viewer;
    walker.timeParts = false;
  }
  const Scene scene;
  std::vector<Script> scripts;
  WalkerOptions walker;
};

/// Part 3: the BV tests of every hierarchy on the flythroughs, fACT's Table 2. False when the
/// hierarchies' contacts differ.
bool table2(Document& doc, const WalkerBenchOptions& o, const Flythroughs& f) {
  const Scene& scene = f.scene;
  const std::vector<Script>& scripts = f.scripts;
  Table table;
  table.column({"hierarchy", "/hierarchy", 28});
  for (std::size_t i = 0; i < scripts.size(); ++i)
    table.column({std::filesystem::path(o.scripts[i]).filename().string().substr(0, 21),
                  "/bv_tests_per_script/" + std::to_string(i), 22});
  table.column({"total", "/total", 14}).column({"%", "/percent_of_template", 9, 1, false, false, "%"});
  std::vector<std::string> firstContacts;
  bool identical = true;
  double base = 0;
  for (const auto& [name, method] : hierarchies(scene.spec.method)) {
    const CollisionWorld world = CollisionWorld::fromScene(scene, method);
    Json row = {{"hierarchy", name}};
    std::vector<std::string> contacts;  // per script: the blocked-by sequence
    std::uint64_t total = 0;
    for (const Script& sc : scripts) {
      std::uint64_t node = 0, stage[3] = {0, 0, 0};
      std::string signature;
      for (const auto& r : runFlythrough(scene, world, sc, f.walker).records) {
        node += r.nodeTests;
        for (int k = 0; k < 3; ++k) stage[k] += r.stageTests.values[std::size_t(k)];
        signature += r.blocked ? r.blockedBy + ";" : "-;";
      }
      row["bv_tests_per_script"].push_back(node + stage[0] + stage[1] + stage[2]);
      row["node_tests_per_script"].push_back(node);
      for (int k = 0; k < 3; ++k) row[kStageKeys[k]].push_back(stage[k]);
      total += node + stage[0] + stage[1] + stage[2];
      contacts.push_back(signature);
    }
    if (base == 0) base = double(total);
    if (firstContacts.empty()) firstContacts = contacts;
    identical = identical && contacts == firstContacts;
    row["total"] = total;
    row["percent_of_template"] = 100.0 * double(total) / base;
    table.add(std::move(row));
  }
  doc.text << "\nBV tests on the bundled flythroughs (fACT Table 2 style: hierarchy node tests + AABB-AABB + "
              "AABB-OBB + OBB-OBB; % of the template hierarchy)\n";
  doc.table("table2", table);
  doc.text << "contacts identical across hierarchies: " << (identical ? "yes" : "NO") << "\n";
  doc.json["table2_identical_contacts"] = identical;
  doc.json["table2_scripts"] = o.scripts;
  return identical;
}

/// Part 4's recorder: every sweep's broad-phase candidates (the swept outer box's query, as
/// CollisionWorld::sweep runs it; repeated sweeps, answered from the world's cache, included).
class CandidateRecorder : public SweepObserver {
 public:
  struct Query {
    NestedVolume<double> viewer;
    std::vector<std::uint32_t> candidates;
  };
  explicit CandidateRecorder(const CollisionWorld& w) : world_(w) {}
  void onSweep(const NestedVolume<double>& viewer, const Vec3<double>& d, const SweepHit&) override {
    Aabb<double> swept = viewer.outer;
    swept.extend(Aabb<double>{viewer.outer.min + d, viewer.outer.max + d});
    Query q{viewer, {}};
    world_.tree().query(swept, q.candidates);
    queries.push_back(std::move(q));
  }
  std::vector<Query> queries;

 private:
  const CollisionWorld& world_;
};

/// ns per query of `run` over all queries, repeated for at least 0.2 s.
template <class F>
double nsPerQuery(std::size_t queries, const F& run) {
  std::size_t passes = 0, sink = 0;
  const auto t0 = std::chrono::steady_clock::now();
  do {
    sink += run();
    ++passes;
  } while (secondsSince(t0) < 0.2);
  benchmark::DoNotOptimize(sink);
  return 1e9 * secondsSince(t0) / double(passes * std::max<std::size_t>(1, queries));
}

/// The static nested test of each query's viewer against its candidates, two ways on the same
/// queries: scalar testNested per candidate (CollisionWorld::overlapping's narrow phase), and
/// testBoxPairs on the viewer's and the candidates' inner boxes (the float batch's cost at that
/// size). A row of the narrow-phase table.
Json narrowRow(const std::string& what, const CollisionWorld& world,
               const std::vector<CandidateRecorder::Query>& qs) {
  const std::vector<double> counts = figureOf(qs, [](const CandidateRecorder::Query& q) { return q.candidates.size(); });
  const double scalar = nsPerQuery(qs.size(), [&] {
    std::size_t hits = 0;
    for (const auto& q : qs)
      for (std::uint32_t u : q.candidates) hits += testNested(q.viewer, world.unit(u)).overlap ? 1 : 0;
    return hits;
  });
  const double pairs = nsPerQuery(qs.size(), [&] {
    std::size_t hits = 0;
    std::vector<Obb<double>> a, b;
    std::vector<NestedResult> r;
    for (const auto& q : qs) {
      a.assign(q.candidates.size(), q.viewer.inner);
      b.clear();
      for (std::uint32_t u : q.candidates) b.push_back(world.unit(u).inner);
      r.resize(b.size());
      testBoxPairs({a.data(), b.data(), b.size()}, r.data());
      for (const NestedResult& x : r) hits += x.overlap ? 1 : 0;
    }
    return hits;
  });
  return {{"queries", what},       {"count", qs.size()},       {"mean_candidates", mean(counts)},
          {"p99_candidates", percentile(counts, 99)}, {"max_candidates", percentile(counts, 100)},
          {"scalar_ns", scalar},  {"pairs_ns", pairs}};
}

/// Part 4: the walker's narrow phase at the candidate counts it sees on the bundled flythroughs,
/// and at fixed counts (each recorded viewer against its k nearest units) to find where a batch
/// pays. Recorded on the scene's own method and hierarchy.
void narrowPhase(Document& doc, const Flythroughs& f) {
  CollisionWorld world = CollisionWorld::fromScene(f.scene, f.scene.spec.method);
  CandidateRecorder recorder(world);
  {
    const ObservedSweeps observed(world, recorder);
    for (const Script& script : f.scripts) runFlythrough(f.scene, world, script, f.walker);
  }
  Table table;
  table.column({"queries", "/queries", 22, 0, true}).column({"count", "/count", 8});
  table.column({"cand mean", "/mean_candidates", 10, 2}).column({"cand p99", "/p99_candidates", 9, 0});
  table.column({"cand max", "/max_candidates", 9, 0}).column({"scalar ns", "/scalar_ns", 10, 1});
  table.column({"pairs ns", "/pairs_ns", 10, 1});
  table.add(narrowRow("flythrough sweeps", world, recorder.queries));
  for (const std::size_t k : {1, 2, 4, 8, 16, 32, 64}) {
    if (k > world.size()) break;
    std::vector<CandidateRecorder::Query> fixed;
    for (std::size_t i = 0; i < recorder.queries.size(); i += 16) {
      CandidateRecorder::Query q{recorder.queries[i].viewer, {}};
      std::vector<std::pair<double, std::uint32_t>> byDistance;
      for (std::uint32_t u = 0; u < world.size(); ++u)
        byDistance.emplace_back((world.unit(u).inner.center - q.viewer.inner.center).squaredNorm(), u);
      std::partial_sort(byDistance.begin(), byDistance.begin() + std::ptrdiff_t(k), byDistance.end());
      for (std::size_t j = 0; j < k; ++j) q.candidates.push_back(byDistance[j].second);
      fixed.push_back(std::move(q));
    }
    table.add(narrowRow(std::to_string(k) + " nearest units", world, fixed));
  }
  doc.text << "\nnarrow phase per query: the viewer's static nested test against its broad-phase candidates"
              " (bundled flythroughs' sweeps; then each 16th viewer against its k nearest units):"
              " scalar testNested per candidate, testBoxPairs on the inner boxes; ns per query, same run\n";
  doc.table("narrow_phase", table);
}

/// Part 5: what a run's results layers cost next to the whole headless run (each flythrough
/// recorded as `nestwalk run` does), and a 10,000-fix GPS track turned into a script.
void routesAndResults(Document& doc, const WalkerBenchOptions& o) {
  // The runs and the track in a folder of the benchmark's own, removed at the end (also when a run
  // or the route throws).
  const OutputFolder scratch((std::filesystem::temp_directory_path() / "nestwalk-bench-routes").string());
  const std::filesystem::path folder = scratch.tempPath();
  Table table;
  table.column({"flythrough", "/script", 22, 0, true}).column({"run s", "/run_s", 9, 3}).column({"layers s", "/layers_s", 10, 3});
  table.column({"%", "/layers_percent", 7, 1, false, false, "%"});
  double run = 0, layers = 0;
  for (const std::string& script : o.scripts) {
    RecordedRunOptions ro;
    ro.scene = o.scene;
    ro.script = script;
    ro.out = (folder / "run").string();
    ro.overwrite = true;
    const RecordedRun r = recordRun(ro);
    run += r.seconds;
    layers += r.layersSeconds;
    table.add({{"script", std::filesystem::path(script).filename().string()}, {"run_s", r.seconds},
               {"layers_s", r.layersSeconds}, {"layers_percent", 100.0 * r.layersSeconds / r.seconds}});
  }
  // A phone's track of kRouteFixes fixes, walking back and forth across the scene's middle (the
  // scene loaded after the runs, which load their own: one copy resident at a time).
  const Scene scene = loadScene(o.scene);
  const terrain::Heightfield& hf = *scene.terrain;
  const Eigen::Vector2d mid = hf.samplePosition(hf.cols() / 2, hf.rows() / 2);
  assets::PhoneTrack track;
  track.name = "bench";
  const double leg = 0.3 * double(hf.cols()) * (hf.samplePosition(1, 0).x() - hf.samplePosition(0, 0).x());
  for (std::size_t k = 0; double(k) * leg < track.speed * double(kRouteFixes) + 2 * leg; ++k)
    track.legs.push_back(mid + Eigen::Vector2d(k % 2 ? leg / 2 : -leg / 2, 0.5 * double(k % 7)));
  const std::string gpx = (folder / "track.gpx").string();
  writeFileAtomically(gpx, assets::phoneTrackGpx(track, hf, hf.crsWkt().c_str(), 1));
  gis::RouteRequest request;
  request.route.source = gpx;
  request.script.useTimes = true;
  std::size_t gotos = 0;
  const double routeSeconds = leastSeconds(3, [&] { gotos = gis::planRoute(o.scene, request).gotos; });
  doc.text << "\nResults layers (results.gpkg, results.geojson) against the whole headless run, per flythrough\n";
  doc.table("results_layers", table);
  doc.text << "route: a " << gotos + 1 << "-fix GPX track into a timed script: " << routeSeconds << " s\n";
  doc.json["route_fixes"] = gotos + 1;
  doc.json["route_seconds"] = routeSeconds;
  doc.target("results layers' share of the headless runs (%)", "", 100.0 * layers / run, "<=", kTargetLayersPercent);
  doc.target("10,000-fix GPX track into a script (s)", "", routeSeconds, "<=", kTargetRouteSeconds);
}

}  // namespace

int runBenchmark(const WalkerBenchOptions& o, std::ostream& out) {
  Document doc("nestwalk bench walker:"
               " walker steps, the broad phase against btDbvt and FCL, BV tests per hierarchy");
  walkerSteps(doc, o);
  if (o.broadPhase) {
    BroadPhaseBenchOptions bo;
    bo.quick = o.quick;
    const Document bp = measureBroadPhase(bo);
    doc.text << "\n" << bp.title() << "\n" << bp.text.str();
    doc.json["broad_phase"] = bp.finalJson();
    doc.targets.insert(doc.targets.end(), bp.targets.begin(), bp.targets.end());
    for (const auto& [name, message] : bp.errors) doc.errors["broad phase: " + name] = message;
  }
  if (o.table2 && !o.scene.empty() && !o.scripts.empty()) {
    {
      const Flythroughs flythroughs(o);
      if (!table2(doc, o, flythroughs)) doc.errors["table2"] = "the hierarchies' contacts differ on the flythroughs";
      narrowPhase(doc, flythroughs);
    }
    routesAndResults(doc, o);
  }
  return doc.write(out, o.json);
}

}  // namespace nestwalk::bench
