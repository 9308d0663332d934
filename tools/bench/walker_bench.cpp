#include "tools/bench/walker_bench.h"

#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/walker/flythrough.h"
#include "tools/bench/bench_runner.h"
#include "tools/bench/broadphase_bench.h"

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

namespace nestwalk::bench {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSide = 10000.0;  // metres
constexpr double kCell = 5.0;
constexpr double kOriginX = 550000.0, kOriginY = 4650000.0;

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
    b.axes = Eigen::AngleAxisd(rng.uniform(0, 2 * kPi), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    b.halfExtents = Vec3<double>(k->hx, k->hy, k->hz);
    units.push_back(NestedVolume<double>::fromObb(b));
    names.push_back(k->name);
    groups.push_back("cell" + std::to_string(int(x / 1000)) + "_" + std::to_string(int(y / 1000)));
  }
  World w;
  w.hf = hf;
  const auto t0 = std::chrono::steady_clock::now();
  w.world = std::make_unique<CollisionWorld>(std::move(units), std::move(names), std::move(groups), MethodSpec{});
  w.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return w;
}

struct StepStats {
  std::size_t instances = 0, steps = 0, contacts = 0;
  double p50 = 0, p99 = 0, max = 0, mean = 0, buildSeconds = 0;
  double nodeTestsPerStep = 0, stageTestsPerStep[3] = {0, 0, 0};
};

/// Walks the viewer at 5 m/s between random waypoints 50-500 m apart (a new one when reached or
/// after 10 blocked steps) and times every step.
StepStats timeSteps(const World& w, std::size_t steps, std::uint64_t seed) {
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
    const double a = rng.uniform(0, 2 * kPi), dist = rng.uniform(50, 500);
    const Eigen::Vector2d p = walker.state().feet.head<2>() + dist * Eigen::Vector2d(std::cos(a), std::sin(a));
    target = p.cwiseMax(Eigen::Vector2d(kOriginX + 50, kOriginY + 50))
                 .cwiseMin(Eigen::Vector2d(kOriginX + kSide - 50, kOriginY + kSide - 50));
  };
  newTarget();
  const std::size_t warmup = std::min<std::size_t>(1000, steps / 10);
  std::vector<double> us;
  us.reserve(steps);
  StepStats s;
  s.instances = w.world->size();
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
    in.headingDeg = std::fmod(std::atan2(d.x(), d.y()) * 180.0 / kPi + 360.0, 360.0);
    const auto t0 = std::chrono::steady_clock::now();
    const StepReport r = walker.step(in);
    const auto t1 = std::chrono::steady_clock::now();
    blockedRun = walker.state().blocked ? blockedRun + 1 : 0;
    if (i < warmup) continue;
    us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
    s.contacts += walker.state().blocked;
    s.nodeTestsPerStep += double(r.counters.nodeTests);
    for (int k = 0; k < 3; ++k) s.stageTestsPerStep[k] += double(r.counters.stageTests.values[std::size_t(k)]);
  }
  s.steps = us.size();
  s.nodeTestsPerStep /= double(s.steps);
  for (double& v : s.stageTestsPerStep) v /= double(s.steps);
  double sum = 0;
  for (double v : us) sum += v;
  s.mean = sum / double(us.size());
  s.p50 = percentile(us, 50);
  s.p99 = percentile(us, 99);
  s.max = percentile(us, 100);
  return s;
}

struct HierarchyCounts {
  std::string name;
  std::vector<std::uint64_t> perScript;  // BV tests (nodes + three stages) per script
  std::vector<std::uint64_t> nodeTests, stage[3];
  std::uint64_t total = 0;
  std::vector<std::string> contacts;  // per script: blocked-by sequence signature
};

