// The broad-phase benchmark (see broadphase_bench.h).
//
// Every benchmark answers the whole query set once per Google Benchmark iteration, summing the hit
// counts (benchmark::DoNotOptimize), with SetItemsProcessed(iterations * queries), so
// µs/query = 1e6 / items_per_second. The boxes and queries of one size are generated once from
// fixed seeds (splitmix64) and kept while that size's benchmarks run (they run one size after the
// other, registration order); each structure is built on first use, outside the timed loops, and
// its build time recorded. Hits per query are compared with nestwalk's default hierarchy outside
// the timed loops, and that hierarchy itself with brute force on a prefix of the queries.
#include "tools/bench/broadphase_bench.h"

#include "nestwalk/hierarchy/box_tree.h"

#include <benchmark/benchmark.h>

#include <BulletCollision/BroadphaseCollision/btDbvt.h>
#include <LinearMath/btScalar.h>
#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/config.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/narrowphase/collision_object.h>

#include <algorithm>
#include <ctime>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

namespace nestwalk::bench {
namespace {

using Json = nlohmann::ordered_json;
using Box = Aabb<double>;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kArea = 10000.0;      // m, side of the square the boxes are scattered over
constexpr double kBaseZMax = 50.0;     // m, box bases (the ground) between 0 and this
constexpr int kWalkSteps = 1000;       // queries per walk before starting a new one
constexpr double kMaxStep = 1.0;       // m, viewer motion per query (the swept part)
const Eigen::Vector3d kViewer(0.5, 0.5, 1.8);  // m, the viewer's box
constexpr double kBruteForceBoxTests = 2e8;    // box tests spent checking the reference

struct Config {
  std::vector<std::size_t> sizes{1000, 10000, 100000, 1000000};
  std::size_t queries = 100'000;
  double minTime = 0.3;
};
Config& config() {
  static Config c;
  return c;
}

struct MethodDef {
  const char* key;
  const char* label;
  const char* column;  // build-time table header
  int degree;  // 0: a peer
  SplitAxis axis;
  SplitPoint point;
};
constexpr MethodDef kMethods[] = {
    {"nestwalk_d2_longest_median", "nestwalk d=2 longest/median", "d=2", 2, SplitAxis::LongestSide, SplitPoint::Median},
    {"nestwalk_d4_longest_median", "nestwalk d=4 longest/median", "d=4", 4, SplitAxis::LongestSide, SplitPoint::Median},
    {"nestwalk_d8_longest_median", "nestwalk d=8 longest/median", "d=8", 8, SplitAxis::LongestSide, SplitPoint::Median},
    {"nestwalk_d4_splatter_mean", "nestwalk d=4 splatter/mean", "d=4 spl/mean", 4, SplitAxis::Splatter, SplitPoint::Mean},
    {"btdbvt", "Bullet btDbvt", "btDbvt", 0, SplitAxis::LongestSide, SplitPoint::Median},
    {"fcl_dynamic_aabb", "FCL DynamicAABBTree", "FCL", 0, SplitAxis::LongestSide, SplitPoint::Median},
};
constexpr const char* kDefaultTree = "nestwalk_d8_longest_median";  // the default AutoTreeOptions
constexpr const char* kBullet = "btdbvt";
constexpr const char* kFcl = "fcl_dynamic_aabb";

std::string benchName(const std::string& method, std::size_t n) {
  return "broadphase/" + method + "/" + std::to_string(n);
}

/// x rounded down / up to a float, returned as double (so every peer sees the same numbers).
double floatDown(double x) {
  float f = static_cast<float>(x);
  if (double(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}
double floatUp(double x) {
  float f = static_cast<float>(x);
  if (double(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}
Box floatBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  Box b;
  for (int k = 0; k < 3; ++k) {
    b.min[k] = floatDown(lo[k]);
    b.max[k] = floatUp(hi[k]);
  }
  return b;
}

// ------------------------------------------------------------------------------------------------
// Data and structures of one size.

struct FclData {
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects, queries;
  std::unique_ptr<fcl::DynamicAABBTreeCollisionManagerd> manager;
  std::size_t aabbMismatches = 0;  // objects whose FCL AABB differs from the box (should be 0)
};

struct Scene {
  std::size_t n = 0;
  std::vector<Box> boxes, queries;
  std::map<std::string, BoxTree> trees;
  std::unique_ptr<btDbvt> dbvt;
  std::vector<btDbvtVolume> dbvtQueries;
  std::unique_ptr<FclData> fcl;
  std::vector<std::vector<std::uint32_t>> reference;  // sorted hits per query (default tree)
};

std::unique_ptr<Scene>& currentScene() {
  static std::unique_ptr<Scene> s;
  return s;
}

struct Facts {
  std::uint64_t hits = 0;
  long long disagreements = -1;  // queries whose hit set differs from the reference
  double buildSeconds = kNaN;
  std::size_t queries = 0;
  double nodeTests = kNaN, leafTests = kNaN;  // nestwalk: BV tests per query (BroadPhaseCounters)
  int depth = 0;
};
std::map<std::string, Facts>& facts() {
  static std::map<std::string, Facts> f;
  return f;
}
struct ReferenceCheck {
  std::size_t queries = 0, differ = 0;
};
std::map<std::size_t, ReferenceCheck>& referenceChecks() {
  static std::map<std::size_t, ReferenceCheck> r;
  return r;
}
std::map<std::size_t, std::size_t>& fclMismatches() {
  static std::map<std::size_t, std::size_t> m;
  return m;
}

/// CPU time of this thread in seconds: build times like the queries' CPU times, unaffected by other
/// processes on a shared machine (wall time there can be twice as long).
double threadSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

void makeBoxes(Scene& s) {
  SplitMix64 rng(0x62726f6164ull ^ (std::uint64_t(s.n) * 0x9E3779B97F4A7C15ull));
  s.boxes.reserve(s.n);
  const double half = 0.5 * kArea;
  for (std::size_t i = 0; i < s.n; ++i) {
    const Eigen::Vector3d base(rng.uniform(-half, half), rng.uniform(-half, half), rng.uniform(0, kBaseZMax));
    const double kind = rng.uniform();
    Eigen::Vector3d h;  // half extents of the AABB
    if (kind < 0.3) {   // pole
      const double w = rng.uniform(0.05, 0.3);
      h = {0.5 * w, 0.5 * w, 0.5 * rng.uniform(2.0, 12.0)};
    } else if (kind < 0.7) {  // cabinet
      h = {0.5 * rng.uniform(0.5, 3.0), 0.5 * rng.uniform(0.5, 3.0), 0.5 * rng.uniform(0.5, 3.0)};
    } else {  // container at a heading: the AABB of its rotated footprint
      const double a = 0.5 * 2.4, b = 0.5 * rng.uniform(6.0, 12.0), t = rng.uniform(0, std::numbers::pi);
      h = {a * std::abs(std::cos(t)) + b * std::abs(std::sin(t)), a * std::abs(std::sin(t)) + b * std::abs(std::cos(t)),
           0.5 * 2.6};
    }
    const Eigen::Vector3d c(base.x(), base.y(), base.z() + h.z());
    s.boxes.push_back(floatBox(c - h, c + h));
  }
}

void makeQueries(Scene& s) {
  SplitMix64 rng(0x77616c6bull ^ (std::uint64_t(s.n) * 0xC2B2AE3D27D4EB4Full));
  const std::size_t q = config().queries;
  s.queries.reserve(q);
  const double half = 0.5 * kArea;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  double heading = 0;
  for (std::size_t k = 0; k < q; ++k) {
    if (k % kWalkSteps == 0) {  // a new walk, starting 1-5 m from a random box, on its ground
      const Box& b = s.boxes[std::size_t(rng.next() % s.boxes.size())];
      const double d = rng.uniform(1.0, 5.0), a = rng.uniform(0, 2 * std::numbers::pi);
      p = {0.5 * (b.min.x() + b.max.x()) + d * std::cos(a), 0.5 * (b.min.y() + b.max.y()) + d * std::sin(a), b.min.z()};
      heading = rng.uniform(0, 2 * std::numbers::pi);
    }
    heading += 0.3 * rng.gaussian();
    const double step = rng.uniform(0, kMaxStep);
    Eigen::Vector3d next = p + step * Eigen::Vector3d(std::cos(heading), std::sin(heading), 0);
    next.x() = std::clamp(next.x(), -half, half);
    next.y() = std::clamp(next.y(), -half, half);
    const Eigen::Vector3d h(0.5 * kViewer.x(), 0.5 * kViewer.y(), 0);
    const Eigen::Vector3d lo = p.cwiseMin(next) - h, hi = p.cwiseMax(next) + h + Eigen::Vector3d(0, 0, kViewer.z());
    s.queries.push_back(floatBox(lo, hi));
    p = next;
  }
}

Scene& scene(std::size_t n) {
  std::unique_ptr<Scene>& s = currentScene();
  if (!s || s->n != n || s->queries.size() != config().queries) {
    s.reset();  // free the previous size first
    s = std::make_unique<Scene>();
    s->n = n;
    makeBoxes(*s);
    makeQueries(*s);
  }
  return *s;
}

const MethodDef& method(const std::string& key) {
  for (const MethodDef& m : kMethods)
    if (key == m.key) return m;
  return kMethods[1];
}

const BoxTree& tree(Scene& s, const std::string& key) {
  auto it = s.trees.find(key);
  if (it == s.trees.end()) {
    const MethodDef& m = method(key);
    const double t0 = threadSeconds();
    BoxTree t = BoxTree::buildAuto(s.boxes, AutoTreeOptions{m.degree, m.axis, m.point});
    facts()[benchName(key, s.n)].buildSeconds = threadSeconds() - t0;
    it = s.trees.emplace(key, std::move(t)).first;
  }
  return it->second;
}

btVector3 bt(const Eigen::Vector3d& v) { return btVector3(btScalar(v.x()), btScalar(v.y()), btScalar(v.z())); }

btDbvt& dbvt(Scene& s) {
  if (!s.dbvt) {
    const double t0 = threadSeconds();
    s.dbvt = std::make_unique<btDbvt>();
    for (std::size_t i = 0; i < s.boxes.size(); ++i)
      s.dbvt->insert(btDbvtVolume::FromMM(bt(s.boxes[i].min), bt(s.boxes[i].max)),
                     reinterpret_cast<void*>(static_cast<std::uintptr_t>(i)));
    facts()[benchName(kBullet, s.n)].buildSeconds = threadSeconds() - t0;
    s.dbvtQueries.clear();
    for (const Box& q : s.queries) s.dbvtQueries.push_back(btDbvtVolume::FromMM(bt(q.min), bt(q.max)));
  }
  return *s.dbvt;
}

std::unique_ptr<fcl::CollisionObjectd> fclObject(const Box& b, std::size_t index) {
  // Centre and side lengths are exact in double for float coordinates, so FCL's AABB
  // (centre -+ side / 2) is the box itself (checked below).
  const Eigen::Vector3d side = b.max - b.min, centre = 0.5 * (b.min + b.max);
  auto geom = std::make_shared<fcl::Boxd>(side);
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.translation() = centre;
  auto obj = std::make_unique<fcl::CollisionObjectd>(geom, tf);
  obj->setUserData(reinterpret_cast<void*>(static_cast<std::uintptr_t>(index)));
  return obj;
}

FclData& fclData(Scene& s) {
  if (!s.fcl) {
    auto f = std::make_unique<FclData>();
    const double t0 = threadSeconds();
    f->objects.reserve(s.boxes.size());
    std::vector<fcl::CollisionObjectd*> raw;
    raw.reserve(s.boxes.size());
    for (std::size_t i = 0; i < s.boxes.size(); ++i) {
      f->objects.push_back(fclObject(s.boxes[i], i));
      raw.push_back(f->objects.back().get());
    }
    f->manager = std::make_unique<fcl::DynamicAABBTreeCollisionManagerd>();
    f->manager->registerObjects(raw);
    f->manager->setup();
    facts()[benchName(kFcl, s.n)].buildSeconds = threadSeconds() - t0;  // objects + registerObjects + setup
    for (std::size_t i = 0; i < s.boxes.size(); ++i) {
      const fcl::AABBd& a = f->objects[i]->getAABB();
      if (a.min_ != s.boxes[i].min || a.max_ != s.boxes[i].max) ++f->aabbMismatches;
    }
    for (std::size_t k = 0; k < s.queries.size(); ++k) {
      f->queries.push_back(fclObject(s.queries[k], k));
      const fcl::AABBd& a = f->queries.back()->getAABB();
      if (a.min_ != s.queries[k].min || a.max_ != s.queries[k].max) ++f->aabbMismatches;
    }
    fclMismatches()[s.n] = f->aabbMismatches;
    s.fcl = std::move(f);
  }
  return *s.fcl;
}

// The answers: append the hits of query k to `out`.

struct DbvtCollect : btDbvt::ICollide {
  std::vector<std::uint32_t>* out = nullptr;
  void Process(const btDbvtNode* leaf) override {
    out->push_back(static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(leaf->data)));
  }
};

bool fclRecord(fcl::CollisionObjectd* inTree, fcl::CollisionObjectd*, void* data) {
  static_cast<std::vector<std::uint32_t>*>(data)->push_back(
      static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(inTree->getUserData())));
  return false;  // go on: all pairs, no narrow phase
}

void reference(Scene& s) {
  if (!s.reference.empty()) return;
  const BoxTree& t = tree(s, kDefaultTree);
  s.reference.resize(s.queries.size());
  for (std::size_t k = 0; k < s.queries.size(); ++k) {
    t.query(s.queries[k], s.reference[k]);
    std::sort(s.reference[k].begin(), s.reference[k].end());
  }
  // The reference itself against brute force, on as many queries as kBruteForceBoxTests allows.
  ReferenceCheck c;
  c.queries = std::min(s.queries.size(), std::max<std::size_t>(10, std::size_t(kBruteForceBoxTests / double(s.n))));
  std::vector<std::uint32_t> h;
  for (std::size_t k = 0; k < c.queries; ++k) {
    h.clear();
    const Box& q = s.queries[k];
    for (std::uint32_t i = 0; i < s.boxes.size(); ++i) {
      const Box& b = s.boxes[i];
      if ((b.min.array() <= q.max.array()).all() && (q.min.array() <= b.max.array()).all()) h.push_back(i);
    }
    c.differ += h != s.reference[k] ? 1 : 0;
  }
  referenceChecks()[s.n] = c;
}

template <class Answer>
void queryBenchmark(benchmark::State& state, const std::string& name, Scene& s, Answer&& answer) {
  Facts& f = facts()[name];
  if (f.disagreements < 0) {
    reference(s);
    std::vector<std::uint32_t> out;
    f.hits = 0;
    f.disagreements = 0;
    for (std::size_t k = 0; k < s.queries.size(); ++k) {
      out.clear();
      answer(k, out);
      f.hits += out.size();
      std::sort(out.begin(), out.end());
      f.disagreements += out != s.reference[k] ? 1 : 0;
    }
    f.queries = s.queries.size();
  }
  std::vector<std::uint32_t> out;
  out.reserve(1024);
  for (auto _ : state) {
    std::size_t hits = 0;
    for (std::size_t k = 0; k < s.queries.size(); ++k) {
      out.clear();
      answer(k, out);
      hits += out.size();
    }
    benchmark::DoNotOptimize(hits);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(s.queries.size()));
  state.counters["hits"] = double(f.hits);
  state.counters["disagreements"] = double(f.disagreements);
}

void runMethod(benchmark::State& state, const std::string& key, std::size_t n) {
  Scene& s = scene(n);
  const std::string name = benchName(key, n);
  if (key == kBullet) {
    btDbvt& d = dbvt(s);
    DbvtCollect cb;
    queryBenchmark(state, name, s, [&](std::size_t k, std::vector<std::uint32_t>& out) {
      cb.out = &out;
      d.collideTV(d.m_root, s.dbvtQueries[k], cb);
    });
  } else if (key == kFcl) {
    FclData& f = fclData(s);
    queryBenchmark(state, name, s, [&](std::size_t k, std::vector<std::uint32_t>& out) {
      f.manager->collide(f.queries[k].get(), &out, fclRecord);
    });
  } else {
    const BoxTree& t = tree(s, key);
    Facts& f = facts()[name];
    if (std::isnan(f.nodeTests)) {
      BroadPhaseCounters c;
      std::vector<std::uint32_t> out;
      for (const Box& q : s.queries) {
        out.clear();
        t.query(q, out, &c);
      }
      f.nodeTests = double(c.nodeTests) / double(s.queries.size());
      f.leafTests = double(c.leafTests) / double(s.queries.size());
      f.depth = t.depth();
    }
    queryBenchmark(state, name, s,
                   [&](std::size_t k, std::vector<std::uint32_t>& out) { t.query(s.queries[k], out); });
  }
}

std::map<std::string, benchmark::internal::Benchmark*>& registered() {
  static std::map<std::string, benchmark::internal::Benchmark*> r;
  return r;
}

std::string fmtInt(std::uint64_t v) { return std::to_string(v); }

}  // namespace

// ------------------------------------------------------------------------------------------------

void registerBroadPhaseBenchmarks(const BroadPhaseBenchOptions& opts) {
  Config& c = config();
  c.sizes = !opts.sizes.empty() ? opts.sizes
            : opts.quick        ? std::vector<std::size_t>{1000, 10000}
                                : std::vector<std::size_t>{1000, 10000, 100000, 1000000};
  c.queries = opts.queries ? opts.queries : (opts.quick ? 10'000 : 100'000);
  c.minTime = opts.minTimeSeconds > 0 ? opts.minTimeSeconds : (opts.quick ? 0.02 : 0.3);
  for (std::size_t n : c.sizes)
    for (const MethodDef& m : kMethods) {
      const std::string name = benchName(m.key, n);
      if (registered().count(name)) continue;
      const std::string key = m.key;
      registered()[name] = benchmark::RegisterBenchmark(
          name.c_str(), [key, n](benchmark::State& st) { runMethod(st, key, n); });
    }
  std::vector<benchmark::internal::Benchmark*> all;
  for (const auto& [k, b] : registered()) all.push_back(b);
  configureBenchmarks(all, c.minTime, opts.repetitions);
}

BroadPhaseReport measureBroadPhase(const BroadPhaseBenchOptions& opts) {
  registerBroadPhaseBenchmarks(opts);
  struct Release {
    ~Release() { currentScene().reset(); }
  } release;
  facts().clear();
  referenceChecks().clear();
  fclMismatches().clear();
  const Config cfg = config();
  std::string sizes;
  for (std::size_t n : cfg.sizes) sizes += (sizes.empty() ? "" : "|") + std::to_string(n);
  const std::string spec = benchmarkSpec(opts.filter, ("^broadphase/[^/]+/(" + sizes + ")(/|$)").c_str());

  BroadPhaseReport report;
  Collector collector;
  const std::size_t matched = runBenchmarks(spec, opts.googleBenchmarkOutput, collector);
  if (matched == 0) {
    report.table = "nestwalk bench broadphase: no benchmark matches '" + spec + "'\n";
    report.rc = 1;
    return report;
  }
  auto us = [&](const std::string& key, std::size_t n) { return collector.ns(benchName(key, n)) * 1e-3; };
  auto factsOf = [&](const std::string& key, std::size_t n) -> const Facts* {
    const auto it = facts().find(benchName(key, n));
    return it == facts().end() ? nullptr : &it->second;
  };

  bool disagree = false;
  for (const auto& [k, f] : facts()) disagree = disagree || f.disagreements > 0;
  for (const auto& [n, c] : referenceChecks()) disagree = disagree || c.differ > 0;

  // Targets: >= 2x faster than btDbvt with the default hierarchy at every size; 1M build < 1 s.
  for (std::size_t n : cfg.sizes) {
    const double v = us(kBullet, n) / us(kDefaultTree, n);
    if (!std::isnan(v))
      report.targets.push_back({"query_vs_btdbvt/" + std::to_string(n), "btDbvt / nestwalk d=8 >= 2", v, v >= 2.0});
    if (n >= 1000000) {
      const Facts* f = factsOf(kDefaultTree, n);
      if (f && !std::isnan(f->buildSeconds))
        report.targets.push_back({"build_s/" + std::to_string(n), "nestwalk d=8 build < 1 s", f->buildSeconds,
                                  f->buildSeconds < 1.0});
    }
  }
  report.rc = (collector.errors.empty() && !disagree) ? 0 : 1;

  // JSON.
  Json j;
  Json list = Json::array();
  for (std::size_t n : cfg.sizes)
    for (const MethodDef& m : kMethods) {
      const Facts* f = factsOf(m.key, n);
      const double u = us(m.key, n);
      if (!f && std::isnan(u)) continue;
      Json b;
      b["name"] = benchName(m.key, n);
      b["method"] = m.label;
      b["boxes"] = n;
      b["us_per_query"] = jsonNumber(u);
      if (m.degree > 0) {
        b["ratio_btdbvt"] = jsonNumber(us(kBullet, n) / u);
        b["ratio_fcl"] = jsonNumber(us(kFcl, n) / u);
      }
      b["hits"] = f ? Json(f->hits) : Json(nullptr);
      b["queries_differing_from_nestwalk"] = f && f->disagreements >= 0 ? Json(f->disagreements) : Json(nullptr);
      b["build_s"] = jsonNumber(f ? f->buildSeconds : kNaN);
      if (m.degree > 0 && f) {
        b["depth"] = f->depth;
        b["node_tests_per_query"] = jsonNumber(f->nodeTests);
        b["leaf_tests_per_query"] = jsonNumber(f->leafTests);
      }
      list.push_back(b);
    }
  j["benchmarks"] = list;
  Json checks = Json::array();
  for (const auto& [n, c] : referenceChecks())
    checks.push_back({{"boxes", n}, {"queries", c.queries}, {"differing", c.differ}});
  j["brute_force_check"] = checks;
  Json mism;
  for (const auto& [n, c] : fclMismatches()) mism[std::to_string(n)] = c;
  j["fcl_aabb_mismatches"] = mism;
  Json mach;
  mach["cpu_model"] = cpuModelName();
  mach["num_cpus"] = benchmark::CPUInfo::Get().num_cpus;
  mach["queries"] = cfg.queries;
  mach["min_time_s"] = cfg.minTime;
  mach["quick"] = opts.quick;
  mach["repetitions"] = collector.repetitions();
#ifdef NDEBUG
  mach["ndebug"] = true;
#else
  mach["ndebug"] = false;
#endif
  mach["libraries"] = {{"bullet", std::to_string(BT_BULLET_VERSION) + (sizeof(btScalar) == 8 ? " (double)" : " (float)")},
                       {"fcl", FCL_VERSION}};
  j["machine"] = mach;
  j["targets"] = targetsJson(report.targets);
  addErrors(j, collector);
  report.json = j;

  // Table.
  std::ostringstream t;
  t << "nestwalk bench broadphase: µs per query (CPU time); ratio = peer µs / nestwalk µs (> 1: nestwalk faster)\n";
  t << "cpu: " << cpuModelName() << ", " << benchmark::CPUInfo::Get().num_cpus << " CPUs"
#ifndef NDEBUG
    << "; ASSERTIONS ON (not a release build)"
#endif
    << "\n";
  t << "boxes over " << kArea / 1000 << " x " << kArea / 1000 << " km, base z 0-" << kBaseZMax
    << " m (poles, cabinets, containers); " << cfg.queries << " swept viewer boxes along walks of " << kWalkSteps
    << " steps; min time " << cfg.minTime << " s" << (opts.quick ? " (quick)" : "") << "\n";
  t << "peers: Bullet " << BT_BULLET_VERSION << " btDbvt (insert, collideTV); FCL " << FCL_VERSION
    << " DynamicAABBTreeCollisionManager (registerObjects + setup, collide with a recording callback)\n\n";
  t << std::left << std::setw(9) << "boxes" << std::setw(30) << "hierarchy" << std::right << std::setw(10)
    << "nestwalk" << std::setw(10) << "btDbvt" << std::setw(8) << "ratio" << std::setw(10) << "FCL" << std::setw(8)
    << "ratio" << std::setw(12) << "hits" << std::setw(8) << "differ" << std::setw(7) << "depth" << std::setw(9)
    << "nodeT/q" << std::setw(9) << "leafT/q" << "\n";
  for (std::size_t n : cfg.sizes) {
    const double b = us(kBullet, n), f = us(kFcl, n);
    for (const MethodDef& m : kMethods) {
      if (m.degree == 0) continue;
      const double u = us(m.key, n);
      const Facts* fa = factsOf(m.key, n);
      if (std::isnan(u) && !fa) continue;
      t << std::left << std::setw(9) << n << std::setw(30) << m.label << std::right << std::setw(10) << fixedText(u, 3)
        << std::setw(10) << fixedText(b, 3) << std::setw(8) << fixedText(b / u, 2) << std::setw(10) << fixedText(f, 3) << std::setw(8)
        << fixedText(f / u, 2) << std::setw(12) << (fa ? fmtInt(fa->hits) : "-") << std::setw(8)
        << (fa ? std::to_string(fa->disagreements) : "-") << std::setw(7) << (fa ? fa->depth : 0) << std::setw(9)
        << fixedText(fa ? fa->nodeTests : kNaN, 1) << std::setw(9) << fixedText(fa ? fa->leafTests : kNaN, 1) << "\n";
    }
    for (const char* peer : {kBullet, kFcl}) {
      const Facts* fa = factsOf(peer, n);
      if (!fa) continue;
      t << std::left << std::setw(9) << n << std::setw(30) << method(peer).label << std::right << std::setw(10) << "-"
        << std::setw(10) << fixedText(us(peer, n), 3) << std::setw(8) << "" << std::setw(10) << "" << std::setw(8) << ""
        << std::setw(12) << fmtInt(fa->hits) << std::setw(8) << fa->disagreements << "\n";
    }
  }
  t << "(hits: total over all queries; differ: queries whose hit set differs from nestwalk d=8's; depth: levels of\n"
       " inner nodes; nodeT/q, leafT/q: inner-node and unit box tests per query, the BV counts of fACT's Table 2)\n";
  t << "brute-force check of nestwalk d=8:";
  for (const auto& [n, c] : referenceChecks()) t << " n=" << n << " " << c.differ << "/" << c.queries << " differ;";
  t << " FCL AABBs different from the boxes:";
  for (const auto& [n, c] : fclMismatches()) t << " n=" << n << " " << c << ";";
  t << "\n\nbuild times (s, CPU time of the building thread):\n" << std::left << std::setw(9) << "boxes";
  for (const MethodDef& m : kMethods) t << std::right << std::setw(13) << m.column;
  t << "\n";
  for (std::size_t n : cfg.sizes) {
    t << std::left << std::setw(9) << n;
    for (const MethodDef& m : kMethods) {
      const Facts* fa = factsOf(m.key, n);
      t << std::right << std::setw(13) << fixedText(fa ? fa->buildSeconds : kNaN, 3);
    }
    t << "\n";
  }
  t << "(nestwalk: buildAuto; btDbvt: one insert per box; FCL: creating the objects + registerObjects + setup)\n";
  {
    std::ostringstream tt;
    printTargets(tt, report.targets, 28, 30);
    t << tt.str();
  }
  for (const auto& [k, v] : collector.errors) t << "error: " << k << ": " << v << "\n";
  report.table = t.str();
  return report;
}

int runBroadPhaseBench(const BroadPhaseBenchOptions& opts, std::ostream& out) {
  const BroadPhaseReport r = measureBroadPhase(opts);
  if (opts.json && !r.json.is_null()) out << r.json.dump(2) << "\n";
  else out << r.table;
  return r.rc;
}

}  // namespace nestwalk::bench
