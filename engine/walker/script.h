// Flythrough scripts: a small line-based text format (documented for users in README.md,
// "Flythrough scripts"). One command per line; '#' starts a comment; numbers are metres, seconds,
// degrees and metres per second; headings are clockwise from north (map +y), pitch positive up.
//
//   mode walk | fly          walking follows the ground; flying keeps z, at least `clearance` up
//   speed V                  m/s for the following moves (default: the scene's viewer speed)
//   clearance C              flying: lowest body bottom above the ground (default: the scene's)
//   start X Y [Z] [heading H]  place the viewer (map coordinates); once, before any motion
//   goto X Y [Z] [by T]      turn toward the point and go there in a straight line; with `by T`,
//                            arrive T seconds after the start (the speed that takes, see below)
//   move D                   go D metres along the current heading (negative: backwards)
//   move DX DY [DZ]          relative move in map axes (east, north, up)
//   turn A                   turn by A degrees (positive: clockwise, to the right)
//   heading H                turn to heading H
//   look P                   pitch the view to P degrees
//   wait T                   stand still for T seconds
//   expect blocked [by NAME] the last step was blocked (by the unit NAME or one in group NAME)
//   expect free              the last step was not blocked
//   expect ground within TOL walking: the eye is eye_height above the terrain, within TOL metres
//   expect position X Y within TOL   horizontal distance to (X, Y) at most TOL
//   expect clearance at least C      flying: body bottom at least C above the ground
//
// A motion command ends when its target is reached or when the viewer has not moved for
// `kBlockedTimeout` seconds (it is blocked); the script then goes on with the next line.
// A timed `goto ... by T` (a route replayed at its recorded pace, gis/route_script.h) turns first,
// then moves at the speed that arrives at the step nearest T seconds after `start` (at least one
// step; a target already reached waits until then): late after a contact, it hurries on.
// Errors name the file and line ("patrol.txt:12: goto: expected 2 or 3 numbers, got 1").
//
// Thread safety: pure functions (readScript reads the file).
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace nestwalk {

enum class ScriptOp : std::uint8_t {
  Mode, Speed, Clearance, Start, Goto, Move, MoveBy, Turn, Heading, Look, Wait,
  ExpectBlocked, ExpectFree, ExpectGround, ExpectPosition, ExpectClearance,
};

const char* scriptOpName(ScriptOp op);  // the keyword(s) as written: "goto", "expect blocked", ...

struct ScriptCommand {
  ScriptOp op = ScriptOp::Wait;
  int line = 0;                    // 1-based line in the source
  Eigen::Vector3d v = Eigen::Vector3d::Zero();  // numeric arguments, by op:
                                   //  Speed/Clearance/Turn/Heading/Look/Wait/Move: v.x()
                                   //  Start/Goto/MoveBy: x y [z]; ExpectPosition: x y, tol in `tolerance`
  bool hasZ = false;               // Start/Goto/MoveBy gave a z
  bool hasHeading = false;         // Start: `heading H` given, in `heading`
  bool hasTime = false;            // Goto: `by T` given, in `time` (seconds after `start`)
  double time = 0;
  double heading = 0;
  double tolerance = 0;            // ExpectGround/ExpectPosition: TOL; ExpectClearance: C
  bool fly = false;                // Mode: true for fly
  std::string name;                // ExpectBlocked: NAME ("" = by anything)
};

struct Script {
  std::string path;                // as given, for messages
  std::vector<ScriptCommand> commands;
};

inline constexpr double kBlockedTimeout = 0.5;  // seconds without progress that end a motion command

Script parseScript(const std::string& text, const std::string& path);  // throws InputError

}  // namespace nestwalk