std::vector<MethodSpec> hierarchies(const MethodSpec& base, std::vector<std::string>& names) {
  std::vector<MethodSpec> out;
  MethodSpec t = base;
  t.templateHierarchy = true;
  out.push_back(t);
  names.push_back("template");
  for (int degree : {2, 4, 8})
    for (SplitAxis axis : {SplitAxis::LongestSide, SplitAxis::Splatter})
      for (SplitPoint point : {SplitPoint::Mean, SplitPoint::Median}) {
        MethodSpec m = base;
        m.templateHierarchy = false;
        m.autoTree = {degree, axis, point};
        out.push_back(m);
        names.push_back("delta=" + std::to_string(degree) + " " + splitAxisName(axis) + "/" + splitPointName(point));
      }
  return out;
}

}  // namespace

int runWalkerBench(const WalkerBenchOptions& o, std::ostream& out) {
  std::vector<std::size_t> sizes = o.sizes;
  if (sizes.empty()) sizes = o.quick ? std::vector<std::size_t>{1000, 10000} : std::vector<std::size_t>{1000, 100000, 1000000};
  const std::size_t steps = o.steps ? o.steps : (o.quick ? 5000 : 200000);
  nlohmann::ordered_json j;
  std::ostringstream text;

  // 1. Walker steps.
  const auto hf = rollingTerrain();
  std::vector<StepStats> stats;
  for (std::size_t n : sizes) {
    const World w = scatter(hf, n, 42 + n);
    StepStats s = timeSteps(w, steps, 7);
    s.buildSeconds = w.buildSeconds;
    stats.push_back(s);
  }
  text << "cpu: " << cpuModelName() << "\n\nwalker step without rendering (10 km x 10 km, auto delta=8 longest/median, "
       << steps << " timed steps at 5 m/s)\n";
  text << std::setw(10) << "instances" << std::setw(10) << "p50 us" << std::setw(10) << "p99 us" << std::setw(10)
       << "max us" << std::setw(10) << "mean us" << std::setw(12) << "contacts/k" << std::setw(12) << "node tests"
       << std::setw(10) << "aabb-aabb" << std::setw(10) << "aabb-obb" << std::setw(10) << "obb-obb" << std::setw(10)
       << "build s" << "\n";
  for (const auto& s : stats) {
    text << std::setw(10) << s.instances << std::setw(10) << fixedText(s.p50, 3) << std::setw(10) << fixedText(s.p99, 3)
         << std::setw(10) << fixedText(s.max, 1) << std::setw(10) << fixedText(s.mean, 3) << std::setw(12)
         << fixedText(1000.0 * double(s.contacts) / double(s.steps), 1) << std::setw(12) << fixedText(s.nodeTestsPerStep, 1)
         << std::setw(10) << fixedText(s.stageTestsPerStep[0], 2) << std::setw(10) << fixedText(s.stageTestsPerStep[1], 2)
         << std::setw(10) << fixedText(s.stageTestsPerStep[2], 2) << std::setw(10) << fixedText(s.buildSeconds, 3) << "\n";
    nlohmann::ordered_json r;
    r["instances"] = s.instances;
    r["steps"] = s.steps;
    r["p50_us"] = s.p50;
    r["p99_us"] = s.p99;
    r["max_us"] = s.max;
    r["mean_us"] = s.mean;
    r["contacts_per_1000"] = 1000.0 * double(s.contacts) / double(s.steps);
    r["node_tests_per_step"] = s.nodeTestsPerStep;
    r["stage_tests_per_step"] = {s.stageTestsPerStep[0], s.stageTestsPerStep[1], s.stageTestsPerStep[2]};
    r["build_s"] = s.buildSeconds;
    j["walker_steps"].push_back(r);
  }
  std::vector<Target> targets;
  if (!stats.empty() && stats.back().instances >= 1000000)
    targets.push_back({"walker step p99 at 1M instances", "<= 2 us", stats.back().p99, stats.back().p99 <= 2.0});

  // 2. The broad phase against btDbvt and FCL on the same boxes.
  if (o.broadPhase) {
    BroadPhaseBenchOptions bo;
    bo.quick = o.quick;
    const BroadPhaseReport bp = measureBroadPhase(bo);
    text << "\n" << bp.table;
    j["broad_phase"] = bp.json;
    targets.insert(targets.end(), bp.targets.begin(), bp.targets.end());
    if (bp.rc != 0) {
      out << text.str();
      return bp.rc;
    }
  }

  // 3. Table 2 on the bundled flythroughs.
  if (!o.scene.empty() && !o.scripts.empty()) {
    const Scene scene = loadScene(o.scene);
    std::vector<Script> scripts;
    for (const auto& p : o.scripts) scripts.push_back(readScript(p));
    std::vector<std::string> names;
    const std::vector<MethodSpec> methods = hierarchies(scene.spec.method, names);
    std::vector<HierarchyCounts> rows;
    WalkerOptions wo;
    wo.viewer = scene.spec.viewer;
    wo.timeParts = false;
    for (std::size_t m = 0; m < methods.size(); ++m) {
      const CollisionWorld world = CollisionWorld::fromScene(scene, methods[m]);
      HierarchyCounts row;
      row.name = names[m];
      for (const Script& sc : scripts) {
        const FlythroughResult res = runFlythrough(scene, world, sc, wo);
        std::uint64_t node = 0, st[3] = {0, 0, 0};
        std::string sig;
        for (const auto& r : res.records) {
          node += r.nodeTests;
          for (int k = 0; k < 3; ++k) st[k] += r.stageTests.values[std::size_t(k)];
          sig += r.blocked ? r.blockedBy + ";" : "-;";
        }
        row.nodeTests.push_back(node);
        for (int k = 0; k < 3; ++k) row.stage[k].push_back(st[k]);
        row.perScript.push_back(node + st[0] + st[1] + st[2]);
        row.total += row.perScript.back();
        row.contacts.push_back(sig);
      }
      rows.push_back(row);
    }
    bool identical = true;
    for (const auto& r : rows) identical = identical && r.contacts == rows.front().contacts;
    text << "\nBV tests on the bundled flythroughs (fACT Table 2 style: hierarchy node tests + AABB-AABB + "
            "AABB-OBB + OBB-OBB; % of the template hierarchy)\n";
    text << std::setw(28) << "hierarchy";
    for (const auto& p : o.scripts) {
      std::string s = p.substr(p.find_last_of('/') + 1);
      text << std::setw(22) << s.substr(0, 21);
    }
    text << std::setw(14) << "total" << std::setw(9) << "%" << "\n";
    const double base = double(rows.front().total);
    for (const auto& r : rows) {
      text << std::setw(28) << r.name;
      for (std::size_t s = 0; s < r.perScript.size(); ++s) text << std::setw(22) << r.perScript[s];
      text << std::setw(14) << r.total << std::setw(8) << fixedText(100.0 * double(r.total) / base, 1) << "%\n";
      nlohmann::ordered_json jr;
      jr["hierarchy"] = r.name;
      jr["bv_tests_per_script"] = r.perScript;
      jr["node_tests_per_script"] = r.nodeTests;
      jr["aabb_aabb_per_script"] = r.stage[0];
      jr["aabb_obb_per_script"] = r.stage[1];
      jr["obb_obb_per_script"] = r.stage[2];
      jr["total"] = r.total;
      jr["percent_of_template"] = 100.0 * double(r.total) / base;
      j["table2"].push_back(jr);
    }
    text << "contacts identical across hierarchies: " << (identical ? "yes" : "NO") << "\n";
    j["table2_identical_contacts"] = identical;
    j["table2_scripts"] = o.scripts;
    if (!identical) {
      out << text.str();
      return 1;
    }
  }
  j["targets"] = targetsJson(targets);
  if (o.json) {
    out << j.dump(2) << "\n";
  } else {
    out << text.str();
    printTargets(out, targets, 36, 12);
  }
  return 0;
}

}  // namespace nestwalk::bench
