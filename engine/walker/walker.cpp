#include "nestwalk/walker/walker.h"

#include "nestwalk/terrain/height_tiles.h"

#include "nestwalk/core/angles.h"
#include "nestwalk/core/stopwatch.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace nestwalk {
namespace {

/// Unit forward vector of a heading (clockwise from north = map +y).
Eigen::Vector2d forwardOf(double headingDeg) {
  return {std::sin(radians(headingDeg)), std::cos(radians(headingDeg))};
}

/// The footprint's centre c and its corners, in footprintHeights()'s order: c, c+f+s, c+f-s, c-f+s,
/// c-f-s (f forward, s sideways half extents).
std::array<Eigen::Vector2d, 5> footprintPoints(const Eigen::Vector2d& c, const Eigen::Vector2d& f,
                                               const Eigen::Vector2d& s) {
  return {c, c + f + s, c + f - s, c - f + s, c - f - s};
}

using Clock = std::chrono::steady_clock;

/// Nu, the volumes updated per step, counts each of the body's two volumes (outer AABB and inner
/// OBB) every time the body is placed somewhere new and rebuilt (the collision cost model
/// t = Nv Cv + Np Cp + Nu Cu counts volumes, not bodies).
constexpr std::uint64_t kVolumesPerBody = 2;
/// Back-offs from a contact at most: each doubles the distance backed off (kStopDistance, then 2,
/// 4, ... times it), so 60 reach any step's length long before the cap.
constexpr int kMaxBackOffs = 60;
/// Metres: a slide direction or a rest of the step shorter than this is no motion (far below any
/// step, far above the rounding of a projection at local-frame magnitudes).
constexpr double kNegligibleLength = 1e-9;

}  // namespace

const char* blockReasonName(BlockReason r) {
  switch (r) {
    case BlockReason::None: return "";
    case BlockReason::Equipment: return "equipment";
    case BlockReason::TerrainStep: return "terrain:step";
    case BlockReason::TerrainSlope: return "terrain:slope";
    case BlockReason::TerrainEdge: return "terrain:edge";
  }
  return "";
}

struct Walker::Leg {
  bool blocked = false;
  BlockReason reason = BlockReason::None;
  std::int32_t unit = -1;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  Eigen::Vector3d remaining = Eigen::Vector3d::Zero();  // the part of the leg not walked
};

Walker::Walker(const terrain::Heightfield& terrain, const CollisionWorld& world, const Eigen::Vector3d& origin,
               const WalkerOptions& options)
    : terrain_(terrain), world_(world), origin_(origin), options_(options) {
  sampleSpacing_ = kGroundSampleSpacing * std::min(std::abs(terrain.dx()), std::abs(terrain.dy()));
  state_.clearance = options.viewer.flyClearance;
}

NestedVolume<double> bodyVolumeAt(const ViewerSpec& viewer, const Eigen::Vector3d& origin,
                                  const Eigen::Vector3d& feetMap, double yawDeg) {
  const Eigen::Vector3d& h = viewer.bodyHalfExtents;
  const Eigen::Vector2d f = forwardOf(yawDeg);
  Obb<double> b;
  b.center = feetMap + Eigen::Vector3d(0, 0, h.z()) - origin;
  b.axes.col(0) = Vec3<double>(f.x(), f.y(), 0);
  b.axes.col(1) = Vec3<double>(-f.y(), f.x(), 0);
  b.axes.col(2) = Vec3<double>(0, 0, 1);
  b.halfExtents = h;
  return NestedVolume<double>::fromObb(b);
}

NestedVolume<double> Walker::bodyVolume(const Eigen::Vector3d& feetMap, double yawDeg) const {
  return bodyVolumeAt(options_.viewer, origin_, feetMap, yawDeg);
}

Walker::Footprint Walker::footprintAt(double yawDeg) const {
  const Eigen::Vector2d forward = forwardOf(yawDeg);
  return {forward * options_.viewer.bodyHalfExtents.x(),
          Eigen::Vector2d(-forward.y(), forward.x()) * options_.viewer.bodyHalfExtents.y()};
}

bool Walker::footprintHeights(double x, double y, double yawDeg, std::array<double, 5>& h) const {
  return footprintHeights(x, y, footprintAt(yawDeg), h);
}

