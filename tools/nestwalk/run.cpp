// nestwalk run SCENE --script FILE --headless --out DIR [--render ...]: plays a flythrough script
// on the scene's walker without any display and writes, in DIR: frames.csv (a record per step),
// summary.json, frame_times.png, top_down.png (the run over the terrain's hillshade) and camera.path
// (an OpenSceneGraph AnimationPath osgviewer replays over `nestwalk export`). With --render it also renders the walker's view offscreen (every N-th
// step) into frames/frame_NNNNNN.png and flythrough.mp4, with the render times in the same CSV and
// summary. Exits with 3 when an expectation of the script failed (each is printed with its frame
// and position), with 1 for bad input.
#include "nestwalk/core/input_error.h"
#include "nestwalk/render/frame_writers.h"
#include "nestwalk/render/view_renderer.h"
#include "nestwalk/core/statistics.h"
#include "nestwalk/report/frame_csv.h"
#include "nestwalk/report/frame_time_plot.h"
#include "nestwalk/report/run_summary.h"
#include "nestwalk/report/top_down_map.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/walker/flythrough.h"
#include "nestwalk/walker/script_file.h"
#include "tools/nestwalk/commands.h"
#include "tools/nestwalk/walk_options.h"

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

namespace nestwalk::tools {
namespace {

struct RunArgs {
  std::string scene, script, out;
  bool headless = false, overwrite = false, slide = false, quiet = false;
  double hz = 60.0;
  MethodOverrides method;
  // Rendering.
  bool render = false, showVolumes = false, noVideo = false, noFrames = false, osgCulling = false;
  std::string size = "1280x720";
  int every = 1;
  TerrainArgs terrain;
};

void runRun(const RunArgs& args) {
  namespace fs = std::filesystem;
  const fs::path out(args.out);
  std::vector<std::string> outputs = {"frames.csv", "summary.json", "frame_times.png", "top_down.png", "camera.path"};
  if (args.render) {
    if (!args.noFrames) outputs.push_back("frames");
    if (!args.noVideo) outputs.push_back("flythrough.mp4");
  }
  if (!args.overwrite)
    for (const std::string& f : outputs)
      if (fs::exists(out / f))
        throw InputError((out / f).string() + ": exists; pass --overwrite to replace the run's outputs");
  const auto [width, height] = parseFrameSize(args.size);
  if (args.render && !args.noVideo && !VideoWriter::ffmpegAvailable())
    throw InputError((out / "flythrough.mp4").string() +
                     ": cannot write the video: ffmpeg is not installed (tools/setup-deps.sh installs it; "
                     "--no-video renders without it)");

  const Script script = readScript(args.script);
  const Scene scene = loadScene(args.scene);
  const MethodSpec method = applyMethodOverrides(args.method, scene.spec.method);
  CollisionWorld world = CollisionWorld::fromScene(scene, method);
  world.setTiming(true);
  WalkerOptions options;
  options.viewer = scene.spec.viewer;
  options.dt = 1.0 / args.hz;
  options.slide = args.slide;

  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw InputError(out.string() + ": cannot create the folder: " + ec.message());

  std::unique_ptr<ViewRenderer> renderer;
  std::unique_ptr<PngSequenceWriter> pngs;
  std::unique_ptr<VideoWriter> video;
  if (args.render) {
    RenderOptions ro;
    ro.width = width;
    ro.height = height;
    ro.volumes = args.showVolumes;
    ro.nestedCulling = !args.osgCulling;
    // A rendered run is a film: every frame the error rule's full answer, the same on every run.
    ro.terrainLoading = TerrainLoading::Complete;
    applyTerrainArgs(args.terrain, ro);
    try {
      renderer = std::make_unique<ViewRenderer>(scene, ro);
    } catch (const std::runtime_error& e) {
      throw InputError(std::string("--render: ") + e.what());
    }
    if (!args.noFrames) pngs = std::make_unique<PngSequenceWriter>((out / "frames").string());
    if (!args.noVideo)
      video = std::make_unique<VideoWriter>((out / "flythrough.mp4").string(), width, height, args.hz / args.every);
  }

  const bool terminal = !args.quiet && isatty(fileno(stderr));
  double lastRenderMs = 0;
  std::vector<RenderRecord> renders;  // one per frame when rendering
  const FlythroughResult result = runFlythrough(scene, world, script, options, [&](const FrameRecord& r) {
    if (renderer && (r.frame - 1) % std::uint64_t(args.every) == 0) {
      RenderRecord& rr = renders.emplace_back();
      const RenderFrameStats& s =
          renderer->render({r.eye, r.headingDeg, r.pitchDeg, r.blocked, r.blockedBy});
      rr.rendered = true;
      rr.triangles = s.triangles;
      rr.instancesDrawn = s.cull.instances ? s.cull.visible : scene.instances.size();
      rr.culledByAabb = s.cull.aabbOutside;
      rr.culledByObb = s.cull.obbOutside;
      rr.terrainErrorPx = s.terrainErrorPx;
      rr.micros[RenderPart::Cull] = 1000.0 * s.cullMs;
      rr.micros[RenderPart::Draw] = 1000.0 * s.drawMs;
      rr.micros[RenderPart::Readback] = 1000.0 * s.readbackMs;
      rr.micros[RenderPart::Total] = 1000.0 * s.totalMs;
      lastRenderMs = s.totalMs;
      if (pngs) pngs->write(renderer->image(), r.frame);
      if (video) video->addFrame(renderer->image());
    } else if (renderer) {
      renders.emplace_back();  // not rendered
    }
    if (terminal && r.frame % 30 == 0)
      std::fprintf(stderr, "\rframe %6llu  t %7.2f s  eye %.2f %.2f %.2f%s  %s\033[K",
                   static_cast<unsigned long long>(r.frame), r.time, r.eye.x(), r.eye.y(), r.eye.z(),
                   renderer ? ("  render " + std::to_string(int(lastRenderMs + 0.5)) + " ms").c_str() : "",
                   r.blocked ? ("blocked by " + r.blockedBy).c_str() : "");
  });
  if (terminal) std::fprintf(stderr, "\r\033[K");
  std::size_t pngCount = pngs ? pngs->finish() : 0;
  if (video) video->finish();
  writeFrameCsv((out / "frames.csv").string(), result.records, renders);
  RunSummaryInfo info;
  info.scene = args.scene;
  info.script = args.script;
  info.method = describe(method);
  info.dt = options.dt;
  info.units = world.size();
  if (renderer) {
    nlohmann::ordered_json r;
    r["route"] = offscreenRouteName(renderer->route());
    r["gl_renderer"] = renderer->glRenderer();
    r["size"] = {width, height};
    r["every"] = args.every;
    r["culling"] = args.osgCulling ? "osg bounding spheres" : "nested (outer AABB, then inner OBB)";
    r["near_far"] = {renderer->nearPlane(), renderer->farPlane()};
    info.renderInfoJson = r.dump();
  }
  writeRunSummary((out / "summary.json").string(), info, result.records, result.expectations, renders);
  writeFrameTimePlot((out / "frame_times.png").string(), result.records, renders);
  writeTopDownMap((out / "top_down.png").string(), scene, result.records, result.expectations);
  writeAnimationPath((out / "camera.path").string(), result.camera);

  std::vector<double> total;
  std::size_t blocked = 0;
  for (const auto& r : result.records) {
    total.push_back(r.micros[StepPart::Total]);
    blocked += r.blocked;
  }
  std::printf("%s on %s: %zu frames (%.1f s at %g Hz), %zu units, method %s\n", args.script.c_str(),
              args.scene.c_str(), result.records.size(), result.records.empty() ? 0.0 : result.records.back().time,
              args.hz, world.size(), info.method.c_str());
  std::printf("  step time: p50 %.2f us, p99 %.2f us, max %.2f us; %zu frames blocked\n", percentile(total, 50),
              percentile(total, 99), percentile(total, 100), blocked);
  std::size_t met = 0;
  for (const auto& e : result.expectations) {
    met += e.met;
    if (!e.met)
      std::printf("  FAILED %s:%d: %s at frame %llu, eye (%.3f, %.3f, %.3f): %s\n", e.script.c_str(), e.line,
                  e.text.c_str(), static_cast<unsigned long long>(e.frame), e.eye.x(), e.eye.y(), e.eye.z(),
                  e.detail.c_str());
  }
  if (renderer) {
    EnumArray<RenderPart, kRenderParts, std::vector<double>> ms;
    std::size_t frames = 0;
    for (const RenderRecord& r : renders)
      if (r.rendered) {
        ++frames;
        for (RenderPart part : kAllRenderParts) ms[part].push_back(r.micros[part] / 1000.0);
      }
    std::printf("  rendered %zu frames at %dx%d (%s, %s): ms per frame p50 %.1f (cull %.1f, draw %.1f, readback %.1f), "
                "p95 %.1f\n",
                frames, width, height, offscreenRouteName(renderer->route()), renderer->glRenderer().c_str(),
                percentile(ms[RenderPart::Total], 50), percentile(ms[RenderPart::Cull], 50),
                percentile(ms[RenderPart::Draw], 50), percentile(ms[RenderPart::Readback], 50),
                percentile(ms[RenderPart::Total], 95));
    if (pngCount) std::printf("  wrote %zu frames to %s\n", pngCount, (out / "frames").string().c_str());
    if (video) std::printf("  wrote %s (%zu frames)\n", (out / "flythrough.mp4").string().c_str(), video->frames());
  }
  std::printf("  expectations: %zu of %zu met\n", met, result.expectations.size());
  std::printf("  wrote %s/{frames.csv, summary.json, frame_times.png, top_down.png, camera.path}\n", out.string().c_str());
  if (met != result.expectations.size()) throw CLI::RuntimeError(3);
}

}  // namespace

void registerRun(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* cmd = app.add_subcommand("run", "Play a flythrough script on a scene (headless): per-frame CSV, summary, plot, camera path");
  cmd->add_option("SCENE", args->scene, "Scene file (JSON, see README)")->required();
  cmd->add_option("--script", args->script, "Flythrough script (text, see README) or an osgviewer AnimationPath (.path)")
      ->required();
  cmd->add_option("--out", args->out, "Folder for the run's files")->required();
  cmd->add_flag("--headless", args->headless, "No display (nestwalk never opens a window: rendering is offscreen)");
  cmd->add_flag("--render", args->render, "Render the walker's view offscreen: frames/*.png, flythrough.mp4, render times");
  cmd->add_option("--size", args->size, "Rendered frame size, WIDTHxHEIGHT (default 1280x720)");
  cmd->add_option("--every", args->every, "Render every N-th step (default 1; the video plays at hz/N frames per second)")
      ->check(CLI::Range(1, 1000000));
  cmd->add_flag("--show-volumes", args->showVolumes, "Draw the equipment's outer AABBs (yellow) and inner OBBs (cyan)");
  cmd->add_flag("--osg-culling", args->osgCulling, "Cull equipment with OSG's bounding spheres instead of the nested volumes");
  cmd->add_flag("--no-video", args->noVideo, "Render without writing flythrough.mp4");
  addTerrainOptions(*cmd, args->terrain, "complete");
  cmd->add_flag("--no-frames", args->noFrames, "Render without writing the PNG frames");
  cmd->add_flag("--overwrite", args->overwrite, "Replace the run's files in the output folder");
  cmd->add_flag("--slide", args->slide, "Slide along contact faces instead of stopping");
  cmd->add_flag("--quiet", args->quiet, "No progress line");
  cmd->add_option("--hz", args->hz, "Steps per second (fixed time step 1/hz; default 60)")->check(CLI::Range(1.0, 10000.0));
  cmd->add_option("--method", args->method.volumes, "Contact test: nested (default), aabb, obb, nested+mesh, kdop18, auto (overrides the scene)");
  cmd->add_option("--hierarchy", args->method.hierarchy, "Broad phase: auto or template (overrides the scene)");
  cmd->add_option("--degree", args->method.degree, "Auto hierarchy: children per node, 2, 4 or 8")->check(CLI::IsMember({2, 4, 8}));
  cmd->add_option("--split-axis", args->method.splitAxis, "Auto hierarchy: longest or splatter");
  cmd->add_option("--split-point", args->method.splitPoint, "Auto hierarchy: mean or median");
  cmd->callback([args] { runRun(*args); });
}

}  // namespace nestwalk::tools
