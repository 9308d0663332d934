#include "nestwalk/gis/route_script.h"

#include "nestwalk/core/angles.h"
#include "nestwalk/core/input_error.h"
#include "nestwalk/core/number_text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <tuple>

namespace nestwalk::gis {
namespace {

std::string at(const Eigen::Vector2d& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, " at (%.3f, %.3f)", p.x(), p.y());
  return buf;
}

/// A point of the script: where the eye goes, and when (seconds after the start; timed scripts).
struct Waypoint {
  Eigen::Vector2d map;
  double eyeZ = 0;  // flying only
  double time = 0;
};

struct StopVisit {
  std::size_t segment = 0;  // from waypoint `segment` to the next
  double along = 0;         // 0..1 along it
  std::size_t stop = 0;
  Eigen::Vector2d map;      // the route's nearest point to the stop
  double distance = 0;
};

class ScriptWriter {
 public:
  explicit ScriptWriter(const RouteScriptOptions& o) : o_(o) {}

  void line(const std::string& s) { text_ += s + "\n"; }
  void go(const char* op, const Eigen::Vector2d& p, double eyeZ, std::optional<double> time) {
    std::string s = std::string(op) + " " + exactText(p.x()) + " " + exactText(p.y());
    if (o_.fly) s += " " + exactText(eyeZ);
    if (time) s += " by " + exactText(*time);
    line(s);
  }
  std::string text() && { return std::move(text_); }

 private:
  const RouteScriptOptions& o_;
  std::string text_;
};

}  // namespace

