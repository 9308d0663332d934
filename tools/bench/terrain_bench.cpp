// The terrain benchmark (see terrain_bench.h).
//
// Every benchmark answers its whole ray set (or OSG's prefix of it) once per Google Benchmark
// iteration and sums the answers (benchmark::DoNotOptimize on the sum), with
// SetItemsProcessed(iterations * rays), so ns/ray = 1e9 / items_per_second. The DEM and the ray
// sets are generated once from fixed seeds (splitmix64) and kept for the whole run; each peer's
// structure (Embree scene, Bullet shape, OSG KdTree) is built on first use, outside the timed
// loops, and its build time is reported. nestwalk is given map coordinates (a UTM-like origin), the
// peers the heightfield's local frame as float (their native precision). Hit fractions,
// disagreements with nestwalk (hit/miss) and the largest |height difference| of the hit points are
// counted once per benchmark outside the timed loop.
#include "tools/bench/terrain_bench.h"

#include "tools/bench/bench_runner.h"

#include "nestwalk/terrain/heightfield.h"
#include "nestwalk/terrain/terrain_mesh.h"

#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>
#include <nlohmann/json.hpp>

#include <BulletCollision/CollisionShapes/btHeightfieldTerrainShape.h>
#include <BulletCollision/NarrowPhaseCollision/btRaycastCallback.h>
#include <LinearMath/btScalar.h>

#include <osg/Geode>
#include <osg/Geometry>
#include <osg/KdTree>
#include <osg/Version>
#include <osgUtil/IntersectionVisitor>
#include <osgUtil/LineSegmentIntersector>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
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

using Json = nlohmann::ordered_json;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kOriginX = 500000.0, kOriginY = 5200000.0;  // map coordinates of sample (0, 0)
constexpr double kSpacing = 1.0;                             // metres, both directions

struct Config {
  int grid = 2049;
  std::size_t rays = 1'000'000;
  std::size_t slowRays = 50'000;  // OSG on every set, Bullet on the oblique set
  double minTime = 0.5;
};
Config& config() {
  static Config c;
  return c;
}

using Rng = SplitMix64;  // splitmix64 (bench_runner.h)

std::uint64_t hash2(std::int64_t x, std::int64_t y, std::uint64_t seed) {
  Rng r(seed ^ (std::uint64_t(x) * 0x9E3779B97F4A7C15ull) ^ (std::uint64_t(y) * 0xC2B2AE3D27D4EB4Full));
  return r.next();
}

/// Value noise in [-1, 1] with smoothstep interpolation on a lattice of `wavelength` samples.
double valueNoise(double x, double y, double wavelength, std::uint64_t seed) {
  const double fx = x / wavelength, fy = y / wavelength;
  const double ix = std::floor(fx), iy = std::floor(fy);
  const double u = fx - ix, v = fy - iy;
  const double su = u * u * (3 - 2 * u), sv = v * v * (3 - 2 * v);
  auto at = [&](double a, double b) {
    return double(hash2(std::int64_t(a), std::int64_t(b), seed) >> 11) * 0x1.0p-52 - 1.0;
  };
  const double a = at(ix, iy), b = at(ix + 1, iy), c = at(ix, iy + 1), d = at(ix + 1, iy + 1);
  return (a * (1 - su) + b * su) * (1 - sv) + (c * (1 - su) + d * su) * sv;
}

/// The rough DEM: fBm (wavelengths 512 m down to 4 m, amplitude halving) plus +-0.25 m per sample.
std::vector<float> makeDem(int n) {
  std::vector<float> h(std::size_t(n) * std::size_t(n));
  Rng rng(0x7465727261696eull);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      double z = 300.0, amp = 120.0;
      for (int o = 0; o < 8; ++o, amp *= 0.5)
        z += amp * valueNoise(c, r, 512.0 / double(1 << o), 0x1234 + std::uint64_t(o));
      z += rng.uniform(-0.25, 0.25);
      h[std::size_t(r) * std::size_t(n) + std::size_t(c)] = float(z);
    }
  return h;
}

// ------------------------------------------------------------------------------------------------
// The terrain and its peers' structures.

struct EmbreeScene {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~EmbreeScene() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

struct BulletTerrain {
  std::vector<float> data;  // rows reversed: Bullet's row j is our row rows-1-j
  std::unique_ptr<btHeightfieldTerrainShape> shape;
  btVector3 offset;  // bullet local = our local + offset
};

struct OsgTerrain {
  osg::ref_ptr<osg::Geode> geode;
};

struct Terrain {
  int n = 0;
  std::vector<float> heights;
  float minH = 0, maxH = 0;
  std::unique_ptr<terrain::Heightfield> hf;
  std::unique_ptr<EmbreeScene> embree;
  std::unique_ptr<BulletTerrain> bullet;
  std::unique_ptr<OsgTerrain> osg;
  std::map<std::string, double> buildSeconds;
  std::vector<terrain::TerrainLevelStats> lod;
  double lodSeconds = 0;

