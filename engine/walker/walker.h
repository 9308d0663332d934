// The walker: the viewpoint moved one fixed time step at a time, deterministic (same inputs, same
// states, bit for bit). Each step (the wandering method of Ma et al., see geometry/nested.h):
//   1. the view turns to the commanded heading and pitch; the body box turns with it unless the
//      turned box would overlap equipment (then the body keeps its yaw until it is clear);
//   2. ground following (walking): downward rays at the body centre and the four footprint
//      corners, every kGroundSampleSpacing cells along the step. A rise between samples above
//      max_step, a slope along the motion above max_slope_deg, or a sample with no ground (hole,
//      the raster's edge) blocks like a wall: the step ends at the last good sample. Flying: the
//      body bottom is kept at least `clearance` above the highest footprint sample;
//   3. the swept nested test of the step against the equipment (swept.h, collision_world.h): the
//      step stops kStopDistance before the first contact, never inside (checked with the static
//      test, backing off further if rounding says so), and stays blocked while the commanded
//      motion presses into the obstacle (an advance under kMinBlockedAdvance is not made: the body
//      stays put, and the repeated sweep is answered from the last one); with `slide`, the rest of
//      the step is projected on the contact plane and walked again (at most kMaxSlides times).
// Frames: the state is in map coordinates (double); volumes are built in the scene's local frame.
// Units: metres (map frame for positions and moves), seconds (dt, time), degrees (heading, pitch,
// body yaw, max_slope_deg). `origin` is the map point of the scene's local frame (Scene::origin).
// Ownership: the walker keeps references to `terrain` and `world`; both must outlive it.
// Paged terrain (terrain/heightfield.h): the walker asks for the tiles under a box around its feet
// and kPrefetchSeconds of its current motion ahead (when they change), the soonest reached first, so that a walk
// (at 8 m/s: 16 m ahead, two tiles of a 3.2 cm DEM) finds its ground read before it arrives; a step
// that had to wait for a tile counts it (StepReport::groundWaits). place() reads the tiles of the
// box around the feet before it returns (the one wait of a teleport, outside any step).
// Thread safety: a walker is used by one thread (place(), setView() and step() change its state;
// the const members only read). Walkers on different threads may share the Heightfield (immutable,
// no scratch) but not the CollisionWorld: its sweeps write scratch and a cache (collision_world.h),
// so each needs its own.
#pragma once

#include "nestwalk/scene/scene_file.h"
#include "nestwalk/walker/collision_world.h"
#include "nestwalk/walker/frame_record.h"
#include "nestwalk/terrain/heightfield.h"

#include <Eigen/Core>

#include <array>
#include <limits>
#include <optional>
#include <cstdint>
#include <string>

