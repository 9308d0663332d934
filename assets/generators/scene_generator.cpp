#include "assets/generators/scene_generator.h"

#include "assets/generators/equipment_tours.h"
#include "assets/generators/footprint_rect.h"
#include "assets/generators/generated_folder.h"
#include "assets/generators/phone_track.h"

#include "nestwalk/core/angles.h"
#include "nestwalk/core/input_error.h"
#include "nestwalk/terrain/heightfield.h"
#include "nestwalk/terrain/mining_dump_ortho.h"
#include "nestwalk/terrain/terrain_import.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <random>
#include <sstream>

namespace nestwalk::assets {
namespace {

/// The heading (degrees clockwise from north) of a map direction.
double headingOf(const Eigen::Vector2d& d) { return nestwalk::headingOf(d.x(), d.y()); }

namespace fs = std::filesystem;

// Placement.
constexpr double kCornerMargin = 5.0;         // metres kept from where a berm starts to bend
constexpr double kStationLoggerOffset = -1.5;  // metres along the berm from the mast
constexpr double kStationPanelOffset = 2.2;
constexpr double kBarrierLength = 3.0;        // one jersey barrier, end to end in a line
constexpr double kContainerPitch = 2.44 + 1.2;  // container width plus a 1.2 m aisle
constexpr std::uint64_t kPlacementSeedSalt = 0x5CE7E5EEDull;  // keeps placement apart from the terrain's draws

// Scripts. The viewer is the scene's default (scene_file.h): body half extents 0.25 m forward and
// sideways; the walker stops kStopDistance (0.5 mm) short of a contact.
constexpr double kBodyHalfForward = 0.25;
constexpr double kStopDistance = 0.5e-3;
constexpr double kPatrolApproach = 40.0;   // metres of lane walked before the station
constexpr double kPatrolOvershoot = 20.0;  // the goto aims this far past the mast
constexpr double kPatrolRetreat = 25.0;    // metres walked back after turning
constexpr double kPatrolSpeed = 1.4;       // m/s, walking
// The bundled GPS track (routes/patrol_track.gpx): it stops this far before the patrol's mast,
// stands there this long, and walks back to this far along the lane from the patrol's start.
constexpr double kTrackStopShort = 8.0;   // metres
constexpr double kTrackPause = 12.0;      // seconds
constexpr double kTrackBackShort = 10.0;  // metres
constexpr std::uint64_t kTrackSeedSalt = 0x747261636bULL;  // "track": the fixes' noise, apart from the placements
constexpr double kRampRunIn = 12.0;        // metres of flat top before the ramp's head
constexpr double kRampToeRunOut = 3.0;     // the descent ends this far up the ramp from its toe
constexpr double kRampSpeed = 3.0;         // m/s: a brisk walk down 350 m
constexpr double kFlightBeyond = 40.0;     // metres beyond the dump's ends
constexpr double kFlightSpeed = 40.0;      // m/s
constexpr double kFlightClearance = 5.0;   // metres, body bottom above the ground

double uniform(std::mt19937_64& rng) { return double(rng() >> 11) * 0x1.0p-53; }
double uniform(std::mt19937_64& rng, double lo, double hi) { return lo + (hi - lo) * uniform(rng); }
/// x rounded to thousandths (millimetres, millidegrees): the nearest double to the decimal, so the
/// JSON shows it exactly.
double roundMilli(double x) { return std::round(x * 1000.0) / 1000.0; }

class Placer {
 public:
  Placer(const terrain::Heightfield& hf, const DumpGeometry& g) : hf_(hf), g_(g) {
    for (ModelKind m : kAllModels) bounds_[std::size_t(m)] = modelBounds(m);
  }

  Placement piece(ModelKind m, const std::string& group, const std::string& part, const Eigen::Vector2d& at,
                  double headingDeg, int bench, bool useOnly = false) const {
    Placement p;
    p.name = group + "/" + part;
    p.group = group;
    p.model = m;
    p.position = Eigen::Vector2d(roundMilli(at.x()), roundMilli(at.y()));
    p.headingDeg = roundMilli(headingDeg);
    if (p.headingDeg >= 360.0) p.headingDeg -= 360.0;
    p.useOnly = useOnly;
    p.bench = bench;
    p.level = g_.bermLevel(bench);
    return p;
  }