  double local(int c, int r) const { return heights[std::size_t(r) * std::size_t(n) + std::size_t(c)]; }
  /// The triangulated surface at local (x, y) (the heightfield's rule), for generating rays.
  double surface(double x, double y) const {
    const double fx = x / kSpacing, fy = -y / kSpacing;
    const int c = std::clamp(int(fx), 0, n - 2), r = std::clamp(int(fy), 0, n - 2);
    const double u = fx - c, v = fy - r;
    const double a = local(c, r), b = local(c + 1, r), cc = local(c + 1, r + 1), d = local(c, r + 1);
    return u >= v ? a + u * (b - a) + v * (cc - b) : a + v * (d - a) + u * (cc - d);
  }
};

std::unique_ptr<Terrain>& currentTerrain() {
  static std::unique_ptr<Terrain> t;
  return t;
}

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Terrain& terrainData() {
  std::unique_ptr<Terrain>& t = currentTerrain();
  if (!t || t->n != config().grid) {
    t.reset();
    t = std::make_unique<Terrain>();
    t->n = config().grid;
    t->heights = makeDem(t->n);
    const auto [lo, hi] = std::minmax_element(t->heights.begin(), t->heights.end());
    t->minH = *lo;
    t->maxH = *hi;
    const auto t0 = std::chrono::steady_clock::now();
    t->hf = std::make_unique<terrain::Heightfield>(t->n, t->n, t->heights, kOriginX, kOriginY, kSpacing, kSpacing);
    t->buildSeconds["nestwalk"] = secondsSince(t0);
  }
  return *t;
}

void needEmbree(Terrain& t) {
  if (t.embree) return;
  const auto t0 = std::chrono::steady_clock::now();
  auto e = std::make_unique<EmbreeScene>();
  e->device = rtcNewDevice(nullptr);
  e->scene = rtcNewScene(e->device);
  RTCGeometry geom = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  const int n = t.n;
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                         3 * sizeof(float), std::size_t(n) * std::size_t(n)));
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      float* p = v + 3 * (std::size_t(r) * std::size_t(n) + std::size_t(c));
      p[0] = float(c * kSpacing);
      p[1] = float(-r * kSpacing);
      p[2] = t.heights[std::size_t(r) * std::size_t(n) + std::size_t(c)];
    }
  const std::size_t tris = 2 * std::size_t(n - 1) * std::size_t(n - 1);
  auto* idx = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), tris));
  std::size_t k = 0;
  for (int r = 0; r + 1 < n; ++r)
    for (int c = 0; c + 1 < n; ++c) {
      const unsigned a = unsigned(r * n + c), b = a + 1, cc = unsigned((r + 1) * n + c + 1), d = unsigned((r + 1) * n + c);
      idx[k++] = a, idx[k++] = b, idx[k++] = cc;  // upper
      idx[k++] = a, idx[k++] = cc, idx[k++] = d;  // lower
    }
  rtcCommitGeometry(geom);
  rtcAttachGeometry(e->scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(e->scene);
  t.embree = std::move(e);
  t.buildSeconds["embree"] = secondsSince(t0);
}

void needBullet(Terrain& t) {
  if (t.bullet) return;
  const auto t0 = std::chrono::steady_clock::now();
  auto b = std::make_unique<BulletTerrain>();
  const int n = t.n;
  b->data.resize(t.heights.size());
  for (int r = 0; r < n; ++r)
    std::copy_n(t.heights.begin() + std::ptrdiff_t(r) * n, n, b->data.begin() + std::ptrdiff_t(n - 1 - r) * n);
  // Bullet's default split of its cell (x, j) is the diagonal (x, j+1)-(x+1, j); with the rows
  // reversed that is our (c, r)-(c+1, r+1): the same triangles.
  b->shape = std::make_unique<btHeightfieldTerrainShape>(n, n, b->data.data(), btScalar(t.minH), btScalar(t.maxH), 2,
                                                         false);
  b->shape->setLocalScaling(btVector3(btScalar(kSpacing), btScalar(kSpacing), 1));
  // No buildAccelerator(): with Bullet 3.24's accelerator (vertical-bounds chunks) about a third of
  // the oblique rays here missed the surface or hit it metres away from the other peers; without
  // it performRaycast walks the cells under the ray (a 2D DDA) and agrees with everyone.
  b->offset = btVector3(btScalar(-0.5 * (n - 1) * kSpacing), btScalar(0.5 * (n - 1) * kSpacing),
                        btScalar(-0.5 * (double(t.minH) + double(t.maxH))));
  t.bullet = std::move(b);
  t.buildSeconds["bullet"] = secondsSince(t0);
}

