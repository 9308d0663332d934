// The broad-phase benchmark (see broadphase_bench.h).
//
// Every benchmark answers the whole query set once per Google Benchmark iteration (timePasses,
// bench_runner.h), so µs/query = 1e-3 * 1e9 / items_per_second. The boxes and queries of one size
// are generated from fixed seeds (SplitMix64) and kept while that size's benchmarks run (they run
// one size after the other, registration order); each structure is built on its first use, outside
// the timed loops, and its build time recorded. Hits per query are compared with nestwalk's default
// hierarchy outside the timed loops, and that hierarchy itself with brute force on a prefix of the
// queries.
#include "tools/bench/broadphase_bench.h"

#include "tools/bench/peers/broadphase_peers.h"

#include "nestwalk/core/random.h"
#include "nestwalk/geometry/obb_batch.h"
#include "nestwalk/hierarchy/box_tree.h"
#include "nestwalk/core/number_text.h"

#include <algorithm>
#include <memory>
#include <numbers>
#include <ostream>

namespace nestwalk::bench {
namespace {

using Box = Aabb<double>;
constexpr double kArea = 10000.0;              // m, side of the square the boxes are scattered over
constexpr double kBaseZMax = 50.0;             // m, box bases (the ground) between 0 and this
constexpr int kWalkSteps = 1000;               // queries per walk before starting a new one
constexpr double kMaxStep = 1.0;               // m, viewer motion per query (the swept part)
const Eigen::Vector3d kViewer(0.5, 0.5, 1.8);  // m, the viewer's box
constexpr double kBruteForceBoxTests = 2e8;    // box tests spent checking the reference
constexpr double kQueryVsDbvt = 2.0;           // target: btDbvt µs / nestwalk µs at least
constexpr double kBuildSeconds = 1.0;          // target: the default hierarchy's build of 1M boxes
constexpr std::size_t kBuildTargetBoxes = 1'000'000;

struct MethodDef {
  const char* key;
  const char* label;
  const char* column;  // build-time table header
  int degree;          // 0: a peer
  SplitAxis axis;
  SplitPoint point;
  BroadPhasePeer (*peer)(const std::vector<Box>&, const std::vector<Box>&);
};
constexpr MethodDef kMethods[] = {
    {"nestwalk_d2_longest_median", "nestwalk d=2 longest/median", "d=2", 2, SplitAxis::LongestSide, SplitPoint::Median, nullptr},
    {"nestwalk_d4_longest_median", "nestwalk d=4 longest/median", "d=4", 4, SplitAxis::LongestSide, SplitPoint::Median, nullptr},
    {"nestwalk_d8_longest_median", "nestwalk d=8 longest/median", "d=8", 8, SplitAxis::LongestSide, SplitPoint::Median, nullptr},
    {"nestwalk_d4_splatter_mean", "nestwalk d=4 splatter/mean", "d=4 spl/mean", 4, SplitAxis::Splatter, SplitPoint::Mean, nullptr},
    {"btdbvt", "Bullet btDbvt", "btDbvt", 0, SplitAxis::LongestSide, SplitPoint::Median, bulletBroadPhase},
    {"fcl_dynamic_aabb", "FCL DynamicAABBTree", "FCL", 0, SplitAxis::LongestSide, SplitPoint::Median, fclBroadPhase},
};
constexpr const MethodDef& kDefaultTree = kMethods[2];  // the default AutoTreeOptions
constexpr const MethodDef& kBullet = kMethods[4];
constexpr const MethodDef& kFcl = kMethods[5];

/// The smallest box of float coordinates around lo..hi, in double (so that every peer, float or
/// double, sees the same numbers).
Box floatBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  return toFloatConservative(Box{lo, hi}).cast<double>();
}

// ------------------------------------------------------------------------------------------------
// The data and structures of one size.

struct ReferenceCheck {
  std::size_t queries = 0, differ = 0;
};

struct Scene {
  std::size_t n = 0;
  std::vector<Box> boxes, queries;
  std::map<std::string, Pass<Hits>> passes;
  std::map<std::string, Facts> built;  // per method: build_s, and the trees' BV tests per query
  std::vector<Hits> reference;         // sorted hits per query of the default hierarchy
};

/// What the run sets, the one size's data its benchmarks keep at a time, and what they found per
/// size apart from the benchmarks' facts.
struct Config {
  std::vector<std::size_t> sizes;
  std::size_t queries = 100'000;
  std::unique_ptr<Scene> scene;
  std::map<std::size_t, ReferenceCheck> referenceChecks;
  std::map<std::size_t, std::size_t> fclMismatches;  // FCL's AABBs different from the boxes
};
Config& config() {
  static Config c;
  return c;
}

void makeBoxes(Scene& s) {
  SplitMix64 rng(0x62726f6164ull ^ (std::uint64_t(s.n) * 0x9E3779B97F4A7C15ull));
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
  const double half = 0.5 * kArea;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  double heading = 0;
  for (std::size_t k = 0; k < config().queries; ++k) {
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
    s.queries.push_back(floatBox(p.cwiseMin(next) - h, p.cwiseMax(next) + h + Eigen::Vector3d(0, 0, kViewer.z())));
    p = next;
  }
}

Scene& scene(std::size_t n) {
  std::unique_ptr<Scene>& s = config().scene;
  if (!s || s->n != n || s->queries.size() != config().queries) {
    s.reset();  // free the previous size first
    s = std::make_unique<Scene>();
    s->n = n;
    makeBoxes(*s);
    makeQueries(*s);
  }
  return *s;
}

/// A nestwalk hierarchy as a method; its build facts: build time, depth, BV tests per query.
Pass<Hits> treePass(const Scene& s, const MethodDef& m, Facts& built) {
  const double t0 = threadSeconds();
  auto tree = std::make_shared<const BoxTree>(BoxTree::buildAuto(s.boxes, AutoTreeOptions{m.degree, m.axis, m.point}));
  built["build_s"] = threadSeconds() - t0;
  BroadPhaseCounters c;
  Hits out;
  for (const Box& q : s.queries) {
    out.clear();
    tree->query(q, out, &c);
  }
  built["depth"] = tree->depth();
  built["node_tests_per_query"] = double(c.nodeTests) / double(s.queries.size());
  built["leaf_tests_per_query"] = double(c.leafTests) / double(s.queries.size());
  auto scratch = std::make_shared<Hits>();
  return [tree, scratch, &queries = s.queries](Hits* answers) {
    const BoxTree& t = *tree;
    const std::vector<Box>& q = queries;
    return answerQueries(q.size(), answers, *scratch, [&](std::size_t k, Hits& hits) { t.query(q[k], hits); });
  };
}

/// The method's pass over the scene's queries, built on first use.
const Pass<Hits>& pass(Scene& s, const MethodDef& m) {
  auto it = s.passes.find(m.key);
  if (it != s.passes.end()) return it->second;
  Facts& built = s.built[m.key];
  if (m.degree > 0) return s.passes[m.key] = treePass(s, m, built);
  BroadPhasePeer peer = m.peer(s.boxes, s.queries);
  built["build_s"] = peer.buildSeconds;
  if (&m == &kFcl) config().fclMismatches[s.n] = peer.aabbMismatches;
  return s.passes[m.key] = std::move(peer.pass);
}

/// The default hierarchy's sorted hits, checked against brute force on as many queries as
/// kBruteForceBoxTests allows.
const std::vector<Hits>& reference(Scene& s) {
  if (!s.reference.empty()) return s.reference;
  s.reference.resize(s.queries.size());
  pass(s, kDefaultTree)(s.reference.data());
  for (Hits& h : s.reference) std::sort(h.begin(), h.end());
  ReferenceCheck& c = config().referenceChecks[s.n];
  c.queries = std::min(s.queries.size(), std::max<std::size_t>(10, std::size_t(kBruteForceBoxTests / double(s.n))));
  for (std::size_t k = 0; k < c.queries; ++k) {
    Hits h;
    const Box& q = s.queries[k];
    for (std::uint32_t i = 0; i < s.boxes.size(); ++i) {
      const Box& b = s.boxes[i];
      if ((b.min.array() <= q.max.array()).all() && (q.min.array() <= b.max.array()).all()) h.push_back(i);
    }
    c.differ += h != s.reference[k] ? 1 : 0;
  }
  return s.reference;
}

void judge(Scene& s, std::vector<Hits>& answers, Facts& facts) {
  const std::vector<Hits>& ref = reference(s);
  std::size_t hits = 0, differ = 0;
  for (std::size_t k = 0; k < answers.size(); ++k) {
    std::sort(answers[k].begin(), answers[k].end());
    hits += answers[k].size();
    differ += answers[k] != ref[k] ? 1 : 0;
  }
  facts["hits"] = double(hits);
  facts["disagreements"] = double(differ);
}

Suite& suite() { return Suite::named("broadphase"); }

void registerBenchmarks() {
  for (std::size_t n : config().sizes)
    for (const MethodDef& m : kMethods)
      suite().add(m.key, std::to_string(n), [&m, n](benchmark::State& state, Facts& facts) {
        Scene& s = scene(n);
        const Pass<Hits>& p = pass(s, m);
        facts.insert(s.built[m.key].begin(), s.built[m.key].end());
        timePasses<Hits>(state, facts, s.queries.size(), p,
                         [&](std::vector<Hits>& answers, Facts& f) { judge(s, answers, f); });
      });
}

// ------------------------------------------------------------------------------------------------
// The output.

/// The row of method m at size n; null when it did not run.
Json makeRow(const MethodDef& m, std::size_t n) {
  const Suite& s = suite();
  const std::string size = std::to_string(n);
  if (!s.facts(m.key, size)) return nullptr;
  auto us = [&](const MethodDef& x) { return jsonNumber(1e-3 * s.ns(x.key, size)); };
  Json row = {{"name", s.benchName(m.key, size)}, {"method", m.label}, {"boxes", n}, {"us_per_query", us(m)}};
  if (m.degree > 0) {
    row["nestwalk_us"] = us(m);
    row["btdbvt_us"] = us(kBullet);
    row["fcl_us"] = us(kFcl);
  } else {
    row[std::string(m.key == kBullet.key ? "btdbvt" : "fcl") + "_us"] = us(m);
  }
  row["hits"] = countJson(s.fact(m.key, size, "hits"));
  row["queries_differing_from_nestwalk"] = countJson(s.fact(m.key, size, "disagreements"));
  row["build_s"] = jsonNumber(s.fact(m.key, size, "build_s"));
  if (m.degree > 0) {
    row["depth"] = countJson(s.fact(m.key, size, "depth"));
    row["node_tests_per_query"] = jsonNumber(s.fact(m.key, size, "node_tests_per_query"));
    row["leaf_tests_per_query"] = jsonNumber(s.fact(m.key, size, "leaf_tests_per_query"));
  }
  return row;
}

void printBuildTimes(std::ostream& out) {
  Table t;
  t.column({"boxes", "/boxes", 9, 0, true});
  for (const MethodDef& m : kMethods) t.column({m.column, "/" + std::string(m.key), 13, 3});
  for (std::size_t n : config().sizes) {
    Json row = {{"boxes", n}};
    for (const MethodDef& m : kMethods) row[m.key] = jsonNumber(suite().fact(m.key, std::to_string(n), "build_s"));
    t.add(row);
  }
  out << "\nbuild times (s, CPU time of the building thread):\n";
  t.print(out);
  out << "(nestwalk: buildAuto; btDbvt: one insert per box; FCL: creating the objects + registerObjects + setup)\n";
}

}  // namespace

