// The terrain benchmark (see terrain_bench.h).
//
// Every benchmark answers its set's rays (or the slow peers' prefix of them) once per Google
// Benchmark iteration (timePasses, bench_runner.h), so ns/ray = 1e9 / items_per_second. The DEM and
// the ray sets are generated from fixed seeds (SplitMix64) and kept for the whole run; each peer's
// structure is built on its first use, outside the timed loops, and its build time reported. The
// reference of a set is nestwalk's own answer (groundHeight on the vertical sets, intersectRay on
// the oblique one); hit fractions, hit/miss disagreements with it, the largest |height difference|
// where both hit and the hits more than 1 cm apart are counted on one pass, outside the timed loop.
#include "tools/bench/terrain_bench.h"

#include "tools/bench/bench_document.h"
#include "tools/bench/peers/terrain_peers.h"

#include "nestwalk/core/output_file.h"
#include "nestwalk/core/random.h"
#include "nestwalk/core/stopwatch.h"
#include "nestwalk/core/number_text.h"
#include "nestwalk/terrain/heightfield.h"
#include "nestwalk/terrain/paged_heightfield.h"
#include "nestwalk/terrain/terrain_chunk.h"
#include "nestwalk/terrain/terrain_import.h"
#include "nestwalk/terrain/value_noise.h"

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <memory>
#include <numbers>
#include <ostream>

namespace nestwalk::bench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kOriginX = 500000.0, kOriginY = 5200000.0;  // map coordinates of sample (0, 0)
constexpr double kSpacing = 1.0;                             // m, both directions
/// m: hits further apart in height are counted apart; the float peers differ by rounding (~1e-4 m).
constexpr double kFarHit = 0.01;
constexpr double kGroundVsDirect = 1.2;    // target: groundHeight ns / direct lookup ns at most
constexpr double kGroundVsEmbree = 15.0;   // target: Embree ns / groundHeight ns at least
constexpr double kObliqueVsEmbree = 1.0;   // target: Embree ns / intersectRay ns at least, oblique
constexpr int kLevelChunkCells = 64;        // the level table's chunks (RenderOptions::terrainChunkCells)

/// A lattice point's value in [-1, 1], hashed from the point and the seed.
double latticeValue(std::int64_t x, std::int64_t y, std::uint64_t seed) {
  SplitMix64 rng(seed ^ (std::uint64_t(x) * 0x9E3779B97F4A7C15ull) ^ (std::uint64_t(y) * 0xC2B2AE3D27D4EB4Full));
  return rng.uniform(-1.0, 1.0);
}

/// Value noise in [-1, 1] with smoothstep interpolation on a lattice of `wavelength` samples
/// (terrain/value_noise.h, the synthetic mining dump's).
double valueNoise(double x, double y, double wavelength, std::uint64_t seed) {
  return terrain::valueNoise([seed](std::int64_t i, std::int64_t j) { return latticeValue(i, j, seed); }, x, y,
                             wavelength);
}

/// The rough DEM: fBm (wavelengths 512 m down to 4 m, amplitude halving) plus +-0.25 m per sample.
HeightGrid makeGrid(int n) {
  HeightGrid g{n, kSpacing, std::vector<float>(std::size_t(n) * std::size_t(n)), 0, 0};
  SplitMix64 rng(0x7465727261696eull);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      double z = 300.0, amp = 120.0;
      for (int o = 0; o < 8; ++o, amp *= 0.5)
        z += amp * valueNoise(c, r, 512.0 / double(1 << o), 0x1234 + std::uint64_t(o));
      g.heights[std::size_t(r) * std::size_t(n) + std::size_t(c)] = float(z + rng.uniform(-0.25, 0.25));
    }
  const auto [lo, hi] = std::minmax_element(g.heights.begin(), g.heights.end());
  g.minH = *lo;
  g.maxH = *hi;
  return g;
}