void needOsg(Terrain& t) {
  if (t.osg) return;
  const auto t0 = std::chrono::steady_clock::now();
  const int n = t.n;
  osg::ref_ptr<osg::Vec3Array> v = new osg::Vec3Array;
  v->reserve(std::size_t(n) * std::size_t(n));
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c)
      v->push_back(osg::Vec3(float(c * kSpacing), float(-r * kSpacing), t.heights[std::size_t(r) * std::size_t(n) + std::size_t(c)]));
  osg::ref_ptr<osg::DrawElementsUInt> e = new osg::DrawElementsUInt(GL_TRIANGLES);
  e->reserve(6 * std::size_t(n - 1) * std::size_t(n - 1));
  for (int r = 0; r + 1 < n; ++r)
    for (int c = 0; c + 1 < n; ++c) {
      const unsigned a = unsigned(r * n + c), b = a + 1, cc = unsigned((r + 1) * n + c + 1), d = unsigned((r + 1) * n + c);
      for (unsigned i : {a, cc, b, a, d, cc}) e->push_back(i);  // counter-clockwise from above
    }
  osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
  g->setVertexArray(v.get());
  g->addPrimitiveSet(e.get());
  auto o = std::make_unique<OsgTerrain>();
  o->geode = new osg::Geode;
  o->geode->addDrawable(g.get());
  osg::ref_ptr<osg::KdTreeBuilder> builder = new osg::KdTreeBuilder;
  o->geode->accept(*builder);
  t.osg = std::move(o);
  t.buildSeconds["osg_kdtree"] = secondsSince(t0);
}

// ------------------------------------------------------------------------------------------------
// Ray sets. Local frame rays (double); nestwalk gets origin + (kOriginX, kOriginY, 0).

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
  const SetSpec* spec = nullptr;
  std::size_t n = 0;
  std::vector<Eigen::Vector3d> origin, dir;  // local frame, direction unit
  std::vector<double> tMax;
  std::vector<Eigen::Vector3d> mapOrigin;    // nestwalk's input
  // Reference: nestwalk's answers (hit z, NaN on a miss), computed once.
  std::vector<double> reference;
  bool haveReference = false;
};

std::map<std::string, std::unique_ptr<RaySet>>& raySets() {
  static std::map<std::string, std::unique_ptr<RaySet>> s;
  return s;
}

RaySet& raySet(const SetSpec& spec) {
  Terrain& t = terrainData();
  auto& sets = raySets();
  std::unique_ptr<RaySet>& s = sets[spec.key];
  if (s && s->n == config().rays) return *s;
  s = std::make_unique<RaySet>();
  s->spec = &spec;
  const std::size_t n = config().rays;
  s->n = n;
  s->origin.resize(n);
  s->dir.resize(n);
  s->tMax.resize(n);
  Rng rng(spec.seed);
  const double extent = (t.n - 1) * kSpacing;
  const double top = double(t.maxH) + 10.0, bottom = double(t.minH) - 10.0;
  if (std::string(spec.key) == "vertical_random") {
    for (std::size_t k = 0; k < n; ++k) {
      s->origin[k] = {rng.uniform(0, extent), -rng.uniform(0, extent), top};
      s->dir[k] = {0, 0, -1};
      s->tMax[k] = top - bottom;
    }
  } else if (std::string(spec.key) == "walking_path") {
    // A walker 0.1 m per step, heading turning smoothly, turning back 5 m from the edge.
    double x = 0.5 * extent, y = -0.5 * extent, heading = rng.uniform(0, 2 * std::numbers::pi);
    const double margin = std::min(5.0, 0.25 * extent);
    for (std::size_t k = 0; k < n; ++k) {
      s->origin[k] = {x, y, top};
      s->dir[k] = {0, 0, -1};
      s->tMax[k] = top - bottom;
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
    for (std::size_t k = 0; k < n; ++k) {
      const double x = rng.uniform(0, extent), y = -rng.uniform(0, extent);
      const double z = t.surface(x, y) + rng.uniform(1.5, 50.0);
      const double az = rng.uniform(0, 2 * std::numbers::pi);
      const double el = rng.uniform(5.0, 60.0) * std::numbers::pi / 180.0;
      s->origin[k] = {x, y, z};
      s->dir[k] = {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), -std::sin(el)};
      s->tMax[k] = 500.0;
    }
  }
  s->mapOrigin.resize(n);
  for (std::size_t k = 0; k < n; ++k) s->mapOrigin[k] = s->origin[k] + Eigen::Vector3d(kOriginX, kOriginY, 0);
  return *s;
}

