// A recorded run: a flythrough played on a scene's walker without any display, optionally rendered
// offscreen, and the run's files written into a folder (what `nestwalk run` does; a program that
// links nestwalk::engine does the same with one call):
//   frames.csv (a record per step), summary.json, frame_times.png, top_down.png (the run over the
//   terrain's hillshade), camera.path (an OpenSceneGraph AnimationPath osgviewer replays),
//   results.gpkg and results.geojson (the path, contacts, blocked stretches, expectations and
//   frames as GIS layers, report/result_layers.h); with
//   rendering, frames/frame_NNNNNN.png and flythrough.mp4, and the render times in the same CSV
//   and summary.
//
// Files: every output is written through a temporary file and renamed (core/output_file.h); an
// existing output is replaced only with `overwrite`, and the check comes before anything runs.
// Errors: InputError naming the file (scene, script, an existing output, the folder, ffmpeg missing
// for the video, no offscreen context for rendering). A failed expectation is not an error: the
// result says which (RecordedRun::flythrough.expectations).
// Units: seconds, map coordinates (metres); timings are wall clock (µs per step, ms per frame).
// Thread safety: one run per call; the call owns everything it makes.
#pragma once

#include "nestwalk/render/view_renderer.h"
#include "nestwalk/report/render_record.h"
#include "nestwalk/report/run_contacts.h"
#include "nestwalk/scene/method_spec.h"
#include "nestwalk/walker/flythrough.h"

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace nestwalk {

/// How a recorded run renders: the offscreen renderer's options (its terrain always loads
/// completely: a rendered run is a film, every frame the error rule's full answer), every N-th
/// step, and which of the frames and the video it writes.
struct RunRendering {
  RenderOptions view;
  int every = 1;          // render every N-th step; the video plays at hz / every frames per second
  bool frames = true;     // frames/frame_NNNNNN.png
  bool video = true;      // flythrough.mp4 (needs ffmpeg)
};

inline constexpr const char* kRouteScriptFile = "route_script.txt";

struct RecordedRunOptions {
  std::string scene, script, out;  // scene.json, the script (or a .path), the run's folder
  std::string scriptText;          // not empty: the script itself (a planned route, `script` its source),
                                   // kept in `out` as kRouteScriptFile, which messages and files name
  double hz = 60.0;                // steps per second (the walker's fixed time step is 1 / hz)
  bool slide = false;              // slide along contact faces instead of stopping
  bool overwrite = false;          // replace the run's files in `out`
  /// The contact method from the scene's own (empty: the scene's own).
  std::function<MethodSpec(const MethodSpec& sceneMethod)> method;
  std::optional<RunRendering> rendering;
  /// After each step, on the calling thread: its record and, when rendering, the last frame's ms.
  std::function<void(const FrameRecord& record, double lastRenderMs)> onStep;
};

struct RecordedRun {
  FlythroughResult flythrough;
  std::vector<RenderRecord> renders;  // one per step when rendering (rendered or not), else empty
  std::string method;                 // describe() of the method used
  std::size_t units = 0;              // collision units in the world
  // The figures a run is summed up by (percentiles nearest rank, core/statistics.h).
  double stepP50Us = 0, stepP99Us = 0, stepMaxUs = 0;  // whole step, wall clock
  std::size_t blockedSteps = 0, expectationsMet = 0;
  std::vector<RunContact> contacts;   // the blocking events (report/run_contacts.h)
  double seconds = 0;                 // wall clock of the whole run: load, play, render, files
  double layersSeconds = 0;           // of which the results layers (contacts measured, files written)
  // Rendering (zero or empty without it): ms per rendered frame, p50 by part and p95 in all.
  std::size_t framesRendered = 0, pngFrames = 0, videoFrames = 0;
  std::string route, glRenderer;      // the offscreen route and the GL renderer's name
  EnumArray<RenderPart, kRenderParts> renderP50Ms;
  double renderP95Ms = 0;
};

/// The files a run writes into its folder, by the options (frames/ is a folder).
std::vector<std::string> recordedRunOutputs(const RecordedRunOptions& options);

/// Plays, renders and writes the run (see above).
RecordedRun recordRun(const RecordedRunOptions& options);

/// One rendered frame's statistics as the run's files report them. `sceneInstances`: what counts
/// as drawn when nested culling is off (then every instance goes to OSG's own culling).
RenderRecord renderRecordOf(const RenderFrameStats& stats, std::size_t sceneInstances);

}  // namespace nestwalk