/// The grid, nestwalk's heightfield of it and the peers' structures (built on first use).
struct Terrain {
  HeightGrid grid;
  std::unique_ptr<terrain::Heightfield> hf;
  std::map<std::string, RayPeer> peers;
  std::map<std::string, double> buildSeconds;
  /// The same grid paged (terrain/paged_heightfield.h) from a terrain file and its pyramid written
  /// to a temporary folder on first use (the write not timed; the folder removed after the paged
  /// field, with the terrain); the default tile budget holds it all, so the rows measure a paged
  /// query's own cost once its tiles are read.
  std::unique_ptr<const OutputFolder> pagedFolder;
  std::unique_ptr<terrain::Heightfield> paged;
  const terrain::Heightfield& pagedField() {
    if (!paged) {
      pagedFolder.reset();  // an earlier attempt's folder goes first: the new one has the same path
      pagedFolder = std::make_unique<const OutputFolder>(
          (std::filesystem::temp_directory_path() / "nestwalk-bench-paged").string());
      const std::string path = (std::filesystem::path(pagedFolder->tempPath()) / "grid.tif").string();
      terrain::writeTerrainCog(path, grid.n, grid.n, grid.heights, kOriginX, kOriginY, kSpacing, kSpacing, "EPSG:32633",
                               true);
      buildSeconds["nestwalk_paged_open"] = leastSeconds(1, [&] {
        paged = std::make_unique<terrain::Heightfield>(
            terrain::openPagedHeightfield(std::make_shared<const terrain::TerrainPyramid>(path)));
      });
    }
    return *paged;
  }

  const RayPeer& peer(const std::string& key, RayPeer (*make)(const HeightGrid&)) {
    auto it = peers.find(key);
    if (it == peers.end()) buildSeconds[key] = leastSeconds(1, [&] { it = peers.emplace(key, make(grid)).first; });
    return it->second;
  }
};

// ------------------------------------------------------------------------------------------------
// Ray sets, in the local frame; nestwalk gets the origins in map coordinates.