namespace nestwalk {

/// The stop short of a contact, metres along the motion. The gap left to the obstacle along the
/// motion is at most this plus kMinBlockedAdvance (within 1 mm) and positive, so the viewer never
/// ends inside.
inline constexpr double kStopDistance = 0.5e-3;
/// A step blocked by equipment that would advance the body less than this (metres) leaves it where
/// it is (before and after each back-off). Pressing on in the same direction, the sweep meets the
/// same face kStopDistance ahead again, and what is left after the stop is the sweep's rounding and
/// its tie (mesh_tree.h: tens of nanometres in the scene's local frame, where models lie): a
/// creep that would pay two static tests against the model's triangles every frame (2-5 us each on
/// a heavy model: most of the slowest 1 % of steps on tools/data/make_heavy_scene.py's
/// flythroughs). Staying is always allowed: the step's start is where the last step ended, checked
/// then. The same length as a script's kProgressEpsilon (script_player.h), so a script never
/// counted such a creep as progress.
inline constexpr double kMinBlockedAdvance = 1e-6;
/// Ground samples along a step, in cells of the terrain: half a cell, so that no ridge or ditch of
/// the triangulated surface is stepped over between two samples.
inline constexpr double kGroundSampleSpacing = 0.5;
/// Flying legs (Walker::highestFlyingFeet): a range of this many samples or fewer is sampled, not
/// bounded (a ground ceiling costs about what two or three samples of one point cost).
inline constexpr int kFlyingSampledRange = 3;
/// Seconds of motion ahead whose ground a paged terrain reads in the background: a tile takes a few
/// milliseconds to read, 2 s leave a wide margin. The walker asks when the tiles under its box
/// change, and every kPrefetchRefreshSteps steps anyway (so that the cache counts its tiles as
/// used). Asking stores the request for the terrain's reader thread, which orders and looks up the
/// tiles itself (terrain/height_tiles.h, request()); it is timed as part of the step's ground. Done
/// on the step's own thread, the look-ups, the ordering and the wake-up set the step's p99 at 3.2 cm
/// cells (bench render, 2026-11-29: 30 us with them against 7 without; a wake-up alone, 23-93 us
/// against 14-18 with the reader polling, 2026-11-30). The check every step costs nanoseconds.
inline constexpr double kPrefetchSeconds = 2.0;
inline constexpr int kPrefetchRefreshSteps = 600;
/// Metres around the feet whose ground is always asked for: more than the body's half-width and a
/// turn's reach within one prefetch interval.
inline constexpr double kPrefetchMarginMetres = 4.0;
/// The box ahead reaches at most this many tiles (terrain/height_tiles.h) of the terrain: a fast
/// flight over a fine DEM would otherwise ask for a box of hundreds of tiles, most of the budget.
inline constexpr double kPrefetchMaxAheadTiles = 3.0;

/// Slides per step at most (a corner between two obstacles ends the step after two).
inline constexpr int kMaxSlides = 2;

enum class BlockReason : std::uint8_t { None, Equipment, TerrainStep, TerrainSlope, TerrainEdge };
const char* blockReasonName(BlockReason r);  // "", "equipment", "terrain:step", "terrain:slope", "terrain:edge"

struct WalkerOptions {
  ViewerSpec viewer;
  double dt = 1.0 / 60.0;  // seconds per step
  bool slide = false;      // slide along contact faces instead of stopping
  bool timeParts = true;   // measure µs per part (off for benchmarks timing whole steps)
};

struct WalkerState {
  Eigen::Vector3d feet = Eigen::Vector3d::Zero();  // map frame: the ground point under the body
                                                   // centre (walking) or the body bottom (flying)
  double headingDeg = 0, pitchDeg = 0;             // the view
  double bodyYawDeg = 0;                           // the body box's heading
  bool flying = false;
  double clearance = 2.0;                          // flying: body bottom above the ground, at least
  bool blocked = false;                            // the last step was stopped short
  BlockReason reason = BlockReason::None;
  std::int32_t blockedUnit = -1;
  bool hasGround = false;
  double ground = 0;                               // terrain height under the body centre
  std::uint64_t frame = 0;
  double time = 0;
};

struct StepInput {
  Eigen::Vector3d move = Eigen::Vector3d::Zero();  // desired displacement this step, map axes, metres
                                                   // (walking: z is ignored, the ground decides)
  double headingDeg = 0, pitchDeg = 0;             // the view at the end of the step
};

struct StepReport {
  CollisionCounters counters;
  std::uint64_t volumesUpdated = 0;  // Nu: viewer volumes rebuilt
  StepTimes micros;                  // µs per part of the step
  std::uint64_t groundWaits = 0;     // paged terrain: tile reads the step waited for (heightfield.h)
};

/// The body's nested volumes in the local frame (map - `origin`): the box of `viewer`'s half
/// extents standing on `feetMap`, turned to `yawDeg` (forward along the heading). What the walker
/// tests every step, and what a run's contacts are measured from afterwards (report).
NestedVolume<double> bodyVolumeAt(const ViewerSpec& viewer, const Eigen::Vector3d& origin,
                                  const Eigen::Vector3d& feetMap, double yawDeg);

class Walker {
 public:
  Walker(const terrain::Heightfield& terrain, const CollisionWorld& world, const Eigen::Vector3d& origin,
         const WalkerOptions& options);

  // Places the viewer at map (x, y) (walking: on the ground; flying: at z if given, at least
  // `clearance` above the ground). Returns "" or a message saying why the place is not valid
  // (no ground there, inside a unit).
  std::string place(const Eigen::Vector3d& position, bool hasZ, double headingDeg, bool flying, double clearance);
  void setFlying(bool flying, double clearance);
  // Sliding along contact faces (WalkerOptions::slide) from the next step on.
  void setSlide(bool slide) { options_.slide = slide; }
  // Turns the view without a step (the body follows at the next step, if it can).
  void setView(double headingDeg, double pitchDeg) {
    state_.headingDeg = headingDeg;
    state_.pitchDeg = pitchDeg;
  }

  StepReport step(const StepInput& in);

  // Flying: the lowest the feet may be at map (x, y) with the body's current yaw (highest
  // footprint sample plus the clearance); nullopt where there is no ground.
  std::optional<double> lowestFlyingFeet(double x, double y) const;