Document measureBroadPhase(const BroadPhaseBenchOptions& opts) {
  Config& c = config();
  c.sizes = opts.orDefault(opts.sizes, {1000, 10000}, {1000, 10000, 100000, 1000000});
  c.queries = opts.orDefault(opts.queries, 10'000, 100'000);
  const double minTime = opts.minTime(0.3);
  registerBenchmarks();
  const ReleaseAtEnd release([] {  // the scene and the checks kept for the table (the settings stay)
    config().scene.reset();
    config().referenceChecks.clear();
    config().fclMismatches.clear();
  });
  std::string sizes;
  for (std::size_t n : c.sizes) sizes += (sizes.empty() ? "" : "|") + std::to_string(n);
  Document doc("nestwalk bench broadphase: µs per query (CPU time);"
               " ratio = peer µs / nestwalk µs (> 1: nestwalk faster)");
  Suite& s = suite();
  std::ostringstream noMatch;
  if (s.run(opts, minTime, "^broadphase/[^/]+/(" + sizes + ")(/|$)", noMatch) == 1)
    doc.errors["filter"] = noMatch.str();
  doc.errors.insert(s.errors().begin(), s.errors().end());

  Table table;
  table.column({"boxes", "/boxes", 9, 0, true})
      .column({"hierarchy", "/method", 30, 0, true})
      .column({"nestwalk", "/nestwalk_us", 10, 3, false, true})
      .column({"btDbvt", "/btdbvt_us", 10, 3, false, true})
      .ratio({"ratio", "/ratio_btdbvt", 8, 2}, "/btdbvt_us", "/nestwalk_us")
      .column({"FCL", "/fcl_us", 10, 3, false, true})
      .ratio({"ratio", "/ratio_fcl", 8, 2}, "/fcl_us", "/nestwalk_us")
      .column({"hits", "/hits", 12})
      .column({"differ", "/queries_differing_from_nestwalk", 8})
      .column({"depth", "/depth", 7})
      .column({"nodeT/q", "/node_tests_per_query", 9, 1})
      .column({"leafT/q", "/leaf_tests_per_query", 9, 1});
  std::size_t differing = 0;
  for (std::size_t n : c.sizes)
    for (const MethodDef& m : kMethods)
      if (Json row = makeRow(m, n); !row.is_null()) {
        const Json& differ = row["queries_differing_from_nestwalk"];
        differing += differ.is_number() ? differ.get<std::size_t>() : 0;
        table.add(std::move(row));
      }

  Json& mach = doc.json["machine"];
  mach["queries"] = c.queries;
  doc.text << "boxes over " << kArea / 1000 << " x " << kArea / 1000 << " km, base z 0-" << kBaseZMax
           << " m (poles, cabinets, containers); " << c.queries << " swept viewer boxes along walks of " << kWalkSteps
           << " steps; " << doc.runSettings(minTime, opts.quick, s.repetitions()) << "\n"
           << "peers: Bullet " << mach["libraries"]["bullet"].get<std::string>() << " btDbvt (insert, collideTV); FCL "
           << mach["libraries"]["fcl"].get<std::string>()
           << " DynamicAABBTreeCollisionManager (registerObjects + setup, collide with a recording callback)\n\n";
  doc.table("benchmarks", table);
  doc.text << "(hits: total over all queries; differ: queries whose hit set differs from nestwalk d=8's; depth: "
              "levels of\n inner nodes; nodeT/q, leafT/q: inner-node and unit box tests per query, the BV counts of "
              "fACT's Table 2)\n"
              "brute-force check of nestwalk d=8:";
  Json checks = Json::array();
  for (const auto& [n, check] : c.referenceChecks) {
    doc.text << " n=" << n << " " << check.differ << "/" << check.queries << " differ;";
    checks.push_back({{"boxes", n}, {"queries", check.queries}, {"differing", check.differ}});
    differing += check.differ;
  }
  doc.json["brute_force_check"] = checks;
  doc.text << " FCL AABBs different from the boxes:";
  for (const auto& [n, count] : c.fclMismatches) {
    doc.text << " n=" << n << " " << count << ";";
    doc.json["fcl_aabb_mismatches"][std::to_string(n)] = count;
  }
  doc.text << "\n";
  printBuildTimes(doc.text);
  if (differing > 0) doc.errors["hits"] = std::to_string(differing) + " queries whose hits differ (see 'differ')";

  for (std::size_t n : c.sizes) {
    const std::string size = std::to_string(n);
    doc.target("query_vs_btdbvt/" + size, "btDbvt / nestwalk d=8",
               s.ns(kBullet.key, size) / s.ns(kDefaultTree.key, size), ">=", kQueryVsDbvt);
    if (n >= kBuildTargetBoxes)
      doc.target("build_s/" + size, "nestwalk d=8 build", s.fact(kDefaultTree.key, size, "build_s"), "<",
                 kBuildSeconds, " s");
  }
  return doc;
}

int runBenchmark(const BroadPhaseBenchOptions& opts, std::ostream& out) {
  return measureBroadPhase(opts).write(out, opts.json);
}

}  // namespace nestwalk::bench
