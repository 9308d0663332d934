// A walk session: the window's loop without the window (`nestwalk view`; walk_window.h
// draws it). It owns the scene, its collision world and the walker, and does what the loop does
// between frames:
//  - the start: --start X Y [HEADING], or the terrain's centre; where that has no ground or stands
//    in equipment, the nearest free ground on rings around it (every kStartRingStep metres,
//    kStartRingDirections directions, out to half the terrain's larger side);
//  - a played script: computed first on its own walker (the steps `nestwalk run` takes), then
//    shown frame by frame, its expectations said as the shown frame reaches them;
//  - recording (R): walk_NNN.txt (a script `run` plays back), walk_NNN.path and the walk as GIS
//    layers, walk_NNN.gpkg and walk_NNN.geojson (report/result_layers.h), in the recording folder,
//    started and stopped by toggleRecording(), fed by recordStep() after each hand step;
//  - each frame's HUD data (viewer/hud.h's HudState), the blocked-by events, and the frame
//    statistics.
// Every event goes to the `say` sink as one line (standard output for `nestwalk view`).
//
// Units: map coordinates (metres), degrees, milliseconds per frame.
// Errors: InputError naming the file or option (the scene, the script, --start, the recording
// folder when it exists without `overwrite`).
// Ownership: the session owns everything it loads; walker() refers to its scene and world.
// Thread safety: one thread (the window's).
#pragma once

#include "nestwalk/render/paged_terrain.h"
#include "nestwalk/render/view_graph.h"
#include "nestwalk/scene/method_spec.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/viewer/hud.h"
#include "nestwalk/walker/collision_world.h"
#include "nestwalk/walker/flythrough.h"
#include "nestwalk/walker/walker.h"

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace nestwalk {

class WalkRecording;

/// The start search's rings: metres between rings, directions per ring.
inline constexpr double kStartRingStep = 5.0;
inline constexpr int kStartRingDirections = 16;

struct WalkSessionOptions {
  std::string scene;               // scene.json
  std::string script;              // a flythrough to play ("": walked by hand)
  std::vector<double> start;       // map X Y [HEADING]; empty: the terrain's centre, heading north
  bool fly = false;                // start flying
  double hz = 60.0;                // walker steps per second
  /// The contact method from the scene's own (empty: the scene's own).
  std::function<MethodSpec(const MethodSpec& sceneMethod)> method;
  std::string recordFolder = "recordings";
  bool overwrite = false;          // write into an existing recording folder
  std::function<void(const std::string& line)> say;  // event lines (may be empty)
};

/// What the window knows of one frame, for the HUD and the events.
struct WalkFrame {
  ViewPose pose;                            // what the camera shows
  const FrameRecord* shown = nullptr;       // the played record shown (playing), else null
  const StepReport* lastStep = nullptr;     // the walker's last step (walking), else null
  int stepsThisFrame = 0;
  bool paused = false;                      // a played script paused
  std::string walkerMessage;                // the manipulator's last mode message ("flying", ...)
  PagedTerrainStats terrain;                // the drawn terrain's figures
  std::size_t terrainBudgetBytes = 0;
};

class WalkSession {
 public:
  explicit WalkSession(WalkSessionOptions options);
  ~WalkSession();
  WalkSession(const WalkSession&) = delete;
  WalkSession& operator=(const WalkSession&) = delete;

  const Scene& scene() const { return scene_; }
  const MethodSpec& method() const { return method_; }
  Walker& walker() { return *walker_; }
  /// The played script's steps and expectations (empty without a script).
  const FlythroughResult& played() const { return played_; }
  bool playsScript() const { return !options_.script.empty(); }

  /// R: starts a recording (the folder made on the first one), or stops the one running and writes
  /// its files. Refused, with a status, while a script plays or when the folder cannot be had.
  void toggleRecording();
  bool recording() const { return recording_ != nullptr; }
  /// After each step the hand takes (the input it took and the step's report), while recording.
  void recordStep(const StepInput& input, const StepReport& report);
  /// The status line (recording, recorded FILE, why a recording did not start).
  const std::string& status() const { return status_; }

  /// A frame about to be drawn: its HUD data (the last frame's times), and its events said
  /// (a new block, expectations the shown frame reached).
  HudState frame(const WalkFrame& frame);
  /// The frame just drawn took `ms`.
  void frameDrawn(double ms) { frameMs_.push_back(ms); }
  std::size_t framesDrawn() const { return frameMs_.size(); }

  /// The end: stops a recording, says where the walk stopped and the frame rate over `seconds`
  /// (the first frame, which compiles the scene's GL objects, left out of the rate).
  void finish(const ViewPose& end, const FrameRecord* shown, double seconds);
  /// Whether a played script met every expectation (true without a script).
  bool expectationsMet() const { return played_.expectationsMet(); }

 private:
  void say(const std::string& line) const;
  void placeAtStart();
  void stopRecording();

  WalkSessionOptions options_;
  Scene scene_;
  MethodSpec method_;
  std::unique_ptr<CollisionWorld> world_;
  WalkerOptions walkerOptions_;
  FlythroughResult played_;
  std::unique_ptr<Walker> walker_;
  std::string crs_, status_;
  std::unique_ptr<WalkRecording> recording_;
  std::vector<FrameRecord> recorded_;  // the recording's steps (its layers)
  std::pair<std::uint64_t, double> recordStart_{0, 0.0};  // frame and time just before its first step
  int recordings_ = 0;
  bool recordFolderMade_ = false;
  bool wasBlocked_ = false;
  std::size_t expectationsSaid_ = 0;
  std::vector<double> frameMs_;
};

/// "eye E N H heading H pitch P" with 17 significant digits (the pose lines of `nestwalk view`).
std::string poseText(const ViewPose& pose);

}  // namespace nestwalk