struct SetSpec {
  const char* key;
  const char* label;
  bool vertical;
  std::uint64_t seed;
};
constexpr SetSpec kSets[] = {
    {"vertical_random", "vertical random", true, 0x76657274'00000001ull},
    {"walking_path", "vertical walking path", true, 0x77616c6b'00000002ull},
    {"oblique", "oblique", false, 0x6f626c69'00000003ull},
};

struct RaySet {
  std::size_t n = 0;
  Rays rays;
  std::vector<Eigen::Vector3d> mapOrigin;  // nestwalk's input
  std::vector<double> reference;           // nestwalk's answers (hit z, NaN on a miss); empty: not yet
};

/// What the run sets, and the data its benchmarks keep for the whole run.
struct Config {
  int grid = 2049;
  std::size_t rays = 1'000'000;
  std::size_t slowRays = 50'000;  // OSG on every set, Bullet on the oblique set
  std::unique_ptr<Terrain> terrain;
  std::map<std::string, RaySet> raySets;
};
Config& config() {
  static Config c;
  return c;
}

Terrain& terrainData() {
  std::unique_ptr<Terrain>& t = config().terrain;
  if (!t || t->grid.n != config().grid) {
    t = std::make_unique<Terrain>();
    t->grid = makeGrid(config().grid);
    t->buildSeconds["nestwalk"] = leastSeconds(1, [&] {
      t->hf = std::make_unique<terrain::Heightfield>(t->grid.n, t->grid.n, t->grid.heights, kOriginX, kOriginY,
                                                     kSpacing, kSpacing);
    });
  }
  return *t;
}

void makeRays(const SetSpec& spec, const Terrain& t, RaySet& s) {
  const HeightGrid& g = t.grid;
  Rays& q = s.rays;
  SplitMix64 rng(spec.seed);
  const double extent = (g.n - 1) * kSpacing;
  const double top = double(g.maxH) + 10.0, bottom = double(g.minH) - 10.0;
  auto vertical = [&](double x, double y) {
    q.origin.push_back({x, y, top});
    q.dir.push_back({0, 0, -1});
    q.tMax.push_back(top - bottom);
  };
  if (std::string(spec.key) == "vertical_random") {
    for (std::size_t k = 0; k < s.n; ++k) {
      const double x = rng.uniform(0, extent);
      vertical(x, -rng.uniform(0, extent));
    }
  } else if (std::string(spec.key) == "walking_path") {
    // A walker 0.1 m per step, heading turning smoothly, turning back 5 m from the edge.
    double x = 0.5 * extent, y = -0.5 * extent, heading = rng.uniform(0, 2 * std::numbers::pi);
    const double margin = std::min(5.0, 0.25 * extent);
    for (std::size_t k = 0; k < s.n; ++k) {
      vertical(x, y);
      heading += 0.02 * rng.gaussian();
      double nx = x + 0.1 * std::cos(heading), ny = y + 0.1 * std::sin(heading);
      if (nx < margin || nx > extent - margin || ny > -margin || ny < -(extent - margin)) {
        heading += std::numbers::pi;
        nx = x + 0.1 * std::cos(heading);
        ny = y + 0.1 * std::sin(heading);
      }
      x = nx;
      y = ny;
    }
  } else {
    for (std::size_t k = 0; k < s.n; ++k) {
      const double x = rng.uniform(0, extent), y = -rng.uniform(0, extent);
      const double z = *t.hf->groundHeight(kOriginX + x, kOriginY + y) + rng.uniform(1.5, 50.0);
      const double az = rng.uniform(0, 2 * std::numbers::pi);
      const double el = rng.uniform(5.0, 60.0) * std::numbers::pi / 180.0;
      q.origin.push_back({x, y, z});
      q.dir.push_back({std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), -std::sin(el)});
      q.tMax.push_back(500.0);
    }
  }
  for (const Eigen::Vector3d& o : q.origin) s.mapOrigin.push_back(o + Eigen::Vector3d(kOriginX, kOriginY, 0));
}

RaySet& raySet(const SetSpec& spec) {
  RaySet& s = config().raySets[spec.key];
  if (s.n != config().rays) {
    s = RaySet{config().rays, {}, {}, {}};
    makeRays(spec, terrainData(), s);
  }
  return s;
}

// ------------------------------------------------------------------------------------------------
// The methods: nestwalk's queries, the direct lookup and the peers, each a pass over a set's rays.

/// Bilinear read of the grid at map (x, y): no triangle logic, no validity checks.
double directLookup(const HeightGrid& g, double x, double y) {
  const double fx = (x - kOriginX) / kSpacing, fy = (kOriginY - y) / kSpacing;
  if (!(fx >= 0 && fy >= 0 && fx <= g.n - 1 && fy <= g.n - 1)) return kNaN;
  const int c = std::min(int(fx), g.n - 2), r = std::min(int(fy), g.n - 2);
  const double u = fx - c, v = fy - r;
  const float* p = &g.heights[std::size_t(r) * std::size_t(g.n) + std::size_t(c)];
  const double top = p[0] + u * (p[1] - p[0]), bottom = p[g.n] + u * (p[g.n + 1] - p[g.n]);
  return top + v * (bottom - top);
}

struct MethodDef {
  const char* key;
  const char* row;    // nestwalk's queries: the row's name and title; null: a peer
  const char* label;
  bool verticalOnly;
  bool prefixVertical, prefixOblique;  // answers only the first slowRays rays of such sets
  Pass<double> (*make)(Terrain& t, const RaySet& s, std::size_t n);
};
template <RayPeer (*make)(const HeightGrid&)>
Pass<double> peerPass(Terrain& t, const RaySet& s, std::size_t n, const char* key) {
  return [&peer = t.peer(key, make), &rays = s.rays, n](double* z) { return peer(rays, n, z); };
}
/// A heightfield's ground heights (groundPass) or first hits (rayPass) for the set's first n rays.
Pass<double> groundPass(const terrain::Heightfield& hf, const RaySet& s, std::size_t n) {
  return [&hf, &s, n](double* z) {
    const terrain::Heightfield& field = hf;  // locals: the loop then keeps them in registers
    const std::vector<Eigen::Vector3d>& at = s.mapOrigin;
    return answerAll(n, z, [&](std::size_t k) { return field.groundHeight(at[k].x(), at[k].y()).value_or(kNaN); });
  };
}
Pass<double> rayPass(const terrain::Heightfield& hf, const RaySet& s, std::size_t n) {
  return [&hf, &s, n](double* z) {
    const terrain::Heightfield& field = hf;
    const RaySet& set = s;
    return answerAll(n, z, [&](std::size_t k) {
      const std::optional<terrain::RayHit> h = field.intersectRay(set.mapOrigin[k], set.rays.dir[k], 0.0, set.rays.tMax[k]);
      return h ? h->point.z() : kNaN;
    });
  };
}
const MethodDef kMethods[] = {
    {"nestwalk_ground_height", "ground_height", "groundHeight", true, false, false,
     [](Terrain& t, const RaySet& s, std::size_t n) { return groundPass(*t.hf, s, n); }},
    {"nestwalk_intersect_ray", "intersect_ray", "intersectRay", false, false, false,
     [](Terrain& t, const RaySet& s, std::size_t n) { return rayPass(*t.hf, s, n); }},
    {"nestwalk_paged_ground_height", "paged_ground_height", "paged ground", true, false, false,
     [](Terrain& t, const RaySet& s, std::size_t n) { return groundPass(t.pagedField(), s, n); }},
    {"nestwalk_paged_intersect_ray", "paged_intersect_ray", "paged ray", false, false, false,
     [](Terrain& t, const RaySet& s, std::size_t n) { return rayPass(t.pagedField(), s, n); }},
    {"direct_lookup", nullptr, nullptr, true, false, false,
     [](Terrain& t, const RaySet& s, std::size_t n) -> Pass<double> {
       return [&g = t.grid, &s, n](double* z) {
         const HeightGrid& grid = g;
         const std::vector<Eigen::Vector3d>& at = s.mapOrigin;
         return answerAll(n, z, [&](std::size_t k) { return directLookup(grid, at[k].x(), at[k].y()); });
       };
     }},
    {"embree", nullptr, nullptr, false, false, false,
     [](Terrain& t, const RaySet& s, std::size_t n) { return peerPass<embreeTerrain>(t, s, n, "embree"); }},
    // Bullet walks every cell under an oblique ray (~14 us per 500 m ray): fewer rays there.
    {"bullet", nullptr, nullptr, false, false, true,
     [](Terrain& t, const RaySet& s, std::size_t n) { return peerPass<bulletTerrain>(t, s, n, "bullet"); }},
    {"osg_kdtree", nullptr, nullptr, false, true, true,
     [](Terrain& t, const RaySet& s, std::size_t n) { return peerPass<osgTerrain>(t, s, n, "osg_kdtree"); }},
};
const MethodDef& method(const std::string& key) {
  return *std::find_if(std::begin(kMethods), std::end(kMethods), [&](const MethodDef& m) { return key == m.key; });
}

/// The method whose answers are the set's reference.
const char* referenceMethod(const SetSpec& spec) {
  return spec.vertical ? "nestwalk_ground_height" : "nestwalk_intersect_ray";
}

/// The facts of a method's answers z (hit heights, NaN on a miss), against the set's reference
/// unless the method is the reference.
void judge(const SetSpec& spec, RaySet& s, const MethodDef& m, const std::vector<double>& z, Facts& facts) {
  const std::size_t n = z.size();
  std::size_t hits = 0, differ = 0, far = 0;
  double maxDiff = 0;
  const bool compared = std::string(m.key) != referenceMethod(spec);
  if (compared && s.reference.empty()) {
    s.reference.resize(s.n);
    method(referenceMethod(spec)).make(terrainData(), s, s.n)(s.reference.data());
  }
  for (std::size_t k = 0; k < n; ++k) {
    const bool hit = !std::isnan(z[k]);
    hits += hit ? 1 : 0;
    if (!compared) continue;
    if (hit != !std::isnan(s.reference[k])) {
      ++differ;
    } else if (hit) {
      maxDiff = std::max(maxDiff, std::abs(z[k] - s.reference[k]));
      far += std::abs(z[k] - s.reference[k]) > kFarHit ? 1 : 0;
    }
  }
  facts["rays"] = double(n);
  facts["hit_fraction"] = double(hits) / double(n);
  if (!compared) return;
  facts["disagreements"] = double(differ);
  facts["max_height_diff"] = maxDiff;
  facts["hits_over_1cm_apart"] = double(far);
}

Suite& suite() { return Suite::named("terrain"); }

/// Registers every method on every set it answers.
void registerBenchmarks() {
  suite().addEach(
      kSets, kMethods, [](const SetSpec& set, const MethodDef& m) { return set.vertical || !m.verticalOnly; },
      [](const SetSpec& set, const MethodDef& m, benchmark::State& state, Facts& facts) {
        Terrain& t = terrainData();
        RaySet& s = raySet(set);
        const bool prefix = set.vertical ? m.prefixVertical : m.prefixOblique;
        const std::size_t n = prefix ? std::min(s.n, config().slowRays) : s.n;
        timePasses<double>(state, facts, n, m.make(t, s, n),
                           [&](const std::vector<double>& z, Facts& f) { judge(set, s, m, z, f); });
      });
}

// ------------------------------------------------------------------------------------------------
// The output.

const std::vector<Peer> kPeers = {
    {"direct_lookup", "direct"}, {"embree", "Embree"}, {"bullet", "Bullet"}, {"osg_kdtree", "OSG kd"}};

/// The row of nestwalk's query m on `set`: hit fraction, ns per ray and the agreement of nestwalk
/// and each peer (a peer's method key is its key in the row).
Json makeRow(const MethodDef& method, const SetSpec& set) {
  const Suite& s = suite();
  Json row = {{"name", std::string(method.row) + "/" + set.key}, {"test", method.label}, {"set", set.label}};
  double hitFraction = s.fact(method.key, set.key, "hit_fraction");
  for (const Peer& p : kPeers)
    if (std::isnan(hitFraction)) hitFraction = s.fact(p.key, set.key, "hit_fraction");
  row["hit_fraction"] = jsonNumber(hitFraction);
  std::vector<std::pair<std::string, std::string>> methods = {{"nestwalk", method.key}};
  for (const Peer& p : kPeers) methods.emplace_back(p.key, p.key);
  for (const auto& [key, m] : methods) {
    row["ns_per_ray"][key] = jsonNumber(s.ns(m, set.key));
    row["hit_fractions"][key] = jsonNumber(s.fact(m, set.key, "hit_fraction"));
    row["disagreements"][key] = countJson(s.fact(m, set.key, "disagreements"));
    row["max_height_diff"][key] = jsonNumber(s.fact(m, set.key, "max_height_diff"));
    row["hits_over_1cm_apart"][key] = countJson(s.fact(m, set.key, "hits_over_1cm_apart"));
    row["rays"][key] = countJson(s.fact(m, set.key, "rays"));
  }
  return row;
}

/// Per set, the agreement of intersectRay and the peers with nestwalk's reference.
void printAgreement(std::ostream& out, const Table& table) {
  out << "\nagreement with nestwalk (groundHeight on vertical sets, intersectRay on oblique), counted outside the"
         " timed loops: hit/miss disagreements / max |hit height difference| in m / hits more than 1 cm apart"
         " (direct is bilinear, not the triangles; the float peers differ by rounding, which on grazing oblique"
         " rays can move a hit past a ridge)\n";
  for (const Json& r : table.rows()) {
    if (r["name"].get<std::string>().rfind("ground_height/", 0) == 0) continue;  // the peers' figures are the same
    std::string line;
    auto add = [&](const std::string& key, const std::string& title) {
      if (!r["disagreements"][key].is_number()) return;
      line += (line.empty() ? " " : ", ") + title + " " + r["disagreements"][key].dump() + " / " +
              shortText(r["max_height_diff"][key].get<double>());
      if (key != "nestwalk")
        line += " / " + r["hits_over_1cm_apart"][key].dump() + " (" + r["rays"][key].dump() + " rays)";
    };
    add("nestwalk", "intersectRay");
    for (const Peer& p : kPeers) add(p.key, p.title);
    out << "  " << std::left << std::setw(23) << r["set"].get<std::string>() << std::right << line << "\n";
  }
}

void addTargets(Document& doc, const Table& table) {
  for (const Json& r : table.rows()) {
    const std::string name = r["name"].get<std::string>(), set = name.substr(name.find('/') + 1);
    const Json& ratio = r["ratio"];
    if (name.rfind("ground_height/", 0) == 0) {
      const Json& direct = ratio["direct_lookup"];  // direct / nestwalk: the target is its inverse
      doc.target("ground_height_vs_direct/" + set, "nestwalk / direct",
                 direct.is_number() ? Json(1.0 / direct.get<double>()) : Json(), "<=", kGroundVsDirect);
      doc.target("ground_height_vs_embree/" + set, "Embree / nestwalk", ratio["embree"], ">=", kGroundVsEmbree);
    }
    if (name == "intersect_ray/oblique")
      doc.target("oblique_vs_embree", "Embree / nestwalk", ratio["embree"], ">=", kObliqueVsEmbree);
  }
}

/// The chunk quadtree's levels for the benchmark grid (outside any timing).
void printLevels(Document& doc, const Terrain& t) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<terrain::ChunkLevelStats> levels =
      terrain::chunkLevelTable(*t.hf, terrain::ChunkLayout(t.hf->cols(), t.hf->rows(), kLevelChunkCells));
  Table table;
  table.column({"level", "/level", 5, 0})
      .column({"step", "/step", 7, 0})
      .column({"chunks", "/chunks", 8, 0})
      .column({"triangles", "/triangles", 13, 0})
      .column({"max error (m)", "/max_error_m", 16, 4});
  for (const terrain::ChunkLevelStats& l : levels)
    table.add({{"level", l.level},
               {"step", l.step},
               {"chunks", l.chunks},
               {"triangles", l.triangles},
               {"max_error_m", l.maxError}});
  doc.text << "\nchunk quadtree levels (chunks of " << kLevelChunkCells
           << " cells, each level's grid; error = exact max vertical error vs full resolution, " << fixedText(secondsSince(t0), 2)
           << " s to compute):\n";
  doc.table("lod_levels", table, "  ");
}

}  // namespace

