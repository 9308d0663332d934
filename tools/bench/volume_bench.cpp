// The bounding-volume benchmark (see volume_bench.h).
//
// Every benchmark iterates over the whole pair array once per Google Benchmark iteration and sums
// its verdicts (benchmark::DoNotOptimize on the sum), with SetItemsProcessed(iterations * pairs), so
// ns/op = 1e9 / items_per_second. Data sets are generated once from fixed seeds (splitmix64, own
// uniform/Gaussian transforms: the same boxes on every platform) and kept while the benchmarks of
// one set run; each peer's layout (fcl::OBB, btTransform, ...) is built before its timed loop.
// Verdict fractions and disagreements with satObbObb<double> are counted once per benchmark,
// outside the timed loop.
#include "tools/bench/volume_bench.h"

#include "tools/bench/bench_runner.h"

#include "nestwalk/geometry/nested.h"
#include "nestwalk/geometry/obb_batch.h"
#include "nestwalk/geometry/sat.h"

#include <benchmark/benchmark.h>
#include <ccd/ccd.h>
#include <fcl/config.h>
#include <fcl/math/bv/AABB.h>
#include <fcl/math/bv/OBB.h>
#include <nlohmann/json.hpp>

#include <BulletCollision/CollisionDispatch/btBoxBoxDetector.h>
#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <LinearMath/btTransform.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <ostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace nestwalk::bench {
namespace {

// ------------------------------------------------------------------------------------------------
// Configuration and deterministic random numbers.

struct Config {
  std::size_t pairs = 1'000'000;
  std::size_t stored = 1'000'000;
  double minTime = 0.5;
};

Config& config() {
  static Config c;
  return c;
}

/// splitmix64 (bench_runner.h) with random directions and rotations.
class Rng : public SplitMix64 {
 public:
  using SplitMix64::SplitMix64;
  Vec3<double> direction() {
    for (;;) {
      const Vec3<double> g(gaussian(), gaussian(), gaussian());
      const double n = g.norm();
      if (n > 1e-9) return g / n;
    }
  }
  Mat3<double> rotation() {  // uniform on SO(3): normalized Gaussian quaternion
    for (;;) {
      Eigen::Quaterniond q(gaussian(), gaussian(), gaussian(), gaussian());
      const double n = q.norm();
      if (n > 1e-9) {
        q.coeffs() /= n;
        return q.toRotationMatrix();
      }
    }
  }
};

// Box sizes: half extents log-uniform in [0.1, 2] (poles, panels and blocks of equipment, metres).
constexpr double kMinHalf = 0.1, kMaxHalf = 2.0;

Obb<double> randomBox(Rng& rng, const Vec3<double>& center) {
  Obb<double> b;
  b.center = center;
  b.axes = rng.rotation();
  for (int k = 0; k < 3; ++k) b.halfExtents[k] = std::exp(rng.uniform(std::log(kMinHalf), std::log(kMaxHalf)));
  return b;
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
using Json = nlohmann::ordered_json;

// ------------------------------------------------------------------------------------------------
// Pair sets: n pairs at a wanted OBB-OBB overlap fraction.

struct PairSetSpec {
  const char* key;    // "overlap_50pct"
  const char* label;  // "50%"
  double target;
  std::uint64_t seed;
};
constexpr PairSetSpec kPairSets[] = {
    {"overlap_50pct", "50%", 0.50, 0x6e657374'00000050ull},
    {"overlap_5pct", "5%", 0.05, 0x6e657374'00000005ull},
};

struct BulletPairs {
  std::vector<btTransform> ta, tb;
  std::vector<btVector3> ha, hb;
};

struct PairSet {
  const PairSetSpec* spec = nullptr;
  std::size_t n = 0;
  double scale = 0;            // the centre-distance scale found for the target
  double overlapFraction = 0;  // measured with satObbObb<double> over all n pairs
  std::vector<Obb<double>> a, b;
  std::vector<std::uint8_t> reference;  // satObbObb<double> verdicts

  // Layouts, built on first use.
  std::vector<Obb<float>> af, bf;
  std::vector<Aabb<double>> xa, xb;
  std::vector<Aabb<float>> xaf, xbf;
  std::vector<NestedVolume<double>> na, nb;
  std::unique_ptr<ObbPairBatch> batch;
  std::vector<fcl::OBB<double>> fa, fb;
  std::unique_ptr<BulletPairs> bullet;
};

// The pair geometry: box A at a random point, box B at A's centre + dir * u * scale with u uniform
// in [0, 1). For fixed boxes and direction the overlapping centre offsets form a convex set around
// 0 (A minus B), so the overlap count is non-increasing in scale and bisection finds the scale.
std::unique_ptr<PairSet> makePairSet(const PairSetSpec& spec, std::size_t n) {
  auto set = std::make_unique<PairSet>();
  set->spec = &spec;
  set->n = n;
  Rng rng(spec.seed);
  set->a.resize(n);
  set->b.resize(n);
  std::vector<Vec3<double>> offset(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3<double> c(rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-10, 10));
    set->a[k] = randomBox(rng, c);
    set->b[k] = randomBox(rng, c);
    offset[k] = rng.direction() * rng.uniform();
  }
  const std::size_t m = std::min<std::size_t>(n, 100'000);  // calibration sample
  auto fractionAt = [&](double scale) {
    std::size_t hits = 0;
    for (std::size_t k = 0; k < m; ++k) {
      Obb<double> b = set->b[k];
      b.center = set->a[k].center + scale * offset[k];
      hits += satObbObb(set->a[k], b).overlap ? 1 : 0;
    }
    return double(hits) / double(m);
  };
  double lo = 0, hi = 1;
  while (fractionAt(hi) > spec.target && hi < 1e6) hi *= 2;
  for (int it = 0; it < 50; ++it) {
    const double mid = 0.5 * (lo + hi);
    (fractionAt(mid) > spec.target ? lo : hi) = mid;
  }
  set->scale = 0.5 * (lo + hi);
  set->reference.resize(n);
  std::size_t hits = 0;
  for (std::size_t k = 0; k < n; ++k) {
    set->b[k].center = set->a[k].center + set->scale * offset[k];
    set->reference[k] = satObbObb(set->a[k], set->b[k]).overlap ? 1 : 0;
    hits += set->reference[k];
  }
  set->overlapFraction = double(hits) / double(n);
  return set;
}

std::unique_ptr<PairSet>& currentPairSet() {
  static std::unique_ptr<PairSet> s;
  return s;
}

void releaseQuerySet();

/// The set of `spec` at the configured size; only one pair set is kept at a time (the benchmarks of
/// a set are registered together).
PairSet& pairSet(const PairSetSpec& spec) {
  std::unique_ptr<PairSet>& s = currentPairSet();
  if (!s || s->spec != &spec || s->n != config().pairs) {
    s.reset();
    releaseQuerySet();
    s = makePairSet(spec, config().pairs);
  }
  return *s;
}

// Layout builders.
void needFloat(PairSet& s) {
  if (!s.af.empty()) return;
  s.af.reserve(s.n);
  s.bf.reserve(s.n);
  for (std::size_t k = 0; k < s.n; ++k) {
    s.af.push_back(s.a[k].cast<float>());
    s.bf.push_back(s.b[k].cast<float>());
  }
}
void needAabb(PairSet& s) {
  if (!s.xa.empty()) return;
  s.xa.reserve(s.n);
  s.xb.reserve(s.n);
  s.xaf.reserve(s.n);
  s.xbf.reserve(s.n);
  for (std::size_t k = 0; k < s.n; ++k) {
    s.xa.push_back(aabbOf(s.a[k]));
    s.xb.push_back(aabbOf(s.b[k]));
    s.xaf.push_back(toFloatConservative(s.xa.back()));
    s.xbf.push_back(toFloatConservative(s.xb.back()));
  }
}
void needNested(PairSet& s) {
  if (!s.na.empty()) return;
  s.na.reserve(s.n);
  s.nb.reserve(s.n);
  for (std::size_t k = 0; k < s.n; ++k) {
    s.na.push_back(NestedVolume<double>::fromObb(s.a[k]));
    s.nb.push_back(NestedVolume<double>::fromObb(s.b[k]));
  }
}
void needBatch(PairSet& s) {
  if (s.batch) return;
  std::vector<std::pair<Obb<double>, Obb<double>>> pairs(s.n);
  for (std::size_t k = 0; k < s.n; ++k) pairs[k] = {s.a[k], s.b[k]};
  s.batch = std::make_unique<ObbPairBatch>(pairs);
}
fcl::OBB<double> toFcl(const Obb<double>& b) {
  fcl::OBB<double> f;
  f.axis = b.axes;
  f.To = b.center;
  f.extent = b.halfExtents;
  return f;
}
void needFcl(PairSet& s) {
  if (!s.fa.empty()) return;
  s.fa.reserve(s.n);
  s.fb.reserve(s.n);
  for (std::size_t k = 0; k < s.n; ++k) {
    s.fa.push_back(toFcl(s.a[k]));
    s.fb.push_back(toFcl(s.b[k]));
  }
}
btTransform toBullet(const Obb<double>& b) {
  const Mat3<double>& r = b.axes;  // btMatrix3x3 is row-major; its columns are the box axes
  const btMatrix3x3 basis(btScalar(r(0, 0)), btScalar(r(0, 1)), btScalar(r(0, 2)),  //
                          btScalar(r(1, 0)), btScalar(r(1, 1)), btScalar(r(1, 2)),  //
                          btScalar(r(2, 0)), btScalar(r(2, 1)), btScalar(r(2, 2)));
  return btTransform(basis, btVector3(btScalar(b.center.x()), btScalar(b.center.y()), btScalar(b.center.z())));
}
btVector3 toBulletVec(const Vec3<double>& v) { return btVector3(btScalar(v.x()), btScalar(v.y()), btScalar(v.z())); }
void needBullet(PairSet& s) {
  if (s.bullet) return;
  auto p = std::make_unique<BulletPairs>();
  p->ta.reserve(s.n);
  p->tb.reserve(s.n);
  p->ha.reserve(s.n);
  p->hb.reserve(s.n);
  for (std::size_t k = 0; k < s.n; ++k) {
    p->ta.push_back(toBullet(s.a[k]));
    p->tb.push_back(toBullet(s.b[k]));
    p->ha.push_back(toBulletVec(s.a[k].halfExtents));
    p->hb.push_back(toBulletVec(s.b[k].halfExtents));
  }
  s.bullet = std::move(p);
}

// ------------------------------------------------------------------------------------------------
// Peers' single-pair tests.

// libccd: the object is a nestwalk::Obb<double>; support point of a box in direction d.
void ccdObbSupport(const void* obj, const ccd_vec3_t* dir, ccd_vec3_t* out) {
  const Obb<double>& b = *static_cast<const Obb<double>*>(obj);
  const Vec3<double> d(dir->v[0], dir->v[1], dir->v[2]);
  Vec3<double> p = b.center;
  for (int k = 0; k < 3; ++k) {
    const double s = b.axes.col(k).dot(d) >= 0 ? b.halfExtents[k] : -b.halfExtents[k];
    p += s * b.axes.col(k);
  }
  out->v[0] = p.x();
  out->v[1] = p.y();
  out->v[2] = p.z();
}
void ccdObbCenter(const void* obj, ccd_vec3_t* c) {
  const Obb<double>& b = *static_cast<const Obb<double>*>(obj);
  c->v[0] = b.center.x();
  c->v[1] = b.center.y();
  c->v[2] = b.center.z();
}
ccd_t makeCcd() {
  ccd_t c;
  CCD_INIT(&c);
  c.support1 = ccdObbSupport;
  c.support2 = ccdObbSupport;
  c.center1 = ccdObbCenter;
  c.center2 = ccdObbCenter;
  c.max_iterations = 500;  // FCL's libccd setting; MPR converges in far fewer on boxes
  c.mpr_tolerance = 1e-6;
  return c;
}

// Bullet: btBoxBoxDetector reports contact points only for penetrating boxes (it returns at the first
// separating axis); this result records whether any point was added.
struct OverlapOnlyResult : btDiscreteCollisionDetectorInterface::Result {
  bool hit = false;
  void setShapeIdentifiersA(int, int) override {}
  void setShapeIdentifiersB(int, int) override {}
  void addContactPoint(const btVector3&, const btVector3&, btScalar) override { hit = true; }
};

/// Two reusable btBoxShapes (margin 0, so the half extents are the box's) whose dimensions are set
/// per pair: the detector reads only the half extents from the shapes.
struct BulletTester {
  btBoxShape sa{btVector3(1, 1, 1)}, sb{btVector3(1, 1, 1)};
  btBoxBoxDetector detector{&sa, &sb};
  btDiscreteCollisionDetectorInterface::ClosestPointInput input;
  OverlapOnlyResult result;
  BulletTester() {
    sa.setMargin(0);
    sb.setMargin(0);
    input.m_maximumDistanceSquared = 0;
  }
  bool test(const BulletPairs& p, std::size_t k) {
    sa.setImplicitShapeDimensions(p.ha[k]);
    sb.setImplicitShapeDimensions(p.hb[k]);
    input.m_transformA = p.ta[k];
    input.m_transformB = p.tb[k];
    result.hit = false;
    detector.getClosestPoints(input, result, nullptr);
    return result.hit;
  }
};

// ------------------------------------------------------------------------------------------------
// One-vs-many sets: one viewer against n stored boxes.

struct QuerySetSpec {
  const char* key;    // "survive_1pct"
  const char* label;  // "1%"
  double target;      // wanted fraction of stored boxes surviving stage 1 (AABB-AABB)
  std::uint64_t seed;
};
constexpr QuerySetSpec kQuerySets[] = {
    {"survive_1pct", "1% s1", 0.01, 0x6e657374'00001001ull},
    {"survive_10pct", "10% s1", 0.10, 0x6e657374'00001010ull},
};

struct QuerySet {
  const QuerySetSpec* spec = nullptr;
  std::size_t n = 0;
  std::vector<NestedVolume<double>> boxes;
  NestedVolume<double> viewer;
  double stage1Exact = 0;  // fraction of exact (double) outer boxes meeting the viewer's outer box
  double stage1Engine = 0;  // stage-2 tests / n as counted by queryOverlaps (float prefilter)
  double hitFraction = 0;
  std::vector<std::uint8_t> reference;  // testNested<double> verdicts
  std::unique_ptr<NestedBoxSet> set;
  std::vector<fcl::AABB<double>> faabb;
  std::vector<fcl::OBB<double>> fobb;
};

std::unique_ptr<QuerySet>& currentQuerySet() {
  static std::unique_ptr<QuerySet> s;
  return s;
}
void releaseQuerySet() { currentQuerySet().reset(); }

// Stored boxes: centres uniform in a cube of side 200 * cbrt(n / 1M) (one box per 8 m^3), sizes and
// rotations as for the pairs. The viewer: a randomly rotated box at the origin with half extents
// s * (1, 0.7, 0.4), s bisected so that the wanted fraction of outer boxes meet its outer box.
std::unique_ptr<QuerySet> makeQuerySet(const QuerySetSpec& spec, std::size_t n) {
  auto q = std::make_unique<QuerySet>();
  q->spec = &spec;
  q->n = n;
  Rng rng(spec.seed);
  const double half = 100.0 * std::cbrt(double(n) / 1e6);
  q->boxes.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3<double> c(rng.uniform(-half, half), rng.uniform(-half, half), rng.uniform(-half, half));
    q->boxes.push_back(NestedVolume<double>::fromObb(randomBox(rng, c)));
  }
  Obb<double> v;
  v.axes = rng.rotation();
  const Vec3<double> shape(1.0, 0.7, 0.4);
  auto viewerAt = [&](double s) {
    Obb<double> b = v;
    b.halfExtents = s * shape;
    return NestedVolume<double>::fromObb(b);
  };
  auto stage1At = [&](double s) {
    const Aabb<double> outer = viewerAt(s).outer;
    std::size_t c = 0;
    for (const auto& b : q->boxes) c += satAabbAabb(outer, b.outer).overlap ? 1 : 0;
    return double(c) / double(n);
  };
  double lo = 0, hi = 2 * half;
  for (int it = 0; it < 40; ++it) {
    const double mid = 0.5 * (lo + hi);
    (stage1At(mid) < spec.target ? lo : hi) = mid;
  }
  q->viewer = viewerAt(0.5 * (lo + hi));
  q->stage1Exact = stage1At(0.5 * (lo + hi));
  q->reference.resize(n);
  std::size_t hits = 0;
  for (std::size_t k = 0; k < n; ++k) {
    q->reference[k] = testNested(q->viewer, q->boxes[k]).overlap ? 1 : 0;
    hits += q->reference[k];
  }
  q->hitFraction = double(hits) / double(n);
  return q;
}

QuerySet& querySet(const QuerySetSpec& spec) {
  std::unique_ptr<QuerySet>& q = currentQuerySet();
  if (!q || q->spec != &spec || q->n != config().stored) {
    q.reset();
    currentPairSet().reset();
    q = makeQuerySet(spec, config().stored);
  }
  return *q;
}

void needEngineSet(QuerySet& q) {
  if (q.set) return;
  q.set = std::make_unique<NestedBoxSet>(q.boxes);
  StageCounters counters;
  std::vector<std::uint32_t> hits;
  q.set->queryOverlaps(q.viewer, hits, &counters);
  q.stage1Engine = double(counters.tests[1]) / double(q.n);
}
void needFclQuery(QuerySet& q) {
  if (!q.fobb.empty()) return;
  q.faabb.reserve(q.n);
  q.fobb.reserve(q.n);
  for (const auto& b : q.boxes) {
    q.faabb.emplace_back(b.outer.min, b.outer.max);
    q.fobb.push_back(toFcl(b.inner));
  }
}

// ------------------------------------------------------------------------------------------------
// Facts per benchmark, counted once outside the timed loops (reset by runVolumeBench).

struct Facts {
  double setFraction = kNaN;      // the set's defining fraction (OBB overlap, or stage-1 survival)
  double verdictFraction = kNaN;  // fraction of "overlap" answers of this benchmark's test
  long long disagreements = -1;   // answers that differ from satObbObb<double> (-1: not compared)
  double uncertainFraction = kNaN;  // ObbPairBatch: lanes re-decided in double
  double hitFraction = kNaN;        // queries: final overlap fraction
};

std::map<std::string, Facts>& facts() {
  static std::map<std::string, Facts> f;
  return f;
}

/// Counts the verdicts of `verdict(k)` against `reference` (null: no comparison).
template <class F>
Facts countVerdicts(std::size_t n, const std::vector<std::uint8_t>* reference, F&& verdict) {
  Facts f;
  std::size_t hits = 0, differ = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const bool v = verdict(k);
    hits += v ? 1 : 0;
    if (reference) differ += (v != ((*reference)[k] != 0)) ? 1 : 0;
  }
  f.verdictFraction = double(hits) / double(n);
  if (reference) f.disagreements = static_cast<long long>(differ);
  return f;
}

void publish(benchmark::State& state, const Facts& f, std::size_t items) {
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(items));
  // Seconds per item, shown by the console reporter as e.g. "5.2ns".
  state.counters["time_per_op"] =
      benchmark::Counter(double(items), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  if (!std::isnan(f.setFraction)) state.counters["overlap_fraction"] = f.setFraction;
  if (!std::isnan(f.verdictFraction)) state.counters["verdict_fraction"] = f.verdictFraction;
  if (f.disagreements >= 0) state.counters["disagreements"] = double(f.disagreements);
  if (!std::isnan(f.uncertainFraction)) state.counters["uncertain_fraction"] = f.uncertainFraction;
  if (!std::isnan(f.hitFraction)) state.counters["hit_fraction"] = f.hitFraction;
}

/// The timed loop over all pairs: one pass per iteration, verdicts summed.
template <class F>
void timePairs(benchmark::State& state, std::size_t n, F&& verdict) {
  for (auto _ : state) {
    std::size_t hits = 0;
    for (std::size_t k = 0; k < n; ++k) hits += verdict(k) ? 1 : 0;
    benchmark::DoNotOptimize(hits);
  }
}

/// Runs `build` once per benchmark name (the facts of the benchmark), then the timed loop.
template <class Prepare, class F>
void pairBenchmark(benchmark::State& state, const std::string& name, const PairSetSpec& spec, Prepare&& prepare,
                   bool compare, F&& verdict) {
  PairSet& s = pairSet(spec);
  prepare(s);
  auto& cache = facts();
  auto it = cache.find(name);
  if (it == cache.end()) {
    Facts f = countVerdicts(s.n, compare ? &s.reference : nullptr, [&](std::size_t k) { return verdict(s, k); });
    f.setFraction = s.overlapFraction;
    it = cache.emplace(name, f).first;
  }
  timePairs(state, s.n, [&](std::size_t k) { return verdict(s, k); });
  publish(state, it->second, s.n);
}

// ------------------------------------------------------------------------------------------------
// Registration.

/// ObbPairBatch picks its kernel on every call: AVX2 + FMA where the processor has them, unless
/// NESTWALK_SIMD=portable (engine/geometry/obb_batch.cpp). This forces the portable kernel for one
/// benchmark and restores the environment afterwards.
class SimdOverride {
 public:
  explicit SimdOverride(bool portable) : active_(portable) {
    if (!active_) return;
    if (const char* v = std::getenv("NESTWALK_SIMD")) saved_ = v;
    ::setenv("NESTWALK_SIMD", "portable", 1);
  }
  ~SimdOverride() {
    if (!active_) return;
    if (saved_)
      ::setenv("NESTWALK_SIMD", saved_->c_str(), 1);
    else
      ::unsetenv("NESTWALK_SIMD");
  }
  SimdOverride(const SimdOverride&) = delete;
  SimdOverride& operator=(const SimdOverride&) = delete;

 private:
  bool active_;
  std::optional<std::string> saved_;
};

/// The kernel ObbPairBatch uses here, by the same rule as obb_batch.cpp.
std::string batchKernel() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_cpu_init();
  const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  const char* env = std::getenv("NESTWALK_SIMD");
  if (avx2 && !(env && std::strcmp(env, "portable") == 0)) return "avx2+fma (8 lanes, chosen at run time)";
#endif
  return "portable (SSE, 4 lanes)";
}

std::string benchName(const char* test, const char* set) { return std::string("volumes/") + test + "/" + set; }

std::vector<benchmark::internal::Benchmark*>& registered() {
  static std::vector<benchmark::internal::Benchmark*> r;
  return r;
}

void registerPairBenchmarks(const PairSetSpec& spec) {
  auto add = [&](const char* test, auto&& fn) {
    const std::string name = benchName(test, spec.key);
    registered().push_back(
        benchmark::RegisterBenchmark(name.c_str(), [name, fn](benchmark::State& st) { fn(st, name); }));
  };
  const PairSetSpec* sp = &spec;
  add("aabb_aabb_double", [sp](benchmark::State& st, const std::string& name) {
    pairBenchmark(st, name, *sp, needAabb, false,
                  [](const PairSet& s, std::size_t k) { return satAabbAabb(s.xa[k], s.xb[k]).overlap; });
  });
  add("aabb_aabb_float", [sp](benchmark::State& st, const std::string& name) {
    pairBenchmark(st, name, *sp, needAabb, false,
                  [](const PairSet& s, std::size_t k) { return satAabbAabb(s.xaf[k], s.xbf[k]).overlap; });
  });
  add("aabb_obb_double", [sp](benchmark::State& st, const std::string& name) {
    pairBenchmark(st, name, *sp, needAabb, false,
                  [](const PairSet& s, std::size_t k) { return satAabbObb(s.xa[k], s.b[k]).overlap; });
  });
  add("obb_obb_double", [sp](benchmark::State& st, const std::string& name) {
    pairBenchmark(st, name, *sp, [](PairSet&) {}, true,
                  [](const PairSet& s, std::size_t k) { return satObbObb(s.a[k], s.b[k]).overlap; });
  });
  add("obb_obb_float", [sp](benchmark::State& st, const std::string& name) {
    pairBenchmark(st, name, *sp, needFloat, true,
                  [](const PairSet& s, std::size_t k) { return satObbObb(s.af[k], s.bf[k]).overlap; });
  });
  auto batchBenchmark = [sp](benchmark::State& st, const std::string& name, bool portable) {
    const SimdOverride simd(portable);
    PairSet& s = pairSet(*sp);
    needBatch(s);
    std::vector<std::uint8_t> out(s.n);
    auto& cache = facts();
    auto it = cache.find(name);
    if (it == cache.end()) {
      const std::size_t uncertain = s.batch->test(out.data());
      Facts f = countVerdicts(s.n, &s.reference, [&](std::size_t k) { return out[k] != 0; });
      f.setFraction = s.overlapFraction;
      f.uncertainFraction = double(uncertain) / double(s.n);
      it = cache.emplace(name, f).first;
    }
    for (auto _ : st) {
      std::size_t uncertain = s.batch->test(out.data());
      benchmark::DoNotOptimize(uncertain);
      benchmark::DoNotOptimize(out.data());
      benchmark::ClobberMemory();
    }
    publish(st, it->second, s.n);
  };
  add("obb_obb_batch",
      [batchBenchmark](benchmark::State& st, const std::string& name) { batchBenchmark(st, name, false); });
  add("obb_obb_batch_portable",
      [batchBenchmark](benchmark::State& st, const std::string& name) { batchBenchmark(st, name, true); });
  add("nested_double", [sp](benchmark::State& st, const std::string& name) {
    pairBenchmark(st, name, *sp, needNested, true,
                  [](const PairSet& s, std::size_t k) { return testNested(s.na[k], s.nb[k]).overlap; });
  });
  add("peer_fcl_obb", [sp](benchmark::State& st, const std::string& name) {
    pairBenchmark(st, name, *sp, needFcl, true,
                  [](const PairSet& s, std::size_t k) { return s.fa[k].overlap(s.fb[k]); });
  });
  add("peer_ccd_mpr", [sp](benchmark::State& st, const std::string& name) {
    const ccd_t ccd = makeCcd();
    pairBenchmark(st, name, *sp, [](PairSet&) {}, true, [&ccd](const PairSet& s, std::size_t k) {
      return ccdMPRIntersect(&s.a[k], &s.b[k], &ccd) != 0;
    });
  });
  add("peer_bullet_boxbox", [sp](benchmark::State& st, const std::string& name) {
    BulletTester bt;
    pairBenchmark(st, name, *sp, needBullet, true,
                  [&bt](const PairSet& s, std::size_t k) { return bt.test(*s.bullet, k); });
  });
}

void registerQueryBenchmarks(const QuerySetSpec& spec) {
  const QuerySetSpec* sp = &spec;
  {
    const std::string name = benchName("query_nested_set", spec.key);
    registered().push_back(benchmark::RegisterBenchmark(name.c_str(), [sp, name](benchmark::State& st) {
      QuerySet& q = querySet(*sp);
      needEngineSet(q);
      std::vector<std::uint32_t> hits;
      hits.reserve(q.n);
      auto& cache = facts();
      auto it = cache.find(name);
      if (it == cache.end()) {
        q.set->queryOverlaps(q.viewer, hits);
        std::vector<std::uint8_t> got(q.n, 0);
        for (std::uint32_t i : hits) got[i] = 1;
        Facts f = countVerdicts(q.n, &q.reference, [&](std::size_t k) { return got[k] != 0; });
        f.setFraction = q.stage1Engine;
        f.hitFraction = f.verdictFraction;
        it = cache.emplace(name, f).first;
      }
      for (auto _ : st) {
        hits.clear();
        q.set->queryOverlaps(q.viewer, hits);
        benchmark::DoNotOptimize(hits.data());
        benchmark::ClobberMemory();
      }
      publish(st, it->second, q.n);
    }));
  }
  {
    // FCL, the same cascade without the AABB-OBB stage: AABB-AABB, then OBB-OBB on the survivors.
    const std::string name = benchName("peer_fcl_query", spec.key);
    registered().push_back(benchmark::RegisterBenchmark(name.c_str(), [sp, name](benchmark::State& st) {
      QuerySet& q = querySet(*sp);
      needFclQuery(q);
      const fcl::AABB<double> va(q.viewer.outer.min, q.viewer.outer.max);
      const fcl::OBB<double> vo = toFcl(q.viewer.inner);
      auto verdict = [&](std::size_t k) { return q.faabb[k].overlap(va) && vo.overlap(q.fobb[k]); };
      auto& cache = facts();
      auto it = cache.find(name);
      if (it == cache.end()) {
        Facts f = countVerdicts(q.n, &q.reference, verdict);
        f.setFraction = q.stage1Exact;
        f.hitFraction = f.verdictFraction;
        it = cache.emplace(name, f).first;
      }
      timePairs(st, q.n, verdict);
      publish(st, it->second, q.n);
    }));
  }
}

// ------------------------------------------------------------------------------------------------
// The table (the collecting reporter is in bench_runner.h).


struct RowDef {
  const char* key;
  const char* label;
  const char* nestwalk;
  const char* fcl;
  const char* ccd;
  const char* bullet;
};
constexpr RowDef kPairRows[] = {
    {"aabb_aabb_double", "AABB-AABB double", "aabb_aabb_double", nullptr, nullptr, nullptr},
    {"aabb_aabb_float", "AABB-AABB float", "aabb_aabb_float", nullptr, nullptr, nullptr},
    {"aabb_obb_double", "AABB-OBB double", "aabb_obb_double", nullptr, nullptr, nullptr},
    {"obb_obb_double", "OBB-OBB double scalar", "obb_obb_double", "peer_fcl_obb", "peer_ccd_mpr", "peer_bullet_boxbox"},
    {"obb_obb_float", "OBB-OBB float scalar", "obb_obb_float", "peer_fcl_obb", "peer_ccd_mpr", "peer_bullet_boxbox"},
    {"obb_obb_batch", "OBB-OBB batch", "obb_obb_batch", "peer_fcl_obb", "peer_ccd_mpr", "peer_bullet_boxbox"},
    {"obb_obb_batch_portable", "OBB-OBB batch portable", "obb_obb_batch_portable", "peer_fcl_obb", "peer_ccd_mpr",
     "peer_bullet_boxbox"},
    {"nested_double", "nested double (3-stage)", "nested_double", "peer_fcl_obb", "peer_ccd_mpr", "peer_bullet_boxbox"},
};
constexpr RowDef kQueryRows[] = {
    {"query_nested_set", "1-vs-N query /stored box", "query_nested_set", "peer_fcl_query", nullptr, nullptr},
};

constexpr const char* kPeerKeys[] = {"fcl", "ccd_mpr", "bullet"};
constexpr const char* kPeerTitles[] = {"FCL", "ccd MPR", "Bullet"};

struct Row {
  std::string name;  // "obb_obb_batch/overlap_50pct"
  std::string label, set;
  double setFraction = kNaN, verdictFraction = kNaN;
  double nestwalk = kNaN;
  double peer[3] = {kNaN, kNaN, kNaN};
  long long nestwalkDisagreements = -1;
  long long peerDisagreements[3] = {-1, -1, -1};
  double uncertainFraction = kNaN, hitFraction = kNaN;
};

const Facts* factsOf(const std::string& bench) {
  const auto it = facts().find(bench);
  return it == facts().end() ? nullptr : &it->second;
}

Row makeRow(const RowDef& def, const char* setKey, const char* setLabel, const Collector& c) {
  Row r;
  r.name = std::string(def.key) + "/" + setKey;
  r.label = def.label;
  r.set = setLabel;
  const std::string nw = benchName(def.nestwalk, setKey);
  r.nestwalk = c.ns(nw);
  if (const Facts* f = factsOf(nw)) {
    r.setFraction = f->setFraction;
    r.verdictFraction = f->verdictFraction;
    r.nestwalkDisagreements = f->disagreements;
    r.uncertainFraction = f->uncertainFraction;
    r.hitFraction = f->hitFraction;
  }
  const char* peers[3] = {def.fcl, def.ccd, def.bullet};
  for (int p = 0; p < 3; ++p) {
    if (!peers[p]) continue;
    const std::string pb = benchName(peers[p], setKey);
    r.peer[p] = c.ns(pb);
    if (const Facts* f = factsOf(pb)) {
      r.peerDisagreements[p] = f->disagreements;
      if (std::isnan(r.setFraction)) r.setFraction = f->setFraction;
    }
  }
  return r;
}

bool anyMeasured(const Row& r) {
  return !std::isnan(r.nestwalk) || !std::isnan(r.peer[0]) || !std::isnan(r.peer[1]) || !std::isnan(r.peer[2]);
}

// ------------------------------------------------------------------------------------------------
// Machine and build information.


Json machineJson(std::size_t pairs, std::size_t stored, double minTime, bool quick,
                 std::size_t repetitions) {
  const benchmark::CPUInfo& cpu = benchmark::CPUInfo::Get();
  Json m;
  m["cpu_model"] = cpuModelName();
  m["num_cpus"] = cpu.num_cpus;
  m["mhz_per_cpu"] = cpu.cycles_per_second / 1e6;
  m["cpu_scaling"] = cpu.scaling == benchmark::CPUInfo::ENABLED    ? "enabled"
                     : cpu.scaling == benchmark::CPUInfo::DISABLED ? "disabled"
                                                                   : "unknown";
  Json caches = Json::array();
  for (const auto& c : cpu.caches)
    caches.push_back({{"type", c.type}, {"level", c.level}, {"size", c.size}, {"num_sharing", c.num_sharing}});
  m["caches"] = caches;
  m["load_avg"] = cpu.load_avg;
  Json compiled;
#ifdef __SSE4_2__
  compiled["sse4_2"] = true;
#else
  compiled["sse4_2"] = false;
#endif
#ifdef __AVX__
  compiled["avx"] = true;
#else
  compiled["avx"] = false;
#endif
#ifdef __AVX2__
  compiled["avx2"] = true;
#else
  compiled["avx2"] = false;
#endif
#ifdef __FMA__
  compiled["fma"] = true;
#else
  compiled["fma"] = false;
#endif
#ifdef __AVX512F__
  compiled["avx512f"] = true;
#else
  compiled["avx512f"] = false;
#endif
  m["compiled_isa"] = compiled;
  Json supports;
#if defined(__x86_64__) || defined(__i386__)
  __builtin_cpu_init();
  supports["sse4_2"] = bool(__builtin_cpu_supports("sse4.2"));
  supports["avx"] = bool(__builtin_cpu_supports("avx"));
  supports["avx2"] = bool(__builtin_cpu_supports("avx2"));
  supports["fma"] = bool(__builtin_cpu_supports("fma"));
  supports["avx512f"] = bool(__builtin_cpu_supports("avx512f"));
#endif
  m["cpu_supports"] = supports;
  m["batch_kernel"] = batchKernel();
#ifdef __VERSION__
  m["compiler"] = __VERSION__;
#endif
#ifdef NDEBUG
  m["ndebug"] = true;
#else
  m["ndebug"] = false;
#endif
  m["libraries"] = {
      {"eigen", std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) + "." +
                    std::to_string(EIGEN_MINOR_VERSION)},
      {"fcl", FCL_VERSION},
      {"ccd", sizeof(ccd_real_t) == 8 ? "double" : "float"},
      {"bullet",
       std::to_string(BT_BULLET_VERSION) + (sizeof(btScalar) == 8 ? " (btScalar double)" : " (btScalar float)")},
  };
  m["pairs_per_set"] = pairs;
  m["stored_boxes"] = stored;
  m["min_time_s"] = minTime;
  m["quick"] = quick;
  m["repetitions"] = repetitions;
  return m;
}

std::string isaLine(const Json& m) {
  std::ostringstream s;
  auto flags = [&](const Json& j) {
    std::string out;
    for (const char* k : {"sse4_2", "avx", "avx2", "fma", "avx512f"})
      if (j.contains(k) && j[k].get<bool>()) out += std::string(out.empty() ? "" : " ") + k;
    return out.empty() ? std::string("-") : out;
  };
  s << "compiled for: " << flags(m["compiled_isa"]) << "; CPU supports: " << flags(m["cpu_supports"])
    << " (AVX2 " << (m["compiled_isa"]["avx2"].get<bool>() ? "compiled in" : "not compiled in")
    << (m["cpu_supports"].value("avx2", false) ? ", available at run time" : ", not available at run time") << ")";
  return s.str();
}



}  // namespace

// ------------------------------------------------------------------------------------------------

void registerVolumeBenchmarks(const VolumeBenchOptions& opts) {
  Config& c = config();
  c.pairs = opts.pairs ? opts.pairs : (opts.quick ? 20'000 : 1'000'000);
  c.stored = opts.storedBoxes ? opts.storedBoxes : c.pairs;
  c.minTime = opts.minTimeSeconds > 0 ? opts.minTimeSeconds : (opts.quick ? 0.02 : 0.5);
  if (registered().empty()) {
    for (const auto& s : kPairSets) registerPairBenchmarks(s);
    for (const auto& s : kQuerySets) registerQueryBenchmarks(s);
  }
  configureBenchmarks(registered(), c.minTime, opts.repetitions);
}

int runVolumeBench(const VolumeBenchOptions& opts, std::ostream& out) {
  registerVolumeBenchmarks(opts);
  facts().clear();
  const Config cfg = config();

  const std::string spec = benchmarkSpec(opts.filter, "^volumes/");

  Collector collector;
  const std::size_t matched = runBenchmarks(spec, opts.googleBenchmarkOutput, collector);
  // Free the data sets (up to a few GB at 1M pairs).
  currentPairSet().reset();
  currentQuerySet().reset();
  if (matched == 0) {
    out << "nestwalk bench volumes: no benchmark matches '" << spec << "'\n";
    return 1;
  }
  if (collector.samples.empty() && collector.errors.empty()) return 0;  // --benchmark_list_tests

  std::vector<Row> rows;
  for (const auto& s : kPairSets)
    for (const auto& d : kPairRows) {
      Row r = makeRow(d, s.key, s.label, collector);
      if (anyMeasured(r)) rows.push_back(r);
    }
  for (const auto& s : kQuerySets)
    for (const auto& d : kQueryRows) {
      Row r = makeRow(d, s.key, s.label, collector);
      if (anyMeasured(r)) rows.push_back(r);
    }

  const std::size_t repetitions = collector.repetitions();
  const Json machine = machineJson(cfg.pairs, cfg.stored, cfg.minTime, opts.quick, repetitions);

  // Targets of the issue: OBB-OBB batch >= 6x faster than FCL; query <= 3 ns per stored box at 1%.
  std::vector<Target> targets;
  for (const Row& r : rows) {
    if (r.name.rfind("obb_obb_batch/", 0) == 0 && !std::isnan(r.nestwalk) && !std::isnan(r.peer[0])) {
      const double ratio = r.peer[0] / r.nestwalk;
      targets.push_back({"obb_obb_batch_vs_fcl/" + r.set, "FCL / ObbPairBatch >= 6", ratio, ratio >= 6.0});
    }
    if (r.name == "query_nested_set/survive_1pct" && !std::isnan(r.nestwalk))
      targets.push_back({"query_ns_per_stored_box/1%", "ns per stored box <= 3", r.nestwalk, r.nestwalk <= 3.0});
  }

  if (opts.json) {
    Json j;
    Json list = Json::array();
    for (const Row& r : rows) {
      Json b;
      b["name"] = r.name;
      b["test"] = r.label;
      b["set"] = r.set;
      b["overlap_fraction"] = jsonNumber(r.setFraction);
      b["verdict_fraction"] = jsonNumber(r.verdictFraction);
      if (!std::isnan(r.hitFraction)) b["hit_fraction"] = r.hitFraction;
      if (!std::isnan(r.uncertainFraction)) b["uncertain_fraction"] = r.uncertainFraction;
      Json ns, ratio, dis;
      ns["nestwalk"] = jsonNumber(r.nestwalk);
      dis["nestwalk"] = r.nestwalkDisagreements >= 0 ? Json(r.nestwalkDisagreements) : Json(nullptr);
      for (int p = 0; p < 3; ++p) {
        ns[kPeerKeys[p]] = jsonNumber(r.peer[p]);
        ratio[kPeerKeys[p]] = jsonNumber(r.peer[p] / r.nestwalk);
        dis[kPeerKeys[p]] =
            r.peerDisagreements[p] >= 0 ? Json(r.peerDisagreements[p]) : Json(nullptr);
      }
      b["ns_per_op"] = ns;
      b["ratio"] = ratio;
      b["disagreements"] = dis;
      list.push_back(b);
    }
    j["benchmarks"] = list;
    j["machine"] = machine;
    j["targets"] = targetsJson(targets);
    addErrors(j, collector);
    out << j.dump(2) << "\n";
    return collector.errors.empty() ? 0 : 1;
  }

  out << "nestwalk bench volumes: ns per test (CPU time); ratio = peer ns / nestwalk ns (> 1: nestwalk faster)\n";
  out << "cpu: " << machine["cpu_model"].get<std::string>() << ", " << machine["num_cpus"] << " CPUs @ "
      << fixedText(machine["mhz_per_cpu"].get<double>(), 0) << " MHz, scaling " << machine["cpu_scaling"].get<std::string>()
      << "\n";
  out << "build: " << isaLine(machine) << (machine["ndebug"].get<bool>() ? "" : "; ASSERTIONS ON (not a release build)")
      << "\n";
  out << "ObbPairBatch kernel: " << machine["batch_kernel"].get<std::string>()
      << " (the 'portable' row forces NESTWALK_SIMD=portable)\n";
  out << "peers: FCL " << FCL_VERSION << " OBB<double>::overlap; libccd MPR ("
      << machine["libraries"]["ccd"].get<std::string>() << ", tolerance 1e-6); Bullet "
      << machine["libraries"]["bullet"].get<std::string>() << " btBoxBoxDetector\n";
  out << "pairs per set: " << cfg.pairs << "; stored boxes per query set: " << cfg.stored
      << "; min time per benchmark: " << cfg.minTime << " s" << (opts.quick ? " (quick)" : "");
  if (repetitions > 1) out << "; median of " << repetitions << " repetitions";
  out << "\n";
  out << "overlap: the set's measured fraction (pairs: satObbObb<double> overlap; queries: stage-1 survivors);"
         " hits: this test's own overlap answers\n\n";

  std::ostringstream t;
  t << std::left << std::setw(26) << "test" << std::setw(8) << "set" << std::right << std::setw(8) << "overlap"
    << std::setw(8) << "hits" << std::setw(10) << "nestwalk";
  for (int p = 0; p < 3; ++p) t << std::setw(10) << kPeerTitles[p] << std::setw(8) << "ratio";
  t << "\n";
  for (const Row& r : rows) {
    t << std::left << std::setw(26) << r.label << std::setw(8) << r.set << std::right << std::setw(8)
      << fixedText(r.setFraction, 4) << std::setw(8) << fixedText(r.verdictFraction, 4) << std::setw(10) << fixedText(r.nestwalk);
    for (int p = 0; p < 3; ++p) t << std::setw(10) << fixedText(r.peer[p]) << std::setw(8) << fixedText(r.peer[p] / r.nestwalk, 1);
    t << "\n";
  }
  out << t.str();

  out << "\ndisagreements with satObbObb<double> (queries: with testNested<double> per stored box), counted once per"
         " benchmark outside the timed loop, not an assertion:\n";
  for (const Row& r : rows) {
    bool any = r.nestwalkDisagreements >= 0;
    for (int p = 0; p < 3; ++p) any = any || r.peerDisagreements[p] >= 0;
    if (!any) continue;
    out << "  " << std::left << std::setw(26) << r.label << std::setw(8) << r.set << std::right;
    out << " nestwalk " << (r.nestwalkDisagreements >= 0 ? std::to_string(r.nestwalkDisagreements) : "-");
    for (int p = 0; p < 3; ++p)
      if (r.peerDisagreements[p] >= 0) out << ", " << kPeerTitles[p] << " " << r.peerDisagreements[p];
    if (!std::isnan(r.uncertainFraction)) out << "; uncertain lanes " << fixedText(100 * r.uncertainFraction, 3) << "%";
    if (!std::isnan(r.hitFraction)) out << "; final hits " << fixedText(100 * r.hitFraction, 3) << "%";
    out << "\n";
  }
  printTargets(out, targets, 32, 26);
  for (const auto& [k, v] : collector.errors) out << "error: " << k << ": " << v << "\n";
  return collector.errors.empty() ? 0 : 1;
}

}  // namespace nestwalk::bench
