// The bounding-volume benchmark (see volume_bench.h).
//
// Every benchmark answers its whole set once per Google Benchmark iteration (timePasses,
// bench_runner.h), so ns/op = 1e9 / items_per_second. Data sets are generated from fixed seeds
// (SplitMix64 with its own transforms: the same boxes on every platform), one at a time (the
// benchmarks of a set run together); each method's layout (float boxes, the batch, fcl::OBB,
// btTransform, ...) is built on its first use, outside the timed loop. Verdict fractions and
// disagreements with the reference are counted on one pass, outside the timed loop.
#include "tools/bench/volume_bench.h"

#include "tools/bench/bench_document.h"
#include "tools/bench/bench_process.h"
#include "tools/bench/peers/box_peers.h"

#include "nestwalk/core/random.h"
#include "nestwalk/geometry/obb_batch.h"
#include "nestwalk/core/number_text.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <iomanip>
#include <memory>
#include <ostream>
#include <type_traits>

namespace nestwalk::bench {
namespace {

// Box sizes: half extents log-uniform in [0.1, 2] m (poles, panels and blocks of equipment).
constexpr double kMinHalf = 0.1, kMaxHalf = 2.0;
constexpr std::size_t kCalibrationPairs = 100'000;  // pairs the centre-distance scale is bisected on
constexpr int kScaleHalvings = 50;    // bisection steps of the pairs' centre-distance scale
constexpr double kMaxScale = 1e6;     // m, where the search for the scale's upper bound gives up
constexpr double kBoxPairsVsScalar = 5.0; // target: testBoxPair ns / testBoxPairs ns (query overlap)

/// SplitMix64 with random directions and rotations.
class Rng : public SplitMix64 {
 public:
  using SplitMix64::SplitMix64;
  Vec3<double> direction() {
    for (;;) {
      const Vec3<double> g(gaussian(), gaussian(), gaussian());
      if (g.norm() > 1e-9) return g.normalized();
    }
  }
  Mat3<double> rotation() {  // uniform on SO(3): a normalized Gaussian quaternion
    for (;;) {
      Eigen::Quaterniond q(gaussian(), gaussian(), gaussian(), gaussian());
      if (q.norm() > 1e-9) return q.normalized().toRotationMatrix();
    }
  }
  Obb<double> box(const Vec3<double>& center) {
    Obb<double> b;
    b.center = center;
    b.axes = rotation();
    for (int k = 0; k < 3; ++k) b.halfExtents[k] = std::exp(uniform(std::log(kMinHalf), std::log(kMaxHalf)));
    return b;
  }
};

struct SetSpec {
  const char* key;    // "overlap_50pct"
  const char* label;  // "50%"
  double target;  // wanted OBB-OBB overlap fraction
  std::uint64_t seed;
};
constexpr SetSpec kSets[] = {
    {"overlap_50pct", "50%", 0.50, 0x6e657374'00000050ull},
    {"overlap_5pct", "5%", 0.05, 0x6e657374'00000005ull},
};

/// A data set: n pairs (a[k], b[k]), the reference verdicts (satObbObb<double> per pair) and the
/// methods' passes.
struct BoxSet {
  const SetSpec* spec = nullptr;
  std::size_t n = 0;
  double fraction = 0;  // measured: the pairs' overlap
  std::vector<Obb<double>> a, b;
  std::vector<std::uint8_t> reference;
  std::map<std::string, Pass<std::uint8_t>> passes;
};

/// Bisects [lo, hi] `halvings` times, moving lo up where below(mid), else hi down; the midpoint.
template <class F>
double bisect(double lo, double hi, int halvings, const F& below) {
  for (int it = 0; it < halvings; ++it) {
    const double mid = 0.5 * (lo + hi);
    (below(mid) ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// The pairs: box A at a random point, box B at A's centre + dir * u * scale with u uniform in
// [0, 1). For fixed boxes and direction the overlapping centre offsets form a convex set around 0
// (A minus B), so the overlap count is non-increasing in the scale and bisection finds it.
void makePairs(BoxSet& s, Rng& rng) {
  std::vector<Vec3<double>> offset(s.n);
  for (std::size_t k = 0; k < s.n; ++k) {
    const Vec3<double> c(rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-10, 10));
    s.a.push_back(rng.box(c));
    s.b.push_back(rng.box(c));
    offset[k] = rng.direction() * rng.uniform();
  }
  const std::size_t m = std::min(s.n, kCalibrationPairs);
  auto tooClose = [&](double scale) {  // more pairs than wanted overlap
    std::size_t hits = 0;
    for (std::size_t k = 0; k < m; ++k) {
      Obb<double> b = s.b[k];
      b.center = s.a[k].center + scale * offset[k];
      hits += satObbObb(s.a[k], b).overlap ? 1 : 0;
    }
    return double(hits) / double(m) > s.spec->target;
  };
  double hi = 1;
  while (tooClose(hi) && hi < kMaxScale) hi *= 2;
  const double scale = bisect(0, hi, kScaleHalvings, tooClose);
  for (std::size_t k = 0; k < s.n; ++k) {
    s.b[k].center = s.a[k].center + scale * offset[k];
    s.reference.push_back(satObbObb(s.a[k], s.b[k]).overlap ? 1 : 0);
  }
}

/// What the run sets, and the one set its benchmarks keep at a time.
struct Config {
  std::size_t pairs = 1'000'000;
  std::unique_ptr<BoxSet> set;
};
Config& config() {
  static Config c;
  return c;
}

/// The set of `spec` at the configured size; only one set is kept at a time.
BoxSet& boxSet(const SetSpec& spec) {
  std::unique_ptr<BoxSet>& s = config().set;
  const std::size_t n = config().pairs;
  if (!s || s->spec != &spec || s->n != n) {
    s.reset();
    s = std::make_unique<BoxSet>();
    s->spec = &spec;
    s->n = n;
    Rng rng(spec.seed);
    makePairs(*s, rng);
    s->fraction = double(std::count(s->reference.begin(), s->reference.end(), 1)) / double(n);
  }
  return *s;
}

// ------------------------------------------------------------------------------------------------
// The methods: nestwalk's tests and the peers, each a pass over a set (bench_runner.h).

/// The boxes converted by f (a method's own layout, built once, outside the timed loop).
template <class F, class T = std::invoke_result_t<const F&, const Obb<double>&>>
std::shared_ptr<const std::vector<T>> convert(const std::vector<Obb<double>>& boxes, const F& f) {
  auto out = std::make_shared<std::vector<T>>();
  out->reserve(boxes.size());
  for (const Obb<double>& b : boxes) out->push_back(f(b));
  return out;
}

/// The set's own boxes, not copied (the set outlives its passes).
std::shared_ptr<const std::vector<Obb<double>>> own(const std::vector<Obb<double>>& boxes) {
  return {std::shared_ptr<void>(), &boxes};
}

/// The pass of test(a[k], b[k]) over all pairs.
template <class A, class B, class Test>
Pass<std::uint8_t> pairPass(std::shared_ptr<const std::vector<A>> a, std::shared_ptr<const std::vector<B>> b,
                            Test test) {
  return [a, b, test](std::uint8_t* verdicts) {
    const std::vector<A>& x = *a;
    const std::vector<B>& y = *b;
    return answerAll(x.size(), verdicts, [&](std::size_t k) { return test(x[k], y[k]); });
  };
}

/// The pass of test over the pairs with both boxes converted by f.
template <class F, class Test>
Pass<std::uint8_t> convertedPairPass(const BoxSet& s, const F& f, Test test) {
  return pairPass(convert(s.a, f), convert(s.b, f), test);
}

constexpr auto kAabbAabb = [](const auto& x, const auto& y) { return satAabbAabb(x, y).overlap; };
constexpr auto kAabbObb = [](const auto& x, const auto& y) { return satAabbObb(x, y).overlap; };
constexpr auto kObbObb = [](const auto& x, const auto& y) { return satObbObb(x, y).overlap; };
constexpr auto kNested = [](const auto& x, const auto& y) { return testNested(x, y).overlap; };
constexpr auto kAabb = [](const Obb<double>& b) { return aabbOf(b); };
constexpr auto kAabbFloat = [](const Obb<double>& b) { return toFloatConservative(aabbOf(b)); };
constexpr auto kObbFloat = [](const Obb<double>& b) { return b.cast<float>(); };
constexpr auto kNestedVolume = [](const Obb<double>& b) { return NestedVolume<double>::fromObb(b); };

/// The kernel testBoxPairs uses here (the 'portable' rows set NESTWALK_SIMD=portable while they run).
std::string batchKernel() {
  return batchKernelName(obbBatchKernel());
}

/// testBoxPairs over the pairs, the path of `query overlap` (stage and axis computed, the overlap
/// kept as the verdict); its facts get the fraction of lanes it re-decided in double.
Pass<std::uint8_t> boxPairsPass(const BoxSet& s, Facts& facts, bool portable) {
  auto results = std::make_shared<std::vector<NestedResult>>(s.n);
  // Rotations from unit quaternions: the axes keep Obb's contract, as query overlap's reader ensures.
  const BoxPairsView view{.a = s.a.data(), .b = s.b.data(), .count = s.n, .orthonormalAxes = true};
  const ScopedEnvironment simd("NESTWALK_SIMD", "portable", portable);
  facts["uncertain_fraction"] = double(testBoxPairs(view, results->data())) / double(s.n);
  return [view, results, portable](std::uint8_t* verdicts) {
    const ScopedEnvironment simd("NESTWALK_SIMD", "portable", portable);
    const double uncertain = double(testBoxPairs(view, results->data()));
    if (verdicts)
      for (std::size_t k = 0; k < view.count; ++k) verdicts[k] = (*results)[k].overlap ? 1 : 0;
    return uncertain;
  };
}

struct MethodDef {
  const char* key;
  const char* label;  // nestwalk's tests: the row's title (its name is "<key>/<set>"); null: a peer
  bool compared;  // verdicts compared with the reference, and the peers' figures on its row (the
                  // AABB tests answer another question)
  Pass<std::uint8_t> (*make)(const BoxSet& s, Facts& facts);
};
const MethodDef kMethods[] = {
    {"box_pairs_batch", "query overlap batch", true,
     [](const BoxSet& s, Facts& f) { return boxPairsPass(s, f, false); }},
    {"box_pairs_batch_portable", "query overlap portable", true,
     [](const BoxSet& s, Facts& f) { return boxPairsPass(s, f, true); }},
    {"box_pair_scalar", "query overlap scalar", true,
     [](const BoxSet& s, Facts&) {
       return pairPass(own(s.a), own(s.b), [](const auto& x, const auto& y) { return testBoxPair(x, y).overlap; });
     }},
    {"aabb_aabb_double", "AABB-AABB double", false,
     [](const BoxSet& s, Facts&) { return convertedPairPass(s, kAabb, kAabbAabb); }},
    {"aabb_aabb_float", "AABB-AABB float", false,
     [](const BoxSet& s, Facts&) { return convertedPairPass(s, kAabbFloat, kAabbAabb); }},
    {"aabb_obb_double", "AABB-OBB double", false,
     [](const BoxSet& s, Facts&) { return pairPass(convert(s.a, kAabb), own(s.b), kAabbObb); }},
    {"obb_obb_double", "OBB-OBB double scalar", true,
     [](const BoxSet& s, Facts&) { return pairPass(own(s.a), own(s.b), kObbObb); }},
    {"obb_obb_float", "OBB-OBB float scalar", true,
     [](const BoxSet& s, Facts&) { return convertedPairPass(s, kObbFloat, kObbObb); }},
    {"nested_double", "nested double (3-stage)", true,
     [](const BoxSet& s, Facts&) { return convertedPairPass(s, kNestedVolume, kNested); }},
    {"peer_fcl_obb", nullptr, true, [](const BoxSet& s, Facts&) { return fclBoxPairs(s.a, s.b); }},
    {"peer_ccd_mpr", nullptr, true, [](const BoxSet& s, Facts&) { return ccdBoxPairs(s.a, s.b); }},
    {"peer_bullet_boxbox", nullptr, true, [](const BoxSet& s, Facts&) { return bulletBoxPairs(s.a, s.b); }},
};

/// The facts of a method's verdicts: their fraction, their disagreements with the reference.
void judge(const BoxSet& s, bool compared, const std::vector<std::uint8_t>& verdicts, Facts& facts) {
  std::size_t hits = 0, differ = 0;
  for (std::size_t k = 0; k < s.n; ++k) {
    hits += verdicts[k];
    differ += verdicts[k] != s.reference[k] ? 1 : 0;
  }
  facts["verdict_fraction"] = double(hits) / double(s.n);
  if (compared) facts["disagreements"] = double(differ);
  facts.emplace("overlap_fraction", s.fraction);  // unless the method measured its own
}

Suite& suite() { return Suite::named("volumes"); }

/// Registers every method on every set.
void registerBenchmarks() {
  suite().addEach(
      kSets, kMethods, [](const SetSpec&, const MethodDef&) { return true; },
      [](const SetSpec& set, const MethodDef& m, benchmark::State& state, Facts& facts) {
        BoxSet& s = boxSet(set);
        auto pass = s.passes.find(m.key);
        if (pass == s.passes.end()) pass = s.passes.emplace(m.key, m.make(s, facts)).first;
        timePasses<std::uint8_t>(state, facts, s.n, pass->second,
                                 [&](const auto& verdicts, Facts& f) { judge(s, m.compared, verdicts, f); });
      });
}

// ------------------------------------------------------------------------------------------------
// The output.

const std::vector<Peer> kPeers = {{"fcl", "FCL"}, {"ccd_mpr", "ccd MPR"}, {"bullet", "Bullet"}};
constexpr const char* kPairPeers[] = {"peer_fcl_obb", "peer_ccd_mpr", "peer_bullet_boxbox"};

/// The row of nestwalk's test m on `set`: the fractions, ns/op and disagreements of nestwalk and the
/// peers.
Json makeRow(const MethodDef& m, const SetSpec& set) {
  const Suite& s = suite();
  Json row = {{"name", std::string(m.key) + "/" + set.key}, {"test", m.label}, {"set", set.label}};
  std::vector<std::pair<std::string, const char*>> methods = {{"nestwalk", m.key}};
  for (std::size_t p = 0; p < kPeers.size(); ++p)
    methods.emplace_back(kPeers[p].key, m.compared ? kPairPeers[p] : nullptr);
  double overlap = s.fact(m.key, set.key, "overlap_fraction");
  for (const auto& [key, method] : methods)
    if (std::isnan(overlap) && method) overlap = s.fact(method, set.key, "overlap_fraction");
  row["overlap_fraction"] = jsonNumber(overlap);
  row["verdict_fraction"] = jsonNumber(s.fact(m.key, set.key, "verdict_fraction"));
  if (const double f = s.fact(m.key, set.key, "uncertain_fraction"); !std::isnan(f)) row["uncertain_fraction"] = f;
  for (const auto& [key, method] : methods) {
    row["ns_per_op"][key] = method ? jsonNumber(s.ns(method, set.key)) : Json();
    row["disagreements"][key] = method ? countJson(s.fact(method, set.key, "disagreements")) : Json();
  }
  return row;
}


/// Per row, the disagreements with the reference, the uncertain lanes and the final hits.
void printDisagreements(std::ostream& out, const Table& table) {
  out << "\ndisagreements with satObbObb<double>, counted once per"
         " benchmark outside the timed loop, not an assertion:\n";
  for (const Json& r : table.rows()) {
    std::string line;
    for (const auto& [key, title] : std::vector<Peer>{{"nestwalk", "nestwalk"}, kPeers[0], kPeers[1], kPeers[2]})
      if (r["disagreements"][key].is_number())
        line += (line.empty() ? " " : ", ") + title + " " + std::to_string(r["disagreements"][key].get<long long>());
    if (line.empty()) continue;
    if (r.contains("uncertain_fraction"))
      line += "; uncertain lanes " + fixedText(100 * r["uncertain_fraction"].get<double>(), 3) + "%";
    out << "  " << std::left << std::setw(26) << r["test"].get<std::string>() << std::setw(8)
        << r["set"].get<std::string>() << std::right << line << "\n";
  }
}

}  // namespace

int runBenchmark(const VolumeBenchOptions& opts, std::ostream& out) {
  config().pairs = opts.orDefault(opts.pairs, 20'000, 1'000'000);
  const double minTime = opts.minTime(0.5);
  registerBenchmarks();
  const ReleaseAtEnd release([] { config().set.reset(); });  // the data sets take up to a few GB at 1M pairs
  Suite& s = suite();
  if (const std::optional<int> rc = s.run(opts, minTime, "^volumes/", out)) return *rc;

  Table table = Table::againstPeers({"test", "/test", 26, 0, true}, {"set", "/set", 8, 0, true},
                                    {{"overlap", "/overlap_fraction", 8, 4}, {"hits", "/verdict_fraction", 8, 4}},
                                    "ns_per_op", kPeers, 10, 2, 1);
  for (const SetSpec& set : kSets)
    for (const MethodDef& m : kMethods)
      if (m.label) table.addMeasured(makeRow(m, set), "ns_per_op");

  Document doc("nestwalk bench volumes: ns per test (CPU time);"
               " ratio = peer ns / nestwalk ns (> 1: nestwalk faster)");
  doc.errors = s.errors();
  Json& m = doc.json["machine"];
  m["batch_kernel"] = batchKernel();
  m["pairs_per_set"] = config().pairs;
  doc.text << "testBoxPairs kernel: " << batchKernel() << " (the 'portable' row forces NESTWALK_SIMD=portable)\n"
           << "peers: FCL " << m["libraries"]["fcl"].get<std::string>() << " OBB<double>::overlap; libccd MPR ("
           << m["libraries"]["ccd"].get<std::string>() << ", tolerance 1e-6); Bullet "
           << m["libraries"]["bullet"].get<std::string>() << " btBoxBoxDetector\n"
           << "pairs per set: " << config().pairs << "; "
           << doc.runSettings(minTime, opts.quick, s.repetitions()) << "\n"
           << "overlap: the set's measured fraction (satObbObb<double> overlap);"
              " hits: this test's own overlap answers\n\n";
  doc.table("benchmarks", table);
  printDisagreements(doc.text, table);

  for (const Json& r : table.rows()) {
    const std::string name = r["name"].get<std::string>();
    if (name.rfind("box_pairs_batch/", 0) == 0 && r["ns_per_op"]["nestwalk"].is_number()) {
      const double scalar = s.ns("box_pair_scalar", name.substr(name.find('/') + 1));
      doc.target("box_pairs_batch_vs_scalar/" + r["set"].get<std::string>(), "testBoxPair / testBoxPairs",
                 scalar / r["ns_per_op"]["nestwalk"].get<double>(), ">=", kBoxPairsVsScalar);
    }
  }
  return doc.write(out, opts.json);
}

}  // namespace nestwalk::bench