  Rect footprint(const Placement& p) const { return footprintRect(p, bounds_[std::size_t(p.model)]); }

  /// Places the pieces (one group) when every one stands on flat berm, off the ramp, clear of
  /// other groups; all or nothing.
  bool tryGroup(const std::vector<Placement>& pieces) {
    std::vector<Rect> rects;
    for (const Placement& p : pieces) {
      const Rect r = footprint(p);
      const std::array<Eigen::Vector2d, 5> pts = {r.c, r.c + r.hx * r.ax + r.hy * r.ay, r.c + r.hx * r.ax - r.hy * r.ay,
                                                  r.c - r.hx * r.ax + r.hy * r.ay, r.c - r.hx * r.ax - r.hy * r.ay};
      for (const Eigen::Vector2d& q : pts) {
        const std::optional<double> z = hf_.groundHeight(q.x(), q.y());
        if (!z || std::abs(*z - p.level) > kFlatTolerance) return false;
        const Eigen::Vector2d uv = g_.toDump(q);
        if (std::abs(uv.y() - g_.rampV) < g_.rampHalfWidth + kRampMargin && uv.x() < g_.rampEnd + kRampHeadClear)
          return false;
      }
      for (const Rect& o : rects_)
        if (o.group != r.group && rectsOverlap(o, r, 0.5 * kGroupGap)) return false;
      rects.push_back(r);
    }
    placed_.insert(placed_.end(), pieces.begin(), pieces.end());
    rects_.insert(rects_.end(), rects.begin(), rects.end());
    return true;
  }

  const Aabb<double>& bounds(ModelKind m) const { return bounds_[std::size_t(m)]; }
  std::vector<Placement>& placed() { return placed_; }

