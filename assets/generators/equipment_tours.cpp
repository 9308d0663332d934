#include "assets/generators/equipment_tours.h"

#include "assets/generators/equipment_models.h"
#include "assets/generators/footprint_rect.h"
#include "nestwalk/core/angles.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <span>

namespace nestwalk::assets {
namespace {

// The walker's body (scene_file.h defaults): half extents 0.25 m forward and sideways; a turning
// body reaches 0.36 m (the half diagonal).
constexpr double kBodyReach = 0.36;
constexpr double kCorridorMargin = 0.3;      // metres on either side of the body along an approach
constexpr double kWalkRunUp = 2.5;           // metres walked before the face
constexpr double kFlyRunUp = 8.0;            // metres flown before the face
constexpr double kPastTarget = 2.0;          // the goto aims this far past the piece's centre
constexpr double kBackOff = 1.5;             // metres walked or flown back after the block
constexpr double kFlatTolerance = 0.2;       // metres: the walk's ground vs the berm level
constexpr double kWalkSpeed = 1.4, kFlySpeed = 8.0, kHopSpeed = 30.0;  // m/s
constexpr double kHopClearance = 20.0;       // metres above the top for the hops between targets
constexpr double kLowFlight = 0.6;           // metres: the body's bottom above the ground, flying in
constexpr double kEyeHeight = 1.7;           // metres (scene_file.h default)
constexpr double kApproachAngles[] = {0.0, 30.0, -45.0, 60.0, -20.0};
constexpr int kWalkTargetsPerKind = 2, kFlyTargetsPerKind = 1;
// The kinds visited, in this order (their ModelKind's label).
constexpr ModelKind kTargetKinds[] = {ModelKind::SensorPole, ModelKind::Piezometer, ModelKind::SolarPanel,
                                      ModelKind::LoggerBox,  ModelKind::WeatherStation, ModelKind::JerseyBarrier,
                                      ModelKind::Container20ft, ModelKind::Pickup, ModelKind::DrillRig};
constexpr ModelKind kFlyKinds[] = {ModelKind::SensorPole, ModelKind::WeatherStation, ModelKind::SolarPanel,
                                   ModelKind::Container20ft, ModelKind::JerseyBarrier, ModelKind::Pickup,
                                   ModelKind::DrillRig};

std::string fmt(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", x);
  return buf;
}

Eigen::Vector2d turned(const Eigen::Vector2d& d, double degrees) {
  const auto [s, c] = sinCosDegrees(degrees);
  return {c * d.x() + s * d.y(), -s * d.x() + c * d.y()};  // clockwise, as headings turn
}

struct Approach {
  Eigen::Vector2d from, past;
  double heading = 0, angle = 0;
  double ground = 0;  // at `from`
};

class Planner {
 public:
  Planner(const terrain::Heightfield& hf, const std::vector<Placement>& equipment) : hf_(hf), equipment_(equipment) {
    for (const Placement& p : equipment) rects_.push_back(footprintRect(p, modelBounds(p.model)));
  }

  /// The first clear approach to piece `i` (see the header), walking or flying; the angles are
  /// tried from the `first`-th on (so that successive targets are met at different angles).
  std::optional<Approach> approach(std::size_t i, bool walking, std::size_t first) const {
    const Rect& t = rects_[i];
    const double runUp = walking ? kWalkRunUp : kFlyRunUp;
    constexpr std::size_t kAngles = std::size(kApproachAngles);
    for (std::size_t k = 0; k < kAngles; ++k)
      for (const Eigen::Vector2d& normal : {t.ax, Eigen::Vector2d(-t.ax), t.ay, Eigen::Vector2d(-t.ay)}) {
        const double angle = kApproachAngles[(first + k) % kAngles];
        const Eigen::Vector2d dir = turned(-normal, angle);  // the motion: into the face
        Approach a;
        a.angle = angle;
        a.from = t.c - dir * (t.reach(dir) + kBodyReach + runUp);
        a.past = t.c + dir * kPastTarget;
        a.heading = headingOf(dir.x(), dir.y());
        if (clear(i, a.from, t.c, walking, equipment_[i].level, a.ground)) return a;
      }
    return std::nullopt;
  }

 private:
  /// Whether the corridor from `from` to the piece's centre is clear of every other footprint
  /// (a fence's own pieces excepted: they are one unit) and of their axis-aligned boxes at the
  /// start (where the walker lands), on ground all along (walking: at the berm's level).
  bool clear(std::size_t target, const Eigen::Vector2d& from, const Eigen::Vector2d& to, bool walking, double level,
             double& ground) const {
    const Eigen::Vector2d d = to - from;
    const double length = d.norm();
    Rect corridor;
    corridor.ay = d / length;
    corridor.ax = Eigen::Vector2d(corridor.ay.y(), -corridor.ay.x());
    corridor.c = from + 0.5 * d;
    corridor.hx = kBodyReach + kCorridorMargin;
    corridor.hy = 0.5 * length + kBodyReach;
    const Placement& t = equipment_[target];
    for (std::size_t k = 0; k < rects_.size(); ++k) {
      if (k == target || (t.useOnly && equipment_[k].group == t.group)) continue;
      const Rect& r = rects_[k];
      if (rectsOverlap(corridor, r, 0.0)) return false;
      const Eigen::Vector2d boxHalf(std::abs(r.ax.x()) * r.hx + std::abs(r.ay.x()) * r.hy,
                                    std::abs(r.ax.y()) * r.hx + std::abs(r.ay.y()) * r.hy);
      if (((from - r.c).cwiseAbs() - boxHalf).maxCoeff() < kBodyReach + kCorridorMargin)
        return false;  // the start would be inside (or against) another unit's outer AABB
    }
    for (double s = 0.0; s <= length; s += 0.5) {
      const Eigen::Vector2d p = from + corridor.ay * s;
      for (const Eigen::Vector2d& q : {p, Eigen::Vector2d(p + kBodyReach * corridor.ax), Eigen::Vector2d(p - kBodyReach * corridor.ax)}) {
        const std::optional<double> z = hf_.groundHeight(q.x(), q.y());
        if (!z || (walking && std::abs(*z - level) > kFlatTolerance)) return false;
      }
    }
    ground = *hf_.groundHeight(from.x(), from.y());
    return true;
  }

