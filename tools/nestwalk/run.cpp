// nestwalk run SCENE (--script FILE | --route ROUTE ...) --headless --out DIR [--render ...]: a recorded run
// (session/recorded_run.h: played without a display, optionally rendered offscreen, its files written in
// DIR), its figures printed. Exit 3: an expectation failed (printed with frame and position); 1: bad input.
#include "nestwalk/session/recorded_run.h"
#include "tools/nestwalk/commands.h"
#include "tools/nestwalk/route_options.h"
#include "tools/nestwalk/walk_options.h"

#include <unistd.h>

#include <cstdio>
#include <memory>

namespace nestwalk::tools {
namespace {

struct RunArgs {
  RecordedRunOptions run;
  bool headless = false, quiet = false, render = false, osgCulling = false, noVideo = false, noFrames = false;
  RunRendering rendering;
  std::string size = "1280x720";
  MethodOverrides method;
  TerrainArgs terrain;
  RouteArgs route;  // --route and its options
};

// The run's figures: steps, step times, failed expectations, rendering, files.
void printRun(const RecordedRunOptions& o, const RecordedRun& run) {
  const auto& records = run.flythrough.records;
  std::printf("%s on %s: %zu frames (%.1f s at %g Hz), %zu units, method %s\n", o.script.c_str(), o.scene.c_str(),
              records.size(), records.empty() ? 0.0 : records.back().time, o.hz, run.units, run.method.c_str());
  std::printf("  step time: p50 %.2f us, p99 %.2f us, max %.2f us; %zu frames blocked, %zu contact(s)\n",
              run.stepP50Us, run.stepP99Us, run.stepMaxUs, run.blockedSteps, run.contacts.size());
  for (const auto& e : run.flythrough.expectations)
    if (!e.met)
      std::printf("  FAILED %s:%d: %s at frame %llu, eye (%.3f, %.3f, %.3f): %s\n", e.script.c_str(), e.line,
                  e.text.c_str(), static_cast<unsigned long long>(e.frame), e.eye.x(), e.eye.y(), e.eye.z(),
                  e.detail.c_str());
  if (o.rendering) {
    const auto& p50 = run.renderP50Ms;
    std::printf("  rendered %zu frames at %dx%d (%s, %s): ms per frame p50 %.1f (cull %.1f, draw %.1f, readback %.1f), "
                "p95 %.1f\n", run.framesRendered, o.rendering->view.width, o.rendering->view.height, run.route.c_str(),
                run.glRenderer.c_str(), p50[RenderPart::Total], p50[RenderPart::Cull], p50[RenderPart::Draw],
                p50[RenderPart::Readback], run.renderP95Ms);
    if (run.pngFrames) std::printf("  wrote %zu frames to %s/frames\n", run.pngFrames, o.out.c_str());
    if (o.rendering->video) std::printf("  wrote %s/flythrough.mp4 (%zu frames)\n", o.out.c_str(), run.videoFrames);
  }
  std::printf("  expectations: %zu of %zu met\n", run.expectationsMet, run.flythrough.expectations.size());
  std::printf("  wrote %s/{frames.csv, summary.json, frame_times.png, top_down.png, camera.path, results.gpkg}\n", o.out.c_str());
}

void runRun(RunArgs& args) {
  RecordedRunOptions& o = args.run;
  o.scriptText = scriptOrRoute(o.scene, o.script, args.route);
  o.method = [&args](const MethodSpec& m) { return applyMethodOverrides(args.method, m); };
  if (args.render) {
    std::tie(args.rendering.view.width, args.rendering.view.height) = parseFrameSize(args.size);
    args.rendering.view.nestedCulling = !args.osgCulling;
    args.rendering.frames = !args.noFrames;
    args.rendering.video = !args.noVideo;
    applyTerrainArgs(args.terrain, args.rendering.view);
    o.rendering = args.rendering;
  }
  const bool terminal = !args.quiet && isatty(fileno(stderr));
  if (terminal)
    o.onStep = [](const FrameRecord& r, double renderMs) {
      if (r.frame % 30 == 0)
        std::fprintf(stderr, "\rframe %6llu  t %7.2f s  eye %.2f %.2f %.2f%s  %s\033[K", (unsigned long long)r.frame,
                     r.time, r.eye.x(), r.eye.y(), r.eye.z(),
                     renderMs > 0 ? ("  render " + std::to_string(int(renderMs + 0.5)) + " ms").c_str() : "",
                     r.blocked ? ("blocked by " + r.blockedBy).c_str() : "");
    };
  const RecordedRun run = recordRun(o);
  if (terminal) std::fprintf(stderr, "\r\033[K");
  printRun(o, run);
  if (!run.flythrough.expectationsMet()) throw CLI::RuntimeError(3);
}

}  // namespace

void registerRun(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* cmd = app.add_subcommand("run", "Play a flythrough script on a scene (headless): per-frame CSV, summary, plot, camera path");
  cmd->add_option("SCENE", args->run.scene, "Scene file (JSON, see README)")->required();
  cmd->add_option("--script", args->run.script, "Flythrough script (text, see README) or an osgviewer AnimationPath (.path)");
  addRouteOptions(*cmd, args->route, /*routeOption=*/true);
  cmd->add_option("--out", args->run.out, "Folder for the run's files")->required();
  cmd->add_flag("--headless", args->headless, "No display (nestwalk never opens a window: rendering is offscreen)");
  cmd->add_flag("--render", args->render, "Render the walker's view offscreen: frames/*.png, flythrough.mp4, render times");
  cmd->add_option("--size", args->size, "Rendered frame size, WIDTHxHEIGHT (default 1280x720)");
  cmd->add_option("--every", args->rendering.every, "Render every N-th step (default 1; the video plays at hz/N frames per second)")
      ->check(CLI::Range(1, 1000000));
  cmd->add_flag("--show-volumes", args->rendering.view.volumes, "Draw the equipment's outer AABBs (yellow) and inner OBBs (cyan)");
  cmd->add_flag("--osg-culling", args->osgCulling, "Cull equipment with OSG's bounding spheres instead of the nested volumes");
  cmd->add_flag("--no-video", args->noVideo, "Render without writing flythrough.mp4");
  addTerrainOptions(*cmd, args->terrain, "complete");
  cmd->add_flag("--no-frames", args->noFrames, "Render without writing the PNG frames");
  cmd->add_flag("--overwrite", args->run.overwrite, "Replace the run's files in the output folder");
  cmd->add_flag("--slide", args->run.slide, "Slide along contact faces instead of stopping");
  cmd->add_flag("--quiet", args->quiet, "No progress line");
  cmd->add_option("--hz", args->run.hz, "Steps per second (fixed time step 1/hz; default 60)")->check(CLI::Range(1.0, 10000.0));
  cmd->add_option("--method", args->method.volumes, "Contact test: nested (default), aabb, obb, nested+mesh, kdop18, auto (overrides the scene)");
  cmd->add_option("--hierarchy", args->method.hierarchy, "Broad phase: auto or template (overrides the scene)");
  cmd->add_option("--degree", args->method.degree, "Auto hierarchy: children per node, 2, 4 or 8")->check(CLI::IsMember({2, 4, 8}));
  cmd->add_option("--split-axis", args->method.splitAxis, "Auto hierarchy: longest or splatter");
  cmd->add_option("--split-point", args->method.splitPoint, "Auto hierarchy: mean or median");
  cmd->callback([args] { runRun(*args); });
}

}  // namespace nestwalk::tools