/// nestwalk's answers: groundHeight for vertical sets, intersectRay's hit z for oblique.
void needReference(RaySet& s) {
  if (s.haveReference) return;
  const terrain::Heightfield& hf = *terrainData().hf;
  s.reference.resize(s.n);
  for (std::size_t k = 0; k < s.n; ++k) {
    if (s.spec->vertical) {
      const std::optional<double> g = hf.groundHeight(s.mapOrigin[k].x(), s.mapOrigin[k].y());
      s.reference[k] = g ? *g : kNaN;
    } else {
      const std::optional<terrain::RayHit> h = hf.intersectRay(s.mapOrigin[k], s.dir[k], 0.0, s.tMax[k]);
      s.reference[k] = h ? h->point.z() : kNaN;
    }
  }
  s.haveReference = true;
}

// ------------------------------------------------------------------------------------------------
// Facts, counted once per benchmark outside the timed loop.

struct Facts {
  std::size_t rays = 0;
  double hitFraction = kNaN;
  long long disagreements = -1;  // hit/miss differences with nestwalk's reference
  double maxHeightDiff = kNaN;   // max |z - reference z| where both hit
  long long farHits = -1;        // hits on both sides more than 1 cm apart in height
};

std::map<std::string, Facts>& facts() {
  static std::map<std::string, Facts> f;
  return f;
}

/// answer(k): hit z or NaN.
template <class F>
Facts countFacts(RaySet& s, std::size_t n, bool compare, F&& answer) {
  Facts f;
  f.rays = n;
  if (compare) needReference(s);
  std::size_t hits = 0, differ = 0, far = 0;
  double maxDiff = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double z = answer(k);
    const bool hit = !std::isnan(z);
    hits += hit ? 1 : 0;
    if (!compare) continue;
    const double ref = s.reference[k];
    if (hit != !std::isnan(ref)) {
      ++differ;
    } else if (hit) {
      maxDiff = std::max(maxDiff, std::abs(z - ref));
      far += std::abs(z - ref) > 0.01 ? 1 : 0;
    }
  }
  f.hitFraction = double(hits) / double(n);
  if (compare) {
    f.disagreements = static_cast<long long>(differ);
    f.maxHeightDiff = maxDiff;
    f.farHits = static_cast<long long>(far);
  }
  return f;
}

void publish(benchmark::State& state, const Facts& f) {
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(f.rays));
  state.counters["time_per_ray"] =
      benchmark::Counter(double(f.rays), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["hit_fraction"] = f.hitFraction;
  if (f.disagreements >= 0) state.counters["disagreements"] = double(f.disagreements);
  if (!std::isnan(f.maxHeightDiff)) state.counters["max_height_diff"] = f.maxHeightDiff;
}

template <class F>
void rayBenchmark(benchmark::State& state, const std::string& name, RaySet& s, std::size_t n, bool compare,
                  F&& answer) {
  auto& cache = facts();
  auto it = cache.find(name);
  if (it == cache.end()) it = cache.emplace(name, countFacts(s, n, compare, answer)).first;
  for (auto _ : state) {
    double sum = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const double z = answer(k);
      sum += std::isnan(z) ? 0.0 : z;
    }
    benchmark::DoNotOptimize(sum);
  }
  publish(state, it->second);
}

// ------------------------------------------------------------------------------------------------
// The answers.

/// Bilinear read of the grid at map (x, y): no triangle logic, no validity checks.
struct DirectLookup {
  const float* h;
  int n;
  double inv = 1.0 / kSpacing;
  double operator()(double x, double y) const {
    const double fx = (x - kOriginX) * inv, fy = (kOriginY - y) * inv;
    if (!(fx >= 0 && fy >= 0 && fx <= n - 1 && fy <= n - 1)) return kNaN;
    const int c = std::min(int(fx), n - 2), r = std::min(int(fy), n - 2);
    const double u = fx - c, v = fy - r;
    const float* p = h + std::size_t(r) * std::size_t(n) + std::size_t(c);
    const double top = p[0] + u * (p[1] - p[0]), bot = p[n] + u * (p[n + 1] - p[n]);
    return top + v * (bot - top);
  }
};

struct EmbreeRays {
  RTCScene scene;
  RTCIntersectContext ctx;
  explicit EmbreeRays(RTCScene s) : scene(s) { rtcInitIntersectContext(&ctx); }
  double operator()(const RaySet& s, std::size_t k) {
    RTCRayHit rh;
    rh.ray.org_x = float(s.origin[k].x());
    rh.ray.org_y = float(s.origin[k].y());
    rh.ray.org_z = float(s.origin[k].z());
    rh.ray.dir_x = float(s.dir[k].x());
    rh.ray.dir_y = float(s.dir[k].y());
    rh.ray.dir_z = float(s.dir[k].z());
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = float(s.tMax[k]);
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.time = 0.0f;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return kNaN;
    return double(rh.ray.org_z) + double(rh.ray.tfar) * double(rh.ray.dir_z);
  }
};

/// Keeps the nearest hit (btTriangleRaycastCallback only reports hits nearer than m_hitFraction).
struct BulletNearest : btTriangleRaycastCallback {
  BulletNearest(const btVector3& from, const btVector3& to) : btTriangleRaycastCallback(from, to, 0) {}
  btScalar reportHit(const btVector3&, btScalar hitFraction, int, int) override { return hitFraction; }
};