  const terrain::Heightfield& hf_;
  const std::vector<Placement>& equipment_;
  std::vector<Rect> rects_;
};

struct Target {
  std::size_t piece;
  Approach a;
};

/// Up to `perKind` targets of each kind with a clear approach, one per group.
std::vector<Target> chooseTargets(const Planner& planner, const std::vector<Placement>& equipment, bool walking,
                                  std::span<const ModelKind> kinds, int perKind) {
  std::vector<Target> out;
  for (ModelKind kind : kinds) {
    int found = 0;
    std::string lastGroup;
    for (std::size_t i = 0; i < equipment.size() && found < perKind; ++i) {
      const Placement& p = equipment[i];
      if (p.model != kind || p.group == lastGroup) continue;
      // A fence: its middle barrier.
      if (p.useOnly && p.name.find("barrier0") == std::string::npos) continue;
      std::size_t piece = i;
      if (p.useOnly) {
        std::size_t n = 0;
        while (i + n < equipment.size() && equipment[i + n].group == p.group) ++n;
        piece = i + n / 2;
      }
      if (const std::optional<Approach> a = planner.approach(piece, walking, out.size())) {
        out.push_back({piece, *a});
        lastGroup = p.group;
        ++found;
      }
    }
  }
  return out;
}

/// Nearest first from the first target.
void orderByDistance(std::vector<Target>& targets) {
  for (std::size_t k = 1; k < targets.size(); ++k) {
    std::size_t best = k;
    for (std::size_t j = k + 1; j < targets.size(); ++j)
      if ((targets[j].a.from - targets[k - 1].a.from).norm() < (targets[best].a.from - targets[k - 1].a.from).norm())
        best = j;
    std::swap(targets[k], targets[best]);
  }
}

std::string xy(const Eigen::Vector2d& p) { return fmt(p.x()) + " " + fmt(p.y()); }

Tour writeTour(const std::string& file, const std::string& header, const std::vector<Placement>& equipment,
               std::vector<Target> targets, bool walking, double topLevel) {
  orderByDistance(targets);
  Tour tour;
  tour.file = file;
  const double hop = topLevel + kHopClearance;
  std::string& s = tour.text;
  s = header + (walking ? "# Walking at every kind of equipment at angles to its faces: land a few metres off, walk "
                          "at it, be blocked, step back.\n"
                        : "# Flying at every kind of equipment at 8 m/s, the body 0.6 m above the ground, at angles "
                          "to its faces: be blocked, fly back.\n");
  s += "mode fly\nclearance " + fmt(kHopClearance) + "\nspeed " + fmt(kHopSpeed) + "\n";
  s += "start " + xy(targets.front().a.from) + " " + fmt(hop) + " heading " + fmt(targets.front().a.heading) + "\n";
  for (const Target& t : targets) {
    const Placement& p = equipment[t.piece];
    const std::string kind = modelKindLabel(p.model);
    tour.events.push_back({p.group, kind, t.a.angle});
    s += "# " + kind + " " + p.name + ", " + fmt(t.a.angle) + " degrees off its face's normal\n";
    s += "goto " + xy(t.a.from) + " " + fmt(hop) + "\n";
    const double low = t.a.ground + kLowFlight + kEyeHeight;  // the eye, the body's bottom kLowFlight up
    if (walking) {
      s += "mode walk\nspeed " + fmt(kWalkSpeed) + "\nheading " + fmt(t.a.heading) + "\ngoto " + xy(t.a.past) +
           "\nexpect blocked by " + p.group + "\nmove " + fmt(-kBackOff) + "\nexpect free\nmode fly\nspeed " +
           fmt(kHopSpeed) + "\n";
    } else {
      s += "clearance " + fmt(kLowFlight) + "\ngoto " + xy(t.a.from) + " " + fmt(low) + "\nspeed " + fmt(kFlySpeed) +
           "\nheading " + fmt(t.a.heading) + "\ngoto " + xy(t.a.past) + " " + fmt(low) + "\nexpect blocked by " +
           p.group + "\nmove " + fmt(-kBackOff) + "\nexpect free\nclearance " + fmt(kHopClearance) + "\nspeed " +
           fmt(kHopSpeed) + "\n";
    }
  }
  return tour;
}

}  // namespace

std::vector<Tour> equipmentTours(const terrain::Heightfield& hf, const std::vector<Placement>& equipment,
                                 double topLevel, const std::string& header) {
  const Planner planner(hf, equipment);
  return {writeTour("equipment_walk.txt", header, equipment,
                    chooseTargets(planner, equipment, true, kTargetKinds, kWalkTargetsPerKind), true, topLevel),
          writeTour("equipment_fly.txt", header, equipment,
                    chooseTargets(planner, equipment, false, kFlyKinds, kFlyTargetsPerKind), false, topLevel)};
}

}  // namespace nestwalk::assets