bool Walker::footprintHeights(double x, double y, const Footprint& footprint, std::array<double, 5>& h) const {
  // Centre, then the corners: +f+s, +f-s, -f+s, -f-s (f forward, s sideways).
  const auto pts = footprintPoints(Eigen::Vector2d(x, y), footprint.forward, footprint.side);
  for (int i = 0; i < 5; ++i) {
    const std::optional<double> z = terrain_.groundHeight(pts[i].x(), pts[i].y());
    if (!z) return false;
    h[std::size_t(i)] = *z;
  }
  return true;
}

std::optional<double> Walker::highestFootprintGround(double x, double y, const Footprint& footprint,
                                                    const std::array<bool, 5>& sampled) const {
  const auto pts = footprintPoints(Eigen::Vector2d(x, y), footprint.forward, footprint.side);
  double top = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < 5; ++i) {
    if (!sampled[std::size_t(i)]) continue;
    const std::optional<double> z = terrain_.groundHeight(pts[i].x(), pts[i].y());
    if (!z) return std::nullopt;
    top = std::max(top, *z);
  }
  return top;
}

Walker::PathCeilings Walker::flyingPathCeilings(const Eigen::Vector3d& start, const Eigen::Vector3d& move, int n,
                                                const Footprint& footprint) const {
  PathCeilings ceilings{};
  if (n == 0) return ceilings;
  // Each footprint point's positions over the leg lie between its first and last (the same
  // monotone rounding, coordinate by coordinate), so their box holds every one (a build that fuses
  // the multiply-add moves one by an ulp, well inside groundCeiling's padding).
  const auto pa = flyingSamplePoints(start, move, 1, n, footprint);
  const auto pb = flyingSamplePoints(start, move, n, n, footprint);
  for (std::size_t i = 0; i < 5; ++i)
    ceilings[i] = terrain_.groundCeiling(pa[i].x(), pa[i].y(), pb[i].x(), pb[i].y());
  return ceilings;
}

std::array<Eigen::Vector2d, 5> Walker::flyingSamplePoints(const Eigen::Vector3d& start, const Eigen::Vector3d& move,
                                                          int k, int n, const Footprint& footprint) {
  // The same expression as walkLeg's sample k, so the same bits.
  const Eigen::Vector3d p = start + move * (double(k) / n);
  return footprintPoints(Eigen::Vector2d(p.x(), p.y()), footprint.forward, footprint.side);
}

std::optional<double> Walker::highestFlyingFeet(const Eigen::Vector3d& start, const Eigen::Vector3d& move, int n,
                                                const Footprint& footprint, const PathCeilings& ceilings,
                                                double floorZ) const {
  const double clearance = state_.clearance;
  double best = floorZ;
  // Sample k of point i: its ground lifts `best` when higher; false when it has no ground (not
  // expected under a ceiling, which certifies ground on the whole box: the caller scans instead).
  auto sample = [&](std::size_t i, int k) {
    const Eigen::Vector2d q = flyingSamplePoints(start, move, k, n, footprint)[i];
    const std::optional<double> z = terrain_.groundHeight(q.x(), q.y());
    if (z) best = std::max(best, *z + clearance);
    return z.has_value();
  };
  // The leg's last samples first: a climb's highest ground is usually there, and every range
  // whose ceiling is no higher is then skipped whole.
  for (std::size_t i = 0; i < 5; ++i)
    if (*ceilings[i] + clearance > best && !sample(i, n)) return std::nullopt;
  // Then samples 1 .. n-1 of each point, a range at a time, depth first (the later half first).
  struct Range {
    std::size_t point;
    int first, last;
  };
  std::array<Range, 5 + 64> stack;  // each split adds one entry, at most log2(n) < 31 deep
  std::size_t size = 0;
  for (std::size_t i = 5; i-- > 0;)
    if (n > 1 && *ceilings[i] + clearance > best) stack[size++] = {i, 1, n - 1};
  while (size > 0) {
    const Range r = stack[--size];
    if (r.last - r.first < kFlyingSampledRange) {
      for (int k = r.first; k <= r.last; ++k)
        if (!sample(r.point, k)) return std::nullopt;
      continue;
    }
    const Eigen::Vector2d a = flyingSamplePoints(start, move, r.first, n, footprint)[r.point];
    const Eigen::Vector2d b = flyingSamplePoints(start, move, r.last, n, footprint)[r.point];
    const std::optional<double> ceiling = terrain_.groundCeiling(a.x(), a.y(), b.x(), b.y());
    if (ceiling && *ceiling + clearance <= best) continue;  // no sample of it can lift the body
    const int mid = r.first + (r.last - r.first) / 2;
    stack[size++] = {r.point, r.first, mid};
    stack[size++] = {r.point, mid + 1, r.last};
  }
  return best;
}

