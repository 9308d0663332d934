// The rendering benchmark (`nestwalk bench render`): the bundled scene rendered offscreen
// (software OpenGL where there is no GPU) along its flythroughs, the walker's view at the poses
// the walker takes. Per configuration: median and p95 ms per frame, split into cull, draw and
// readback, triangles drawn and the terrain's vertical error on screen. Configurations: the
// default (terrain LOD at 1 px of error, nested culling), the same with OSG's bounding-sphere
// culling, the terrain at full resolution (no LOD: error 0) and LOD at 0.5, 2 and 4 px (speed
// against error), and the two ways of paging the terrain on the same poses, each pose
// settled (rendered until the terrain is the error rule's full answer) before its timed frame: the
// own quadtree (paged_terrain.h) and osg::PagedLOD with the viewer's DatabasePager
// (peers/osg_paged_lod_terrain.h, drawn through the renderer's terrain hook), each with the time from a new renderer to its first complete frame
// (background loading). The view culling itself is compared on the same frames: instances kept and µs
// per frame for the nested volumes and for OSG's spheres. Target: 30 frames per second.
#pragma once

#include "tools/bench/bench_runner.h"
#include "tools/bench/bench_document.h"

#include "nestwalk/render/frame_stats.h"

#include <functional>
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

namespace nestwalk {
class ViewRenderer;
struct Scene;
struct ViewPose;
}  // namespace nestwalk

namespace nestwalk::bench {

struct RenderBenchOptions : BenchOptions {
  int width = 1280, height = 720;    // quick: 320 x 180
  int framesPerScript = 120;         // poses sampled evenly along each flythrough; quick: 8
  std::string scene;                 // scene file
  std::vector<std::string> scripts;  // its flythroughs
  // The terrain-size sweep (render_terrain_sweep.h) instead of the configurations: on when
  // --terrain-sizes or --terrain-cells is given.
  bool terrainSweep = false;
  std::vector<double> terrainSizes;  // metres; empty: the sweep's defaults
  std::vector<double> terrainCells;  // metres: the finer sweep (the 1000 m dump at these cells); empty: the wider one
  std::string terrainCache;          // folder of the generated DEMs; empty: the default
  std::string sweepChild;            // hidden: a sweep child's request file (it measures one size)
  /// Orthophotos to drape instead of the scene's own, a settled row each, beside a row of the
  /// scene's imagery at the DEM's resolution (make-terrain --ortho-pixel makes the bundled dump's).
  std::vector<std::string> imagery;

  // What a run uses (the configurations and the sweep alike): with quick, 320 x 180 and 8 frames.
  int runWidth() const { return quick ? 320 : width; }
  int runHeight() const { return quick ? 180 : height; }
  int runFramesPerScript() const { return quick ? 8 : framesPerScript; }
};

/// Settling a pose: frames rendered at most (each after waiting for the pager or loader) before its
/// terrain is taken as it stands. The loaders answer each frame's wants in full, so a view settles
/// within a few frames (one per level it refines: 5 for PagedLOD on the bundled 1 km DEM at 64
/// cells a chunk); this only bounds a view the budget keeps from settling.
inline constexpr int kMaxSettleFrames = 64;

/// The document of a rendering run (`benchmark`: "render" or "render terrain sweep"): its title,
/// and in its JSON "benchmark", "cpu", "size" (the run's), "scene", the fields of `more` and
/// "flythroughs" (empty; filled by sampleFlythroughPoses).
Document renderDocument(const std::string& title, const std::string& benchmark, const RenderBenchOptions& opts,
                        const Json& more = Json::object());

/// The text lines of the run's frame size with the GL renderer and route (once a frame has given
/// them: "320x180, llvmpipe (...) (pbuffer)"), and of the frames each flythrough gave ("frames:
/// SCRIPT N ..."), then `legend`.
void printRenderSetup(Document& doc, const std::string& legend);

/// A figure of a frame's paged terrain (PagedTerrainStats::*), read from the frame's statistics
/// (for record_statistics.h).
template <class T>
auto terrainFigure(T PagedTerrainStats::*figure) {
  return [figure](const RenderFrameStats& s) { return s.terrain.*figure; };
}

/// Settles a pose: renders it until done(frame) or kMaxSettleFrames frames, calling wait() (the
/// pager's or loader's) between two frames; without a wait, one frame. With `rendered`, the
/// renderer's last frame is the pose's first and up to kMaxSettleFrames more are rendered. Returns
/// the frames (that one included) and whether the last was done (its figures:
/// renderer.lastStats()).
std::pair<int, bool> settlePose(ViewRenderer& renderer, const ViewPose& pose, bool (*done)(const RenderFrameStats&),
                                const std::function<void()>& wait, bool rendered = false);

/// Renders the configurations (quick: the first two) and prints their table, the culling
/// comparison and the target (or one JSON document) to `out`. Returns 0. With terrainSweep (or
/// sweepChild) set, runs the terrain-size sweep (or its child) instead (render_terrain_sweep.h).
int runBenchmark(const RenderBenchOptions& opts, std::ostream& out);

/// The benchmark's poses: each of opts.scripts walked once on `scene` (no rendering), `perScript`
/// of its frames sampled evenly; appends {"script", "frames"} per flythrough to `flythroughs`.
std::vector<ViewPose> sampleFlythroughPoses(const Scene& scene, const RenderBenchOptions& opts, int perScript,
                                            Json& flythroughs);

}  // namespace nestwalk::bench