struct BulletRays {
  std::vector<btVector3> from, to;  // Bullet's local frame
  const btHeightfieldTerrainShape* shape;
  double zShift;
  BulletRays(const BulletTerrain& b, const RaySet& s, std::size_t n) : shape(b.shape.get()) {
    from.reserve(n);
    to.reserve(n);
    for (std::size_t k = 0; k < n; ++k) {
      const Eigen::Vector3d e = s.origin[k] + s.tMax[k] * s.dir[k];
      from.push_back(btVector3(btScalar(s.origin[k].x()), btScalar(s.origin[k].y()), btScalar(s.origin[k].z())) +
                     b.offset);
      to.push_back(btVector3(btScalar(e.x()), btScalar(e.y()), btScalar(e.z())) + b.offset);
    }
    zShift = -double(b.offset.z());
  }
  double operator()(std::size_t k) const {
    BulletNearest cb(from[k], to[k]);
    shape->performRaycast(&cb, from[k], to[k]);
    if (!(cb.m_hitFraction < 1)) return kNaN;
    const double f = cb.m_hitFraction;
    return double(from[k].z()) + f * (double(to[k].z()) - double(from[k].z())) + zShift;
  }
};

double osgRay(osg::Node& node, const RaySet& s, std::size_t k) {
  const Eigen::Vector3d e = s.origin[k] + s.tMax[k] * s.dir[k];
  osg::ref_ptr<osgUtil::LineSegmentIntersector> lsi = new osgUtil::LineSegmentIntersector(
      osg::Vec3d(s.origin[k].x(), s.origin[k].y(), s.origin[k].z()), osg::Vec3d(e.x(), e.y(), e.z()));
  lsi->setIntersectionLimit(osgUtil::Intersector::LIMIT_NEAREST);
  osgUtil::IntersectionVisitor iv(lsi.get());
  node.accept(iv);
  if (!lsi->containsIntersections()) return kNaN;
  return lsi->getFirstIntersection().getWorldIntersectPoint().z();
}

// ------------------------------------------------------------------------------------------------
// Registration.

std::string benchName(const char* method, const char* set) { return std::string("terrain/") + method + "/" + set; }

std::vector<benchmark::internal::Benchmark*>& registered() {
  static std::vector<benchmark::internal::Benchmark*> r;
  return r;
}

void registerSet(const SetSpec& spec) {
  const SetSpec* sp = &spec;
  auto add = [&](const char* method, auto&& fn) {
    const std::string name = benchName(method, spec.key);
    registered().push_back(
        benchmark::RegisterBenchmark(name.c_str(), [name, fn](benchmark::State& st) { fn(st, name); }));
  };
  if (spec.vertical) {
    add("nestwalk_ground_height", [sp](benchmark::State& st, const std::string& name) {
      RaySet& s = raySet(*sp);
      const terrain::Heightfield& hf = *terrainData().hf;
      rayBenchmark(st, name, s, s.n, false, [&](std::size_t k) {
        const std::optional<double> g = hf.groundHeight(s.mapOrigin[k].x(), s.mapOrigin[k].y());
        return g ? *g : kNaN;
      });
    });
  }
  add("nestwalk_intersect_ray", [sp](benchmark::State& st, const std::string& name) {
    RaySet& s = raySet(*sp);
    const terrain::Heightfield& hf = *terrainData().hf;
    rayBenchmark(st, name, s, s.n, sp->vertical, [&](std::size_t k) {
      const std::optional<terrain::RayHit> h = hf.intersectRay(s.mapOrigin[k], s.dir[k], 0.0, s.tMax[k]);
      return h ? h->point.z() : kNaN;
    });
  });
  if (spec.vertical) {
    add("direct_lookup", [sp](benchmark::State& st, const std::string& name) {
      RaySet& s = raySet(*sp);
      Terrain& t = terrainData();
      const DirectLookup look{t.heights.data(), t.n};
      rayBenchmark(st, name, s, s.n, true,
                   [&](std::size_t k) { return look(s.mapOrigin[k].x(), s.mapOrigin[k].y()); });
    });
  }
  add("embree", [sp](benchmark::State& st, const std::string& name) {
    RaySet& s = raySet(*sp);
    Terrain& t = terrainData();
    needEmbree(t);
    EmbreeRays e(t.embree->scene);
    rayBenchmark(st, name, s, s.n, true, [&](std::size_t k) { return e(s, k); });
  });
  add("bullet", [sp](benchmark::State& st, const std::string& name) {
    RaySet& s = raySet(*sp);
    Terrain& t = terrainData();
    needBullet(t);
    // Bullet walks every cell under an oblique ray (~14 us per 500 m ray): fewer rays there.
    const std::size_t n = sp->vertical ? s.n : std::min(s.n, config().slowRays);
    const BulletRays b(*t.bullet, s, n);
    rayBenchmark(st, name, s, n, true, [&](std::size_t k) { return b(k); });
  });
  add("osg_kdtree", [sp](benchmark::State& st, const std::string& name) {
    RaySet& s = raySet(*sp);
    Terrain& t = terrainData();
    needOsg(t);
    osg::Node& node = *t.osg->geode;
    rayBenchmark(st, name, s, std::min(s.n, config().slowRays), true,
                 [&](std::size_t k) { return osgRay(node, s, k); });
  });
}

