// A route (route_source.h) turned into a flythrough script (walker/script.h's format) that `run`,
// `view --script` and `report --scripts` play: `nestwalk route` and `run --route`.
//
// The script: a header comment (the source, its points, length and duration), `mode fly` when
// flying, `speed V` when given, `start X Y [Z] heading H` at the first point facing the first
// segment, then `goto X Y [Z]` to every further point in order. Walking, heights come from the
// ground (the route's own z is ignored); flying, the eye is `height` metres above the ground at
// each point, or at the route's own z without a height. The player turns toward each point at
// its turn rate and goes straight (walker/script_player.h).
// Timed (useTimes): every goto gets `by T`, T the point's time less the first point's, so the
// walk is replayed at its recorded pace, pauses included (a point where the GPS stood still is
// a goto to where the viewer already is: it waits until then). Untimed, points closer than
// kSamePoint to the one before are dropped.
// Stops: each stop (a point of an instruments layer) closer than stopDistance to the route is
// visited once where the route passes nearest to it: the script goes to that point of the route,
// turns and pitches the view toward the stop (its ground plus kStopLookHeight), waits stopWait
// seconds, looks level again and goes on. Timed, the later points' times move by the waits (the
// turns at a stop are made up by hurrying to the next point).
// Numbers are written exactly (the shortest text that reads back to the same double), so the
// played path passes the route's points to rounding.
//
// Errors (InputError, no script): a point outside the terrain or over a hole (the first such
// point named by its source, layer and feature); --use-times on a route without times, whose
// times go backwards, or with a gap over kMaxTimedGap; flying at the route's z on a route without heights; a stop over no ground.
//
// Units: metres, seconds, degrees (headings clockwise from the grid's north). Thread safety: pure
// (reads the terrain's heights).
#pragma once

#include "nestwalk/gis/route_source.h"
#include "nestwalk/terrain/heightfield.h"

#include <Eigen/Core>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace nestwalk::gis {

/// Metres: untimed route points this close to the one before add nothing to the walk (GPS fixes
/// of a standing receiver, a line digitised with a repeated vertex) and are dropped.
inline constexpr double kSamePoint = 1e-3;
/// Metres above a stop's ground that the view is turned to: about the middle of an instrument.
inline constexpr double kStopLookHeight = 1.0;
inline constexpr double kDefaultStopDistance = 10.0;  // metres
/// Seconds: a timed route whose consecutive points are further apart in time is refused (a replay
/// stands through the gap a step at a time: a day's gap is 5 million steps); split the track.
inline constexpr double kMaxTimedGap = 3600.0;
inline constexpr double kDefaultStopWait = 3.0;       // seconds

struct RouteStop {
  Eigen::Vector2d map = Eigen::Vector2d::Zero();  // terrain CRS
  std::string name;                               // for the script's comment
  std::string where;                              // source, layer, feature (messages)
};

struct RouteScriptOptions {
  bool fly = false;
  std::optional<double> height;  // flying: eye metres above the ground (unset: the route's z)
  std::optional<double> speed;   // m/s (unset: the scene's own; ignored when timed)
  bool useTimes = false;
  std::vector<RouteStop> stops;
  double stopDistance = kDefaultStopDistance;
  double stopWait = kDefaultStopWait;
  double eyeHeight = 1.7;  // the scene's (walking: where the view looks at a stop from)
};

struct RouteScript {
  std::string text;
  std::size_t gotos = 0;     // goto lines
  std::size_t dropped = 0;   // untimed points closer than kSamePoint to the one before
  std::size_t stops = 0;     // stops visited
  double length = 0;         // metres, horizontal, along the route
  double duration = 0;       // timed: seconds from the first point to the last, waits included
};

RouteScript routeScript(const Route& route, const terrain::Heightfield& terrain, const RouteScriptOptions& options);

}  // namespace nestwalk::gis