 private:
  const terrain::Heightfield& hf_;
  const DumpGeometry& g_;
  std::array<Aabb<double>, kAllModels.size()> bounds_;
  std::vector<Placement> placed_;
  std::vector<Rect> rects_;
};

/// One straight side of a berm, in the dump frame: the point `l` metres along it at inset s.
struct Side {
  int index;  // 0: v > 0 long side, 1: v < 0 long side, 2: u > 0 end, 3: u < 0 end
  Eigen::Vector2d point(const DumpGeometry& g, double s, double l) const {
    const double a = g.layout.halfLength - s, b = g.layout.halfWidth - s;
    switch (index) {
      case 0: return {-l, b};
      case 1: return {l, -b};
      case 2: return {a, l};
      default: return {-a, -l};
    }
  }
  Eigen::Vector2d tangent() const {  // dump frame; the model's +x when it faces outwards
    switch (index) {
      case 0: return {-1, 0};
      case 1: return {1, 0};
      case 2: return {0, 1};
      default: return {0, -1};
    }
  }
  Eigen::Vector2d outward() const {
    switch (index) {
      case 0: return {0, 1};
      case 1: return {0, -1};
      case 2: return {1, 0};
      default: return {-1, 0};
    }
  }
  /// Half length of the straight part usable at insets up to sInner.
  double halfLength(const DumpGeometry& g, double sInner) const {
    const double half = index < 2 ? g.layout.halfLength : g.layout.halfWidth;
    return half - std::max(g.cornerRadius, sInner) - kCornerMargin;
  }
};

Eigen::Vector2d mapDirection(const DumpGeometry& g, const Eigen::Vector2d& dumpDir) {
  return dumpDir.x() * g.uAxis() + dumpDir.y() * g.vAxis();
}

std::string benchName(int k) { return "bench" + std::to_string(k); }

std::string fmt(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", x);
  return buf;
}
std::string xy(const Eigen::Vector2d& p) { return fmt(p.x()) + " " + fmt(p.y()); }

}  // namespace

GeneratedScene generateScene(std::uint64_t seed, const SceneSite& site) {
  GeneratedScene out;
  out.seed = seed;
  out.site = site;
  out.params.seed = seed;
  out.params.centreE = site.centreE;
  out.params.centreN = site.centreN;
  out.dump = terrain::generateMiningDump(out.params);
  const DumpGeometry g = dumpGeometry(out.params, out.dump.layout);
  out.geometry = g;
  const terrain::Heightfield hf(out.dump.cols, out.dump.rows, out.dump.heights, out.dump.originX, out.dump.originY,
                                out.dump.cell, out.dump.cell);
  Placer placer(hf, g);
  std::mt19937_64 rng(seed ^ kPlacementSeedSalt);
  std::map<std::string, int> counters;  // "<bench>/<what>" -> next index
  auto nextGroup = [&](int k, const std::string& what) {
    return benchName(k) + "/" + what + std::to_string(counters[benchName(k) + "/" + what]);
  };
  auto commit = [&](int k, const std::string& what) { ++counters[benchName(k) + "/" + what]; };

  const int top = g.benches;
  auto station = [&](int k, const Side& side, double l, double mastW) {
    const double s0 = g.crestInset(k);
    const double out_ = headingOf(mapDirection(g, side.outward()));
    auto at = [&](double w, double ll) { return g.toMap(side.point(g, s0 + w, ll).x(), side.point(g, s0 + w, ll).y()); };
    const std::string grp = nextGroup(k, "station");
    const std::vector<Placement> pieces = {
        placer.piece(ModelKind::WeatherStation, grp, "mast", at(mastW, l), out_, k),
        placer.piece(ModelKind::LoggerBox, grp, "logger", at(kInnerLineW, l + kStationLoggerOffset), out_, k),
        placer.piece(ModelKind::SolarPanel, grp, "panel", at(kInnerLineW, l + kStationPanelOffset), out_, k)};
    if (!placer.tryGroup(pieces)) return std::string();
    commit(k, "station");
    return grp;
  };

  // 1. The patrol's station: its mast on bench 2's lane (the v > 0 long side, clear of the ramp).
  const int patrolBench = std::min(2, std::max(1, top - 1));
  const Side patrolSide{0};
  const double patrolFirstL = uniform(rng, -40.0, 40.0);
  double patrolL = patrolFirstL;
  for (int tries = 0; tries < 30 && out.points.patrolStation.empty(); ++tries) {
    patrolL = patrolFirstL + 7.0 * tries;
    out.points.patrolStation = station(patrolBench, patrolSide, patrolL, kLaneW);
  }
  if (out.points.patrolStation.empty()) throw std::runtime_error("make-scene: no flat place for the patrol's station");

  // 2. The top: a container yard, two pickups, a station in the middle.
  const double topHalfLength = g.layout.halfLength - g.crestInset(top);
  const double topHalfWidth = g.layout.halfWidth - g.crestInset(top);
  const double alongU = headingOf(g.uAxis()), againstU = headingOf(-g.uAxis());
  double yardU = -0.35 * topHalfLength + uniform(rng, -10.0, 10.0);
  const double yardV = 0.2 * topHalfWidth + uniform(rng, -5.0, 5.0);
  bool yard = false;
  for (int tries = 0; tries < 20 && !yard; ++tries, yardU += 5.0) {
    const std::string grp = nextGroup(top, "yard");
    std::vector<Placement> pieces;
    for (int i = 0; i < 3; ++i)
      pieces.push_back(placer.piece(ModelKind::Container20ft, grp, "container" + std::to_string(i),
                                    g.toMap(yardU, yardV + (i - 1) * kContainerPitch), alongU, top));
    if ((yard = placer.tryGroup(pieces))) commit(top, "yard");
  }
  struct Spot { double u, v, heading; };
  for (const Spot& s : {Spot{g.rampEnd + 25.0, g.rampV + g.rampHalfWidth + kRampMargin + 4.0, againstU},
                        Spot{yardU + 12.0, yardV - 9.0, alongU}}) {
    for (int tries = 0; tries < 20; ++tries) {
      const std::string grp = nextGroup(top, "vehicle");
      if (placer.tryGroup({placer.piece(ModelKind::Pickup, grp, "pickup", g.toMap(s.u + 5.0 * tries, s.v), s.heading, top)})) {
        commit(top, "vehicle");
        break;
      }
    }
  }
  for (int tries = 0; tries < 20; ++tries) {
    // Facing along +u: the model's +x is the dump's +v, where the logger and the panel stand.
    const std::string grp = nextGroup(top, "station");
    const Eigen::Vector2d m = g.toMap(0.5 * topHalfLength + 5.0 * tries, 0.0);
    if (placer.tryGroup({placer.piece(ModelKind::WeatherStation, grp, "mast", m, alongU, top),
                         placer.piece(ModelKind::LoggerBox, grp, "logger", m + kStationLoggerOffset * g.vAxis(), alongU, top),
                         placer.piece(ModelKind::SolarPanel, grp, "panel", m + kStationPanelOffset * g.vAxis(), alongU, top)})) {
      commit(top, "station");
      break;
    }
  }

  // 3. Every berm and the top's edge: stations, piezometers and poles on the inner line, fences at the crest.
  for (int k = 1; k <= top; ++k) {
    const double s0 = g.crestInset(k);
    for (int i = 0; i < 4; ++i) {
      const Side side{i};
      const double half = side.halfLength(g, s0 + g.bermWidth);
      if (half < 20.0) continue;
      auto at = [&](double w, double l) {
        const Eigen::Vector2d p = side.point(g, s0 + w, l);
        return g.toMap(p.x(), p.y());
      };
      const double outwards = headingOf(mapDirection(g, side.outward()));
      const double along = headingOf(mapDirection(g, side.tangent()));
      for (double l = -half + uniform(rng, 10.0, 60.0); l < half - 5.0; l += uniform(rng, 90.0, 160.0))
        station(k, side, l, kInnerLineW);
      for (double l = -half + uniform(rng, 5.0, 40.0); l < half; l += uniform(rng, 50.0, 90.0)) {
        const std::string grp = nextGroup(k, "piezometer");
        if (placer.tryGroup({placer.piece(ModelKind::Piezometer, grp, "piezometer", at(kInnerLineW, l), outwards, k)}))
          commit(k, "piezometer");
      }
      for (double l = -half + uniform(rng, 0.0, 20.0); l < half; l += uniform(rng, 22.0, 38.0)) {
        const std::string grp = nextGroup(k, "pole");
        if (placer.tryGroup({placer.piece(ModelKind::SensorPole, grp, "pole", at(kInnerLineW, l), outwards, k)}))
          commit(k, "pole");
      }
      double l = -half + uniform(rng, 0.0, 15.0);
      for (;;) {
        const int n = 4 + int(uniform(rng) * 5.0);
        if (l + n * kBarrierLength > half) break;
        const std::string grp = nextGroup(k, "fence");
        std::vector<Placement> pieces;
        for (int j = 0; j < n; ++j)
          pieces.push_back(placer.piece(ModelKind::JerseyBarrier, grp, "barrier" + std::to_string(j),
                                        at(kFenceLineW, l + (j + 0.5) * kBarrierLength), along, k, true));
        if (placer.tryGroup(pieces)) {
          commit(k, "fence");
          l += n * kBarrierLength + uniform(rng, 20.0, 60.0);
        } else {
          l += 6.0;
        }
      }
    }
  }
  // 4. A drill rig on the top, the scene's heavy model (10 m tall): across the long axis from the
  // container yard (15 % to 45 % of the top's half width on the other side, stepping 6 m along
  // the axis), off the low flight's line over the yard. Placed last, so that everything above
  // stands where it stood before it came.
  for (int tries = 0; tries < 40; ++tries) {
    const std::string grp = nextGroup(top, "drill");
    const Eigen::Vector2d at = g.toMap(yardU + 6.0 * (tries % 10), -(0.15 + 0.1 * (tries / 10)) * topHalfWidth);
    if (placer.tryGroup({placer.piece(ModelKind::DrillRig, grp, "rig", at, againstU, top)})) {
      commit(top, "drill");
      break;
    }
  }
  out.equipment = std::move(placer.placed());

  // 5. Scripts.
  ScriptPoints& P = out.points;
  {
    const double s = g.crestInset(patrolBench) + kLaneW;
    const double l = patrolL;
    auto lane = [&](double ll) {
      const Eigen::Vector2d p = patrolSide.point(g, s, ll);
      return g.toMap(p.x(), p.y());
    };
    const double approachSide = -placer.bounds(ModelKind::WeatherStation).min.x();  // the mast's -x reach
    P.patrolMast = lane(l);
    P.patrolStart = lane(l - kPatrolApproach);
    P.patrolTarget = lane(l + kPatrolOvershoot);
    P.patrolBlockedAt = lane(l - approachSide - kBodyHalfForward - kStopDistance);
    P.patrolEnd = lane(l - approachSide - kBodyHalfForward - kPatrolRetreat);
    P.patrolHeading = roundMilli(headingOf(mapDirection(g, patrolSide.tangent())));
    // The patrol walked with a phone in the pocket: along the lane to within kTrackStopShort of the
    // station, a pause there, then back; the station as the track's waypoint to look at.
    PhoneTrack track;
    track.name = "patrol along " + benchName(patrolBench);
    track.legs = {lane(l - kPatrolApproach), lane(l - kTrackStopShort), lane(l - kPatrolApproach + kTrackBackShort)};
    track.pauseAt = 1;
    track.pauseSeconds = kTrackPause;
    track.waypoints = {{out.points.patrolStation, P.patrolMast}};
    out.routes.emplace_back("patrol_track.gpx", phoneTrackGpx(track, hf, site.crs, seed ^ kTrackSeedSalt));
  }
  P.rampTop = g.toMap(g.rampEnd + kRampRunIn, g.rampV);
  P.rampToe = g.toMap(g.rampStart + kRampToeRunOut, g.rampV);
  P.rampHeading = roundMilli(againstU);
  const double flightV = yardV;
  P.flightStart = g.toMap(-g.layout.halfLength - kFlightBeyond, flightV);
  P.flightOverYard = g.toMap(yardU, flightV);
  P.flightEnd = g.toMap(g.layout.halfLength + kFlightBeyond, flightV);
  P.flightHeading = roundMilli(alongU);

  const std::string header = "# Generated by `nestwalk make-scene` (seed " + std::to_string(seed) +
                             ") for the scene beside this folder; map coordinates, EPSG:32651.\n";
  out.scripts.emplace_back(
      "bench_patrol.txt",
      header + "# A patrol along the walking lane of " + benchName(patrolBench) + " (level " +
          fmt(g.bermLevel(patrolBench)) + " m), " + fmt(kLaneW) + " m inside the crest. The mast of " +
          P.patrolStation + " stands on the lane at " + xy(P.patrolMast) +
          ": its inner box reaches the lane's centre line, so the body (half extents 0.25 m forward and sideways)\n"
          "# stops about " + fmt(-placer.bounds(ModelKind::WeatherStation).min.x() + kBodyHalfForward) +
          " m short of the mast's axis. Then it turns back along the lane, which is free.\n"
          "mode walk\nspeed " + fmt(kPatrolSpeed) + "\nstart " + xy(P.patrolStart) + " heading " + fmt(P.patrolHeading) +
          "\nexpect ground within 0.01\ngoto " + xy(P.patrolTarget) + "\nexpect blocked by " + P.patrolStation +
          "\nexpect position " + xy(P.patrolBlockedAt) + " within 1\nexpect ground within 0.01\nturn 180\nmove " +
          fmt(kPatrolRetreat) + "\nexpect free\nexpect ground within 0.01\nexpect position " + xy(P.patrolEnd) +
          " within 1\n");
  out.scripts.emplace_back(
      "ramp_descent.txt",
      header + "# Down the haul ramp (" + fmt(g.rampGrade * 100.0) + " % grade, " + fmt(2 * g.rampHalfWidth) +
          " m wide) on its centre line, from the top (" + fmt(g.layout.topHeight) + " m) to its toe (" +
          fmt(g.rampHeight(g.rampStart + kRampToeRunOut)) + " m).\n"
          "mode walk\nspeed " + fmt(kRampSpeed) + "\nstart " + xy(P.rampTop) + " heading " + fmt(P.rampHeading) +
          "\nexpect ground within 0.01\ngoto " + xy(P.rampToe) + "\nexpect free\nexpect position " + xy(P.rampToe) +
          " within 1\nexpect ground within 0.01\n");
  out.scripts.emplace_back(
      "low_flight.txt",
      header + "# A low flight along the dump's long axis over the container yard on the top, at least " +
          fmt(kFlightClearance) + " m above the ground (the equipment under it is at most 3 m tall; the\n"
          "# 10 m drill rig stands off the line).\n"
          "mode fly\nclearance " + fmt(kFlightClearance) + "\nspeed " + fmt(kFlightSpeed) + "\nstart " +
          xy(P.flightStart) + " heading " + fmt(P.flightHeading) + "\nexpect clearance at least " +
          fmt(kFlightClearance) + "\ngoto " + xy(P.flightOverYard) + "\nexpect clearance at least " +
          fmt(kFlightClearance) + "\ngoto " + xy(P.flightEnd) + "\nexpect clearance at least " +
          fmt(kFlightClearance) + "\nexpect free\n");

  for (const Tour& tour : equipmentTours(hf, out.equipment, g.layout.topHeight, header)) {
    out.scripts.emplace_back(tour.file, tour.text);
    std::vector<std::pair<std::string, std::string>> events;
    for (const TourEvent& e : tour.events) events.emplace_back(e.group, e.kind);
    out.tourEvents.emplace_back(tour.file, std::move(events));
  }

  // 5. scene.json.
  nlohmann::ordered_json j;
  j["terrain"] = "terrain.tif";
  j["imagery"] = "ortho.tif";
  nlohmann::ordered_json eq = nlohmann::ordered_json::array();
  for (const Placement& p : out.equipment) {
    nlohmann::ordered_json e;
    e["name"] = p.name;
    e["model"] = "models/" + modelFileName(p.model);
    e["position"] = {p.position.x(), p.position.y()};
    e["heading"] = p.headingDeg;
    e["group"] = p.group;
    e["use_only"] = p.useOnly;
    e["kind"] = modelKindLabel(p.model);
    eq.push_back(std::move(e));
  }
  j["equipment"] = std::move(eq);
  j["viewer"] = {{"eye_height", 1.7}, {"body_half_extents", {0.25, 0.25, 0.9}}, {"max_step", 0.3},
                 {"max_slope_deg", 30}, {"speed", 1.4}, {"fly_clearance", 2.0}};
  j["method"] = {{"volumes", "nested"}, {"hierarchy", "auto"}, {"degree", 8},
                 {"split_axis", "longest"}, {"split_point", "median"}, {"fitter", "hull-search"}};
  out.sceneJson = j.dump(1) + "\n";
  return out;
}

void writeScene(const GeneratedScene& scene, const std::string& dir, bool overwrite, double orthoPixel) {
  if (orthoPixel > scene.dump.cell)
    throw InputError(dir + ": an orthophoto pixel of " + (std::ostringstream() << orthoPixel).str() +
                     " m is coarser than the terrain's " + (std::ostringstream() << scene.dump.cell).str() +
                     " m cell; it must be as fine or finer");
  writeGeneratedFolder(dir, overwrite, [&](const fs::path& tmp) {
    fs::create_directories(tmp / "models");
    fs::create_directories(tmp / "scripts");
    const terrain::MiningDump& d = scene.dump;
    terrain::writeTerrainCog((tmp / "terrain.tif").string(), d.cols, d.rows, d.heights, d.originX, d.originY, d.cell,
                             d.cell, scene.site.crs, false);
    if (orthoPixel > 0 && orthoPixel < d.cell)
      terrain::writeFineMiningDumpOrtho((tmp / "ortho.tif").string(), scene.params, orthoPixel, scene.site.crs, false);
    else
      terrain::writeMiningDumpOrtho((tmp / "ortho.tif").string(), d, scene.seed, scene.site.crs, false);
    for (ModelKind m : kAllModels) writeModel(m, (tmp / "models" / modelFileName(m)).string());
    writeTextFile(tmp / "scene.json", scene.sceneJson);
    for (const auto& [name, text] : scene.scripts) writeTextFile(tmp / "scripts" / name, text);
    if (!scene.routes.empty()) fs::create_directories(tmp / "routes");
    for (const auto& [name, text] : scene.routes) writeTextFile(tmp / "routes" / name, text);
  });
}

}  // namespace nestwalk::assets