// ------------------------------------------------------------------------------------------------
// The table (the collecting reporter is in bench_runner.h).


constexpr int kPeers = 4;
constexpr const char* kPeerMethods[kPeers] = {"direct_lookup", "embree", "bullet", "osg_kdtree"};
constexpr const char* kPeerKeys[kPeers] = {"direct_lookup", "embree", "bullet", "osg_kdtree"};
constexpr const char* kPeerTitles[kPeers] = {"direct", "Embree", "Bullet", "OSG kd"};

struct RowDef {
  const char* key;
  const char* label;
  const char* nestwalk;
};
constexpr RowDef kRows[] = {
    {"ground_height", "groundHeight", "nestwalk_ground_height"},
    {"intersect_ray", "intersectRay", "nestwalk_intersect_ray"},
};

struct Row {
  std::string name, label, set;
  double nestwalk = kNaN;
  double peer[kPeers] = {kNaN, kNaN, kNaN, kNaN};
  double hitFraction = kNaN;
  long long nestwalkDisagreements = -1;
  double nestwalkMaxDiff = kNaN;
  long long peerDisagreements[kPeers] = {-1, -1, -1, -1};
  double peerMaxDiff[kPeers] = {kNaN, kNaN, kNaN, kNaN};
  long long peerFarHits[kPeers] = {-1, -1, -1, -1};
  std::size_t peerRays[kPeers] = {0, 0, 0, 0};
};

const Facts* factsOf(const std::string& bench) {
  const auto it = facts().find(bench);
  return it == facts().end() ? nullptr : &it->second;
}

std::string fmtSci(double v) {
  if (std::isnan(v)) return "-";
  std::ostringstream s;
  s << std::setprecision(3) << v;
  return s.str();
}


}  // namespace

// ------------------------------------------------------------------------------------------------