std::optional<double> Walker::lowestFlyingFeet(double x, double y) const {
  std::array<double, 5> h{};
  if (!footprintHeights(x, y, state_.bodyYawDeg, h)) return std::nullopt;
  return *std::max_element(h.begin(), h.end()) + state_.clearance;
}

std::string Walker::place(const Eigen::Vector3d& position, bool hasZ, double headingDeg, bool flying,
                          double clearance) {
  std::array<double, 5> h{};
  if (!footprintHeights(position.x(), position.y(), headingDeg, h)) return "no ground under the viewer's footprint";
  WalkerState s;
  s.headingDeg = s.bodyYawDeg = headingDeg;
  s.flying = flying;
  s.clearance = clearance;
  s.hasGround = true;
  s.ground = h[0];
  if (flying) {
    const double lowest = *std::max_element(h.begin(), h.end()) + clearance;
    const double feetZ = hasZ ? position.z() - options_.viewer.eyeHeight : lowest;
    s.feet = Eigen::Vector3d(position.x(), position.y(), std::max(feetZ, lowest));
  } else {
    s.feet = Eigen::Vector3d(position.x(), position.y(), h[0]);
  }
  CollisionCounters c;
  const std::int32_t u = world_.overlapping(bodyVolume(s.feet, headingDeg), c);
  if (u >= 0) return "the viewer's body overlaps " + world_.name(std::size_t(u));
  s.frame = state_.frame;
  s.time = state_.time;
  s.pitchDeg = state_.pitchDeg;
  // Somewhere new: the ground around the feet is read now, so that the first steps find it held
  // (a prefetch queued now could not be read before the next step on a fine DEM: a tile takes
  // milliseconds), and the ground ahead is asked for at the first step, once the motion is known.
  // Before the state changes: a read that fails leaves the walker where it was.
  if (terrain_.paged()) {
    const auto [x0, y0, x1, y1] = groundAhead(s.feet.head<2>(), Eigen::Vector3d::Zero());
    terrain_.holdTiles(x0, y0, x1, y1);
  }
  state_ = s;
  prefetchGround(Eigen::Vector3d::Zero(), true);
  return {};
}

void Walker::setFlying(bool flying, double clearance) {
  state_.flying = flying;
  state_.clearance = clearance;
}