int runBenchmark(const TerrainBenchOptions& opts, std::ostream& out) {
  Config& c = config();
  c.grid = opts.orDefault(opts.gridSamples, 257, 2049);
  c.rays = opts.orDefault(opts.rays, 20'000, 1'000'000);
  c.slowRays = std::min<std::size_t>(opts.slowRays ? opts.slowRays : 50'000, c.rays);
  const double minTime = opts.minTime(0.5);
  registerBenchmarks();
  const ReleaseAtEnd release([] {  // the terrain, the peers' structures and the rays: a few GB at full size
    config().raySets.clear();
    config().terrain.reset();
  });
  Suite& s = suite();
  if (const std::optional<int> rc = s.run(opts, minTime, "^terrain/", out)) return *rc;

  Table table = Table::againstPeers({"query", "/test", 14, 0, true}, {"set", "/set", 23, 0, true},
                                    {{"hits", "/hit_fraction", 7, 3}}, "ns_per_ray", kPeers, 10, 1, 2);
  for (const SetSpec& set : kSets)
    for (const MethodDef& m : kMethods)
      if (m.row && (set.vertical || !m.verticalOnly)) table.addMeasured(makeRow(m, set), "ns_per_ray");

  const Terrain& t = terrainData();
  const std::size_t triangles = 2 * std::size_t(t.grid.n - 1) * std::size_t(t.grid.n - 1);
  Document doc("nestwalk bench terrain: ns per ray (CPU time);"
               " ratio = peer ns / nestwalk ns (> 1: nestwalk faster)");
  doc.errors = s.errors();
  Json& m = doc.json["machine"];
  m["grid_samples"] = t.grid.n;
  m["triangles"] = triangles;
  m["rays_per_set"] = c.rays;
  m["slow_peer_rays_per_set"] = c.slowRays;
  m["build_seconds"] = t.buildSeconds;
  doc.text << "grid: " << t.grid.n << " x " << t.grid.n << " samples at " << kSpacing << " m (" << triangles
           << " triangles), heights " << fixedText(t.grid.minH, 1) << " .. " << fixedText(t.grid.maxH, 1) << " m\n"
           << "rays per set: " << c.rays << " (OSG, and Bullet on oblique rays: the first " << c.slowRays << "); "
           << doc.runSettings(minTime, opts.quick, s.repetitions()) << "\n"
           << "peers: direct = bilinear grid read; Embree " << m["libraries"]["embree"].get<std::string>()
           << " rtcIntersect1 (float); Bullet " << m["libraries"]["bullet"].get<std::string>()
           << " btHeightfieldTerrainShape::performRaycast (no accelerator); OSG "
           << m["libraries"]["openscenegraph"].get<std::string>() << " LineSegmentIntersector + KdTree\n"
           << "build times (s):";
  for (const auto& [key, seconds] : t.buildSeconds) doc.text << " " << key << " " << fixedText(seconds, 2);
  doc.text << "\n\n";
  doc.table("benchmarks", table);
  printAgreement(doc.text, table);
  printLevels(doc, t);
  addTargets(doc, table);
  return doc.write(out, opts.json);
}

}  // namespace nestwalk::bench