void registerTerrainBenchmarks(const TerrainBenchOptions& opts) {
  Config& c = config();
  c.grid = opts.gridSamples > 0 ? opts.gridSamples : (opts.quick ? 257 : 2049);
  c.rays = opts.rays ? opts.rays : (opts.quick ? 20'000 : 1'000'000);
  c.slowRays = opts.slowRays ? std::min(opts.slowRays, c.rays) : std::min<std::size_t>(c.rays, 50'000);
  c.minTime = opts.minTimeSeconds > 0 ? opts.minTimeSeconds : (opts.quick ? 0.02 : 0.5);
  if (registered().empty())
    for (const auto& s : kSets) registerSet(s);
  configureBenchmarks(registered(), c.minTime, opts.repetitions);
}

int runTerrainBench(const TerrainBenchOptions& opts, std::ostream& out) {
  registerTerrainBenchmarks(opts);
  // Free the terrain, the peers' structures and the rays (a few GB at full size) on the way out.
  struct Release {
    ~Release() {
      raySets().clear();
      currentTerrain().reset();
    }
  } release;
  facts().clear();
  const Config cfg = config();
  const std::string spec = benchmarkSpec(opts.filter, "^terrain/");

  Collector collector;
  const std::size_t matched = runBenchmarks(spec, opts.googleBenchmarkOutput, collector);
  if (matched == 0) {
    out << "nestwalk bench terrain: no benchmark matches '" << spec << "'\n";
    return 1;
  }
  if (collector.samples.empty() && collector.errors.empty()) return 0;  // --benchmark_list_tests

  // The terrain mesh's level table for the benchmark grid (outside any timing).
  Terrain& terrain = terrainData();
  {
    const auto t0 = std::chrono::steady_clock::now();
    const terrain::TerrainMesh mesh(*terrain.hf, terrain::TerrainMeshOptions{128, 0});
    terrain.lod = mesh.levelTable();
    terrain.lodSeconds = secondsSince(t0);
  }

  std::vector<Row> rows;
  for (const SetSpec& s : kSets)
    for (const RowDef& d : kRows) {
      if (!s.vertical && std::string(d.key) == "ground_height") continue;
      Row r;
      r.name = std::string(d.key) + "/" + s.key;
      r.label = d.label;
      r.set = s.label;
      const std::string nw = benchName(d.nestwalk, s.key);
      r.nestwalk = collector.ns(nw);
      if (const Facts* f = factsOf(nw)) {
        r.hitFraction = f->hitFraction;
        r.nestwalkDisagreements = f->disagreements;
        r.nestwalkMaxDiff = f->maxHeightDiff;
      }
      for (int p = 0; p < kPeers; ++p) {
        const std::string pb = benchName(kPeerMethods[p], s.key);
        r.peer[p] = collector.ns(pb);
        if (const Facts* f = factsOf(pb)) {
          r.peerDisagreements[p] = f->disagreements;
          r.peerMaxDiff[p] = f->maxHeightDiff;
          r.peerFarHits[p] = f->farHits;
          r.peerRays[p] = f->rays;
          if (std::isnan(r.hitFraction)) r.hitFraction = f->hitFraction;
        }
      }
      if (!std::isnan(r.nestwalk) || std::any_of(std::begin(r.peer), std::end(r.peer), [](double v) { return !std::isnan(v); }))
        rows.push_back(r);
    }

  // The targets: ground height within 1.2x of the direct lookup and >= 15x faster than
  // Embree; oblique rays no slower than Embree.
  std::vector<Target> targets;
  for (const Row& r : rows) {
    if (r.name.rfind("ground_height/", 0) == 0 && !std::isnan(r.nestwalk)) {
      const std::string set = r.name.substr(14);
      if (!std::isnan(r.peer[0])) {
        const double v = r.nestwalk / r.peer[0];
        targets.push_back({"ground_height_vs_direct/" + set, "nestwalk / direct <= 1.2", v, v <= 1.2});
      }
      if (!std::isnan(r.peer[1])) {
        const double v = r.peer[1] / r.nestwalk;
        targets.push_back({"ground_height_vs_embree/" + set, "Embree / nestwalk >= 15", v, v >= 15.0});
      }
    }
    if (r.name == "intersect_ray/oblique" && !std::isnan(r.nestwalk) && !std::isnan(r.peer[1])) {
      const double v = r.peer[1] / r.nestwalk;
      targets.push_back({"oblique_vs_embree", "Embree / nestwalk >= 1", v, v >= 1.0});
    }
  }

  const std::size_t repetitions = collector.repetitions();
  const std::size_t triangles = 2 * std::size_t(terrain.n - 1) * std::size_t(terrain.n - 1);
  const int rc = collector.errors.empty() ? 0 : 1;

  if (opts.json) {
    Json j;
    Json list = Json::array();
    for (const Row& r : rows) {
      Json b;
      b["name"] = r.name;
      b["test"] = r.label;
      b["set"] = r.set;
      b["hit_fraction"] = jsonNumber(r.hitFraction);
      Json ns, ratio, dis, diff, far, count;
      ns["nestwalk"] = jsonNumber(r.nestwalk);
      if (r.nestwalkDisagreements >= 0) {
        dis["nestwalk"] = r.nestwalkDisagreements;
        diff["nestwalk"] = jsonNumber(r.nestwalkMaxDiff);
      }
      for (int p = 0; p < kPeers; ++p) {
        ns[kPeerKeys[p]] = jsonNumber(r.peer[p]);
        ratio[kPeerKeys[p]] = jsonNumber(r.peer[p] / r.nestwalk);
        dis[kPeerKeys[p]] = r.peerDisagreements[p] >= 0 ? Json(r.peerDisagreements[p]) : Json(nullptr);
        diff[kPeerKeys[p]] = jsonNumber(r.peerMaxDiff[p]);
        far[kPeerKeys[p]] = r.peerFarHits[p] >= 0 ? Json(r.peerFarHits[p]) : Json(nullptr);
        count[kPeerKeys[p]] = r.peerRays[p];
      }
      b["ns_per_ray"] = ns;
      b["ratio"] = ratio;
      b["disagreements"] = dis;
      b["max_height_diff"] = diff;
      b["hits_over_1cm_apart"] = far;
      b["rays"] = count;
      list.push_back(b);
    }
    j["benchmarks"] = list;
    Json m;
    m["cpu_model"] = cpuModelName();
    m["num_cpus"] = benchmark::CPUInfo::Get().num_cpus;
    m["grid_samples"] = terrain.n;
    m["triangles"] = triangles;
    m["rays_per_set"] = cfg.rays;
    m["slow_peer_rays_per_set"] = cfg.slowRays;
    m["min_time_s"] = cfg.minTime;
    m["quick"] = opts.quick;
    m["repetitions"] = repetitions;
#ifdef NDEBUG
    m["ndebug"] = true;
#else
    m["ndebug"] = false;
#endif
    m["libraries"] = {{"embree", RTC_VERSION_STRING},
                      {"bullet", std::to_string(BT_BULLET_VERSION) + (sizeof(btScalar) == 8 ? " (double)" : " (float)")},
                      {"openscenegraph", osgGetVersion()}};
    Json builds;
    for (const auto& [k, v] : terrain.buildSeconds) builds[k] = v;
    m["build_seconds"] = builds;
    j["machine"] = m;
    Json lod = Json::array();
    for (const auto& l : terrain.lod)
      lod.push_back({{"level", l.level}, {"step", l.step}, {"tiles", l.tiles}, {"triangles", l.triangles},
                     {"max_error_m", l.maxError}});
    j["lod_levels"] = lod;
    j["targets"] = targetsJson(targets);
    addErrors(j, collector);
    out << j.dump(2) << "\n";
    return rc;
  }

  out << "nestwalk bench terrain: ns per ray (CPU time); ratio = peer ns / nestwalk ns (> 1: nestwalk faster)\n";
  out << "cpu: " << cpuModelName() << ", " << benchmark::CPUInfo::Get().num_cpus << " CPUs"
#ifndef NDEBUG
      << "; ASSERTIONS ON (not a release build)"
#endif
      << "\n";
  out << "grid: " << terrain.n << " x " << terrain.n << " samples at " << kSpacing << " m (" << triangles
      << " triangles), heights " << fixedText(terrain.minH, 1) << " .. " << fixedText(terrain.maxH, 1) << " m\n";
  out << "rays per set: " << cfg.rays << " (OSG, and Bullet on oblique rays: the first " << cfg.slowRays << "); min time per benchmark: " << cfg.minTime
      << " s" << (opts.quick ? " (quick)" : "");
  if (repetitions > 1) out << "; median of " << repetitions << " repetitions";
  out << "\n";
  out << "peers: direct = bilinear grid read; Embree " << RTC_VERSION_STRING << " rtcIntersect1 (float); Bullet "
      << BT_BULLET_VERSION << " btHeightfieldTerrainShape::performRaycast (no accelerator); OSG " << osgGetVersion()
      << " LineSegmentIntersector + KdTree\n";
  out << "build times (s):";
  for (const auto& [k, v] : terrain.buildSeconds) out << " " << k << " " << fixedText(v, 2);
  out << "\n\n";

  std::ostringstream t;
  t << std::left << std::setw(14) << "query" << std::setw(23) << "set" << std::right << std::setw(7) << "hits"
    << std::setw(10) << "nestwalk";
  for (int p = 0; p < kPeers; ++p) t << std::setw(10) << kPeerTitles[p] << std::setw(8) << "ratio";
  t << "\n";
  for (const Row& r : rows) {
    t << std::left << std::setw(14) << r.label << std::setw(23) << r.set << std::right << std::setw(7)
      << fixedText(r.hitFraction, 3) << std::setw(10) << fixedText(r.nestwalk, 1);
    for (int p = 0; p < kPeers; ++p) t << std::setw(10) << fixedText(r.peer[p], 1) << std::setw(8) << fixedText(r.peer[p] / r.nestwalk, 2);
    t << "\n";
  }
  out << t.str();

  out << "\nagreement with nestwalk (groundHeight on vertical sets, intersectRay on oblique), counted outside the"
         " timed loops: hit/miss disagreements / max |hit height difference| in m / hits more than 1 cm apart"
         " (direct is bilinear, not the triangles; the float peers differ by rounding, which on grazing oblique"
         " rays can move a hit past a ridge)\n";
  for (const Row& r : rows) {
    if (r.name.rfind("ground_height/", 0) == 0) continue;  // the peers' figures are the same on both rows
    out << "  " << std::left << std::setw(23) << r.set << std::right;
    bool first = true;
    if (r.nestwalkDisagreements >= 0) {
      out << " intersectRay " << r.nestwalkDisagreements << " / " << fmtSci(r.nestwalkMaxDiff);
      first = false;
    }
    for (int p = 0; p < kPeers; ++p)
      if (r.peerDisagreements[p] >= 0) {
        out << (first ? " " : ", ") << kPeerTitles[p] << " " << r.peerDisagreements[p] << " / "
            << fmtSci(r.peerMaxDiff[p]) << " / " << r.peerFarHits[p] << " (" << r.peerRays[p] << " rays)";
        first = false;
      }
    out << "\n";
  }
  printTargets(out, targets, 40, 28);
  out << "\nterrain mesh levels (tiles of 128 cells; error = exact max vertical error vs full resolution, "
      << fixedText(terrain.lodSeconds, 2) << " s to compute):\n";
  out << "  level   step   tiles    triangles   max error (m)\n";
  for (const auto& l : terrain.lod)
    out << "  " << std::setw(5) << l.level << std::setw(7) << l.step << std::setw(8) << l.tiles << std::setw(13)
        << l.triangles << std::setw(16) << fixedText(l.maxError, 4) << "\n";
  for (const auto& [k, v] : collector.errors) out << "error: " << k << ": " << v << "\n";
  return rc;
}

}  // namespace nestwalk::bench