Walker::Leg Walker::walkLeg(const Eigen::Vector3d& move, StepReport& report) {
  Leg leg;
  const Eigen::Vector3d start = state_.feet;
  const ViewerSpec& v = options_.viewer;
  const double yaw = state_.bodyYawDeg;
  const Footprint footprint = footprintAt(yaw);  // once a leg: one sine and cosine, not 3 per sample
  Clock::time_point t0;
  if (options_.timeParts) t0 = Clock::now();

  // 1. The terrain along the leg decides how far it can go (walking) or how high (flying).
  Eigen::Vector3d target = start;
  const double len = move.head<2>().norm();
  const int n = len > 0 ? std::max(1, int(std::ceil(len / sampleSpacing_))) : 0;
  std::array<double, 5> h{};
  if (state_.flying) {
    const PathCeilings ceilings = flyingPathCeilings(start, move, n, footprint);
    double lowest = -std::numeric_limits<double>::infinity();
    int good = 0;
    // Ground under the whole leg (every point's ceiling certifies it): the leg is not stopped, and
    // only its highest sample matters, found by bounds. Else every sample in order, so that the
    // leg stops at the first without ground.
    const bool grounded = std::all_of(ceilings.begin(), ceilings.end(), [](const auto& c) { return c.has_value(); });
    const std::optional<double> highest =
        n > kFlyingSampledRange && grounded
            ? highestFlyingFeet(start, move, n, footprint, ceilings, (start + move * (double(n) / n)).z())
            : std::nullopt;
    if (highest) {
      lowest = *highest;
      good = n;
    } else {
      // The leg ends no lower than this, at whichever sample it stops: start.z + move.z (k / n)
      // rounds monotonically in k, so it lies between its ends. A point whose ceiling plus the
      // clearance is no higher can neither lift the body nor end the leg at an edge: not sampled.
      const double floor = std::min(start.z(), (start + move).z());
      std::array<bool, 5> sampled{};
      for (std::size_t i = 0; i < 5; ++i) sampled[i] = !(ceilings[i] && *ceilings[i] + state_.clearance <= floor);
      for (int k = 1; k <= n; ++k) {
        const Eigen::Vector3d p = start + move * (double(k) / n);
        const std::optional<double> top = highestFootprintGround(p.x(), p.y(), footprint, sampled);
        if (!top) {
          leg.blocked = true;
          leg.reason = BlockReason::TerrainEdge;
          break;
        }
        lowest = std::max(lowest, *top + state_.clearance);
        good = k;
      }
    }
    target = n == 0 ? Eigen::Vector3d(start + move) : Eigen::Vector3d(start + move * (double(good) / n));
    if (n == 0 && footprintHeights(target.x(), target.y(), footprint, h))
      lowest = *std::max_element(h.begin(), h.end()) + state_.clearance;
    target.z() = std::max(target.z(), lowest);
  } else if (n > 0) {
    const double maxSlope = std::tan(radians(v.maxSlopeDeg));
    const Eigen::Vector2d dir = move.head<2>() / len;
    const Eigen::Vector2d f = forwardOf(yaw), s(-f.y(), f.x());
    const double alongF = dir.dot(f), alongS = dir.dot(s);
    double prevZ = start.z();
    for (int k = 1; k <= n; ++k) {
      const Eigen::Vector2d p = start.head<2>() + move.head<2>() * (double(k) / n);
      BlockReason r = BlockReason::None;
      if (!footprintHeights(p.x(), p.y(), footprint, h)) {
        r = BlockReason::TerrainEdge;
      } else if (std::abs(h[0] - prevZ) > v.maxStep) {
        r = BlockReason::TerrainStep;
      } else {
        // Plane through the footprint corners (least squares on the rectangle): its gradient
        // along the motion is the slope the viewer would walk.
        const double gf = ((h[1] + h[2]) - (h[3] + h[4])) / (4.0 * v.bodyHalfExtents.x());
        const double gs = ((h[1] + h[3]) - (h[2] + h[4])) / (4.0 * v.bodyHalfExtents.y());
        if (std::abs(gf * alongF + gs * alongS) > maxSlope) r = BlockReason::TerrainSlope;
      }
      if (r != BlockReason::None) {
        leg.blocked = true;
        leg.reason = r;
        break;
      }
      prevZ = h[0];
      target = Eigen::Vector3d(p.x(), p.y(), h[0]);
    }
  }
  Clock::time_point t1;
  if (options_.timeParts) {
    t1 = Clock::now();
    report.micros[StepPart::Ground] += microsBetween(t0, t1);
  }

  // 2. The equipment: the swept nested test along the straight leg start -> target.
  const Eigen::Vector3d d = target - start;
  Eigen::Vector3d end = target;
  if (!d.isZero()) {
    const NestedVolume<double> body = bodyVolume(start, yaw);
    report.volumesUpdated += kVolumesPerBody;
    const SweepHit hit = world_.sweep(body, d, report.counters);
    if (hit.contact) {
      const double back = kStopDistance / d.norm();
      // The stop short of the contact at t (a fraction of d); an advance under kMinBlockedAdvance
      // is a creep by roundings: the body stays (walker.h).
      const auto stopAt = [&](double t) { return t * d.norm() < kMinBlockedAdvance ? 0.0 : t; };
      double t = stopAt(hit.t - back);
      // Never end inside: the static test has the last word (it is conservative by its bands).
      for (int i = 0; i < kMaxBackOffs && t > 0.0; ++i) {
        report.volumesUpdated += kVolumesPerBody;
        if (world_.overlapping(bodyVolume(start + d * t, yaw), report.counters) < 0) break;
        t = stopAt(t - back * std::ldexp(1.0, i));
      }
      end = start + d * t;
      if (!state_.flying && t > 0.0) {
        // Back on the ground at the stop (the leg's straight line cuts chords under curved ground).
        const std::optional<double> z = terrain_.groundHeight(end.x(), end.y());
        if (z) {
          const Eigen::Vector3d grounded(end.x(), end.y(), *z);
          report.volumesUpdated += kVolumesPerBody;
          if (world_.overlapping(bodyVolume(grounded, yaw), report.counters) < 0) end = grounded;
        }
      }
      leg.blocked = true;
      leg.reason = BlockReason::Equipment;
      leg.unit = hit.unit;
      leg.normal = hit.normal;
      leg.remaining = d * (1.0 - t);
    }
  }
  state_.feet = end;
  return leg;
}

Eigen::Vector2d Walker::aheadOf(const Eigen::Vector3d& velocity) const {
  Eigen::Vector2d ahead = kPrefetchSeconds * velocity.head<2>();
  const double reach = kPrefetchMaxAheadTiles * terrain::kHeightTileCells * std::min(terrain_.dx(), terrain_.dy());
  if (ahead.norm() > reach) ahead *= reach / ahead.norm();
  return ahead;
}