RouteScript routeScript(const Route& route, const terrain::Heightfield& terrain, const RouteScriptOptions& o) {
  const std::string what = route.source + ": layer '" + route.layer + "'";
  if (o.useTimes) {
    for (std::size_t k = 0; k < route.points.size(); ++k) {
      const RoutePoint& p = route.points[k];
      if (!p.time)
        throw InputError(p.where + ": has no time (--use-times replays the times of GPX track or route points)");
      if (k > 0 && *p.time < *route.points[k - 1].time)
        throw InputError(p.where + ": its time is before the previous point's (the route's times go backwards)");
      if (k > 0 && *p.time - *route.points[k - 1].time > kMaxTimedGap)
        throw InputError(p.where + ": comes " + exactText(*p.time - *route.points[k - 1].time) +
                         " s after the previous point (over an hour: split the track, or replay it without --use-times)");
    }
  }
  if (o.fly && !o.height)
    for (const RoutePoint& p : route.points)
      if (!p.z) throw InputError(p.where + ": has no height (flying at the route's own heights; or give --height)");

  // Every point over ground, each a waypoint (untimed repeats dropped).
  RouteScript out;
  std::vector<Waypoint> way;
  for (const RoutePoint& p : route.points) {
    const std::optional<double> ground = terrain.groundHeight(p.map.x(), p.map.y());
    if (!ground)
      throw InputError(p.where + at(p.map) + ": outside the terrain or over a hole in it (no ground there)");
    if (!o.useTimes && !way.empty() && (p.map - way.back().map).norm() < kSamePoint) {
      ++out.dropped;
      continue;
    }
    Waypoint w;
    w.map = p.map;
    w.eyeZ = o.fly ? (o.height ? *ground + *o.height : *p.z) : 0.0;
    w.time = o.useTimes ? *p.time - *route.points.front().time : 0.0;
    if (!way.empty()) out.length += (w.map - way.back().map).norm();
    way.push_back(w);
  }
  std::size_t firstMove = 0;
  while (firstMove + 1 < way.size() && (way[firstMove + 1].map - way[0].map).norm() < kSamePoint) ++firstMove;
  if (firstMove + 1 >= way.size()) throw InputError(what + ": the route has no length (all its points are one)");

  // Stops: each where the route passes nearest to it, if near enough.
  std::vector<StopVisit> visits;
  for (std::size_t s = 0; s < o.stops.size(); ++s) {
    const Eigen::Vector2d& q = o.stops[s].map;
    if (!terrain.groundHeight(q.x(), q.y()))
      throw InputError(o.stops[s].where + at(q) + ": the stop is outside the terrain or over a hole in it");
    StopVisit best;
    best.distance = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k + 1 < way.size(); ++k) {
      const Eigen::Vector2d a = way[k].map, d = way[k + 1].map - a;
      const double len2 = d.squaredNorm();
      const double u = len2 > 0 ? std::clamp((q - a).dot(d) / len2, 0.0, 1.0) : 0.0;
      const Eigen::Vector2d p = a + u * d;
      const double dist = (q - p).norm();
      if (dist < best.distance) best = {k, u, s, p, dist};
    }
    if (best.distance <= o.stopDistance) visits.push_back(best);
  }
  std::sort(visits.begin(), visits.end(), [](const StopVisit& a, const StopVisit& b) {
    return std::tie(a.segment, a.along, a.stop) < std::tie(b.segment, b.along, b.stop);
  });
  out.stops = visits.size();

  ScriptWriter w(o);
  char length[32];
  std::snprintf(length, sizeof length, "%.1f m", out.length);
  w.line("# nestwalk route: " + what + " (" + std::to_string(route.points.size()) + " points, " +
         std::to_string(route.features) + " line feature(s), CRS " + route.crs + "): " + length +
         (o.useTimes ? ", timed: " + exactText(way.back().time + double(visits.size()) * o.stopWait) + " s" : ""));
  if (out.dropped) w.line("# " + std::to_string(out.dropped) + " point(s) within 1 mm of the one before left out");
  w.line(o.fly ? "mode fly" : "mode walk");
  if (o.speed && !o.useTimes) w.line("speed " + exactText(*o.speed));
  const Eigen::Vector2d firstDir = way[firstMove + 1].map - way[0].map;
  {
    std::string s = "start " + exactText(way[0].map.x()) + " " + exactText(way[0].map.y());
    if (o.fly) s += " " + exactText(way[0].eyeZ);
    w.line(s + " heading " + exactText(headingOf(firstDir.x(), firstDir.y())));
  }
  double shift = 0;  // seconds of stop waits so far (timed)
  auto when = [&](double t) { return o.useTimes ? std::optional<double>(t + shift) : std::nullopt; };
  std::size_t v = 0;
  for (std::size_t k = 0; k + 1 < way.size(); ++k) {
    for (; v < visits.size() && visits[v].segment == k; ++v) {
      const StopVisit& visit = visits[v];
      const RouteStop& stop = o.stops[visit.stop];
      const Waypoint &a = way[k], &b = way[k + 1];
      const double eyeZ = a.eyeZ + visit.along * (b.eyeZ - a.eyeZ);
      w.line("# stop: " + (stop.name.empty() ? stop.where : stop.name) + ", " + exactText(std::round(visit.distance * 1000) / 1000) +
             " m from the route");
      const bool elsewhere = (visit.map - (v > 0 && visits[v - 1].segment == k ? visits[v - 1].map : a.map)).norm() >= kSamePoint;
      if (elsewhere) {
        w.go("goto", visit.map, eyeZ, when(a.time + visit.along * (b.time - a.time)));
        ++out.gotos;
      }
      const Eigen::Vector2d d = stop.map - visit.map;
      const double eye = o.fly ? eyeZ : *terrain.groundHeight(visit.map.x(), visit.map.y()) + o.eyeHeight;
      const double target = *terrain.groundHeight(stop.map.x(), stop.map.y()) + kStopLookHeight;
      if (d.norm() >= kSamePoint) w.line("heading " + exactText(headingOf(d.x(), d.y())));
      w.line("look " + exactText(degrees(std::atan2(target - eye, std::max(d.norm(), kSamePoint)))));
      w.line("wait " + exactText(o.stopWait));
      w.line("look 0");
      shift += o.stopWait;
    }
    w.go("goto", way[k + 1].map, way[k + 1].eyeZ, when(way[k + 1].time));
    ++out.gotos;
  }
  out.duration = o.useTimes ? way.back().time + shift : 0.0;
  out.text = std::move(w).text();
  return out;
}

}  // namespace nestwalk::gis