  const WalkerState& state() const { return state_; }
  const WalkerOptions& options() const { return options_; }
  Eigen::Vector3d eye() const { return state_.feet + Eigen::Vector3d(0, 0, options_.viewer.eyeHeight); }
  // The body's nested volumes (local frame) with its feet at a map point and a yaw (bodyVolumeAt).
  NestedVolume<double> bodyVolume(const Eigen::Vector3d& feetMap, double yawDeg) const;
  const CollisionWorld& world() const { return world_; }
  const terrain::Heightfield& terrain() const { return terrain_; }

 private:
  struct Leg;
  Leg walkLeg(const Eigen::Vector3d& move, StepReport& report);
  // The footprint's half extents along the body's forward and sideways axes (map frame, metres).
  struct Footprint {
    Eigen::Vector2d forward, side;
  };
  Footprint footprintAt(double yawDeg) const;
  // Ground heights at the footprint's centre and four corners (centre, +f+s, +f-s, -f+s, -f-s);
  // false where one has no ground.
  bool footprintHeights(double x, double y, double yawDeg, std::array<double, 5>& h) const;
  bool footprintHeights(double x, double y, const Footprint& footprint, std::array<double, 5>& h) const;
  // Flying legs of n samples: each footprint point's ground ceiling (Heightfield::groundCeiling)
  // over its whole path, in footprintHeights' order (nullopt for n = 0, or where the path may lack
  // ground). A point whose ceiling plus the clearance is at most the lowest height the leg can end
  // at can neither lift the body nor end the leg at an edge: its samples would not change the
  // answer, to the bit, so they are skipped.
  using PathCeilings = std::array<std::optional<double>, 5>;
  PathCeilings flyingPathCeilings(const Eigen::Vector3d& start, const Eigen::Vector3d& move, int n,
                                  const Footprint& footprint) const;
  // The footprint's points at sample k of n of a leg (walkLeg's own expression, to the bit).
  static std::array<Eigen::Vector2d, 5> flyingSamplePoints(const Eigen::Vector3d& start, const Eigen::Vector3d& move,
                                                           int k, int n, const Footprint& footprint);
  // A flying leg with ground under all of it (every ceiling set): max(floorZ, the highest sampled
  // ground + the clearance), exactly as scanning every point at every sample finds it. Branch and
  // bound: the last samples first, then ranges of samples, each skipped whole when its ground
  // ceiling plus the clearance is no higher than the best so far, else split in two; ranges of
  // at most kFlyingSampledRange samples are sampled. Over a fine DEM a fast flight's leg spans
  // dozens of cells (0.67 m at 40 m/s: 42 samples of 5 points at 3.2 cm), most of them under its
  // highest sample. nullopt if a sample has no ground after all (not expected: the caller scans).
  std::optional<double> highestFlyingFeet(const Eigen::Vector3d& start, const Eigen::Vector3d& move, int n,
                                          const Footprint& footprint, const PathCeilings& ceilings,
                                          double floorZ) const;
  // The highest ground among the sampled footprint points at (x, y) (-inf when none is sampled);
  // nullopt when a sampled one has no ground.
  std::optional<double> highestFootprintGround(double x, double y, const Footprint& footprint,
                                               const std::array<bool, 5>& sampled) const;

  const terrain::Heightfield& terrain_;
  const CollisionWorld& world_;
  Eigen::Vector3d origin_;
  WalkerOptions options_;
  WalkerState state_;
  double sampleSpacing_;  // metres
  /// Paged terrain: asks for the tiles around the feet and ahead along `velocity` (m/s, map axes)
  /// when they changed since the last time, or `force`.
  void prefetchGround(const Eigen::Vector3d& velocity, bool force);
  /// The map rectangle {x0, y0, x1, y1} whose ground prefetchGround() asks for: the feet (map x, y),
  /// and kPrefetchSeconds of `velocity` ahead (at most kPrefetchMaxAheadTiles), widened by the margin.
  std::array<double, 4> groundAhead(const Eigen::Vector2d& feet, const Eigen::Vector3d& velocity) const;
  /// Where kPrefetchSeconds of `velocity` take the feet, from them (at most kPrefetchMaxAheadTiles).
  Eigen::Vector2d aheadOf(const Eigen::Vector3d& velocity) const;
  std::array<int, 4> prefetchedTiles_{-1, -1, -1, -1};
};

}  // namespace nestwalk