std::array<double, 4> Walker::groundAhead(const Eigen::Vector2d& feet, const Eigen::Vector3d& velocity) const {
  const Eigen::Vector2d a = feet, b = a + aheadOf(velocity);
  const double m = kPrefetchMarginMetres + 2.0 * std::max(terrain_.dx(), terrain_.dy());
  return {std::min(a.x(), b.x()) - m, std::min(a.y(), b.y()) - m, std::max(a.x(), b.x()) + m, std::max(a.y(), b.y()) + m};
}

void Walker::prefetchGround(const Eigen::Vector3d& velocity, bool force) {
  if (!terrain_.paged()) return;
  const auto [x0, y0, x1, y1] = groundAhead(state_.feet.head<2>(), velocity);
  const auto tiles = terrain_.tilesUnder(x0, y0, x1, y1);
  if (!tiles || (*tiles == prefetchedTiles_ && !force)) return;
  prefetchedTiles_ = *tiles;
  terrain_.prefetch(x0, y0, x1, y1, state_.feet.head<2>(), state_.feet.head<2>() + aheadOf(velocity));
}

StepReport Walker::step(const StepInput& in) {
  StepReport report;
  const std::uint64_t waitsBefore = terrain::HeightTileCache::threadWaits();
  // The whole step is timed, the request for the ground ahead included (it is part of the ground).
  Clock::time_point t0;
  if (options_.timeParts) t0 = Clock::now();
  prefetchGround(in.move / options_.dt, state_.frame % kPrefetchRefreshSteps == 0);
  if (options_.timeParts) report.micros[StepPart::Ground] += microsBetween(t0, Clock::now());

  // 1. View and body yaw.
  state_.headingDeg = in.headingDeg;
  state_.pitchDeg = in.pitchDeg;
  if (state_.bodyYawDeg != in.headingDeg) {
    // The body turns with the view unless the turned body would overlap equipment or its
    // footprint would overhang a hole or the raster's edge (a pose place() refuses; from it, short
    // steps would all fail their first ground sample and the walker would be stuck).
    std::array<double, 5> h{};
    report.volumesUpdated += kVolumesPerBody;
    if (footprintHeights(state_.feet.x(), state_.feet.y(), in.headingDeg, h) &&
        world_.overlapping(bodyVolume(state_.feet, in.headingDeg), report.counters) < 0)
      state_.bodyYawDeg = in.headingDeg;
  }

  // 2-3. Ground and equipment, then slides along the contact plane if asked.
  state_.blocked = false;
  state_.reason = BlockReason::None;
  state_.blockedUnit = -1;
  Eigen::Vector3d move = in.move;
  if (!state_.flying) move.z() = 0;
  for (int k = 0; k <= kMaxSlides; ++k) {
    const Leg leg = walkLeg(move, report);
    if (!leg.blocked) break;
    state_.blocked = true;
    state_.reason = leg.reason;
    state_.blockedUnit = leg.unit;
    if (!options_.slide || leg.reason != BlockReason::Equipment || k == kMaxSlides) break;
    Eigen::Vector3d nrm = leg.normal;
    Eigen::Vector3d rest = leg.remaining;
    if (!state_.flying) {
      nrm.z() = 0;
      rest.z() = 0;
    }
    const double nn = nrm.norm();
    if (!(nn > kNegligibleLength)) break;
    nrm /= nn;
    const double into = rest.dot(nrm);
    if (into < 0) rest -= into * nrm;
    if (!(rest.norm() > kNegligibleLength)) break;
    move = rest;
  }

  Clock::time_point tg;
  if (options_.timeParts) tg = Clock::now();
  const std::optional<double> g = terrain_.groundHeight(state_.feet.x(), state_.feet.y());
  state_.hasGround = g.has_value();
  state_.ground = g.value_or(0.0);
  ++state_.frame;
  state_.time = double(state_.frame) * options_.dt;
  report.groundWaits = terrain::HeightTileCache::threadWaits() - waitsBefore;
  if (options_.timeParts) {
    const Clock::time_point t1 = Clock::now();
    report.micros[StepPart::Ground] += microsBetween(tg, t1);
    report.micros[StepPart::BroadPhase] = report.counters.broadMicros;
    report.micros[StepPart::Narrow] = report.counters.narrowMicros;
    report.micros[StepPart::Total] = microsBetween(t0, t1);
  }
  return report;
}

}  // namespace nestwalk
