// The recorded run (recorded_run.h): outputs checked, scene and script read, the world built, the
// flythrough played with each step rendered as asked, then the run's files written.
#include "nestwalk/session/recorded_run.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/core/output_file.h"
#include "nestwalk/core/statistics.h"
#include "nestwalk/core/stopwatch.h"
#include "nestwalk/render/frame_writers.h"
#include "nestwalk/report/frame_csv.h"
#include "nestwalk/report/frame_time_plot.h"
#include "nestwalk/report/result_layers.h"
#include "nestwalk/report/run_summary.h"
#include "nestwalk/report/top_down_map.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/walker/animation_path.h"
#include "nestwalk/walker/script_file.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <memory>
#include <stdexcept>

namespace nestwalk {

namespace fs = std::filesystem;

std::vector<std::string> recordedRunOutputs(const RecordedRunOptions& options) {
  std::vector<std::string> outputs = {"frames.csv",  "summary.json", "frame_times.png", "top_down.png",
                                      "camera.path", "results.gpkg", "results.geojson"};
  if (options.rendering) {
    if (options.rendering->frames) outputs.push_back("frames");
    if (options.rendering->video) outputs.push_back("flythrough.mp4");
  }
  if (!options.scriptText.empty()) outputs.push_back(kRouteScriptFile);
  return outputs;
}

RenderRecord renderRecordOf(const RenderFrameStats& s, std::size_t sceneInstances) {
  RenderRecord r;
  r.rendered = true;
  r.triangles = s.triangles;
  r.instancesDrawn = s.cull.instances ? s.cull.visible : sceneInstances;
  r.culledByAabb = s.cull.aabbOutside;
  r.culledByObb = s.cull.obbOutside;
  r.terrainErrorPx = s.terrainErrorPx;
  r.micros[RenderPart::Cull] = 1000.0 * s.cullMs;
  r.micros[RenderPart::Draw] = 1000.0 * s.drawMs;
  r.micros[RenderPart::Readback] = 1000.0 * s.readbackMs;
  r.micros[RenderPart::Total] = 1000.0 * s.totalMs;
  return r;
}

RecordedRun recordRun(const RecordedRunOptions& o) {
  const auto runStart = std::chrono::steady_clock::now();
  const fs::path out(o.out);
  if (!o.overwrite)
    for (const std::string& f : recordedRunOutputs(o))
      if (fs::exists(out / f))
        throw InputError((out / f).string() + ": exists; pass --overwrite to replace the run's outputs");
  const RunRendering* rendering = o.rendering ? &*o.rendering : nullptr;
  if (rendering && rendering->every < 1)
    throw InputError("--every " + std::to_string(rendering->every) + ": render every 1 or more steps");
  if (rendering && rendering->video && !VideoWriter::ffmpegAvailable())
    throw InputError((out / "flythrough.mp4").string() +
                     ": cannot write the video: ffmpeg is not installed (tools/setup-deps.sh installs it; "
                     "--no-video renders without it)");

  // A script given as text (a planned route) is kept in the run's folder, and named by it.
  const std::string scriptFile = o.scriptText.empty() ? o.script : (out / kRouteScriptFile).string();
  const Script script = o.scriptText.empty() ? readScript(o.script) : parseScript(o.scriptText, scriptFile);
  const Scene scene = loadScene(o.scene);
  const MethodSpec method = o.method ? o.method(scene.spec.method) : scene.spec.method;
  CollisionWorld world = CollisionWorld::fromScene(scene, method);
  world.setTiming(true);
  WalkerOptions walker;
  walker.viewer = scene.spec.viewer;
  walker.dt = 1.0 / o.hz;
  walker.slide = o.slide;

  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw InputError(out.string() + ": cannot create the folder: " + ec.message());

  RecordedRun run;
  run.method = describe(method);
  run.units = world.size();
  std::unique_ptr<ViewRenderer> renderer;
  std::unique_ptr<PngSequenceWriter> pngs;
  std::unique_ptr<VideoWriter> video;
  if (rendering) {
    RenderOptions view = rendering->view;
    view.terrainLoading = TerrainLoading::Complete;
    try {
      renderer = std::make_unique<ViewRenderer>(scene, view);
    } catch (const std::runtime_error& e) {
      throw InputError(std::string("--render: ") + e.what());
    }
    run.route = offscreenRouteName(renderer->route());
    run.glRenderer = renderer->glRenderer();
    if (rendering->frames) pngs = std::make_unique<PngSequenceWriter>((out / "frames").string());
    if (rendering->video)
      video = std::make_unique<VideoWriter>((out / "flythrough.mp4").string(), view.width, view.height,
                                            o.hz / rendering->every);
  }

  double lastRenderMs = 0;
  run.flythrough = runFlythrough(scene, world, script, walker, [&](const FrameRecord& r) {
    if (renderer && (r.frame - 1) % std::uint64_t(rendering->every) == 0) {
      const RenderFrameStats& s = renderer->render({r.eye, r.headingDeg, r.pitchDeg, r.blocked, r.blockedBy});
      run.renders.push_back(renderRecordOf(s, scene.instances.size()));
      ++run.framesRendered;
      lastRenderMs = s.totalMs;
      if (pngs) pngs->write(renderer->image(), r.frame);
      if (video) video->addFrame(renderer->image());
    } else if (renderer) {
      run.renders.emplace_back();  // not rendered
    }
    if (o.onStep) o.onStep(r, lastRenderMs);
  });
  if (pngs) run.pngFrames = pngs->finish();
  if (video) {
    video->finish();
    run.videoFrames = video->frames();
  }

  const FlythroughResult& f = run.flythrough;
  std::vector<double> stepUs;
  for (const FrameRecord& r : f.records) {
    stepUs.push_back(r.micros[StepPart::Total]);
    run.blockedSteps += r.blocked;
  }
  run.stepP50Us = percentile(stepUs, 50);
  run.stepP99Us = percentile(stepUs, 99);
  run.stepMaxUs = percentile(stepUs, 100);
  for (const ExpectationResult& e : f.expectations) run.expectationsMet += e.met;
  EnumArray<RenderPart, kRenderParts, std::vector<double>> ms;
  for (const RenderRecord& r : run.renders)
    for (RenderPart part : kAllRenderParts)
      if (r.rendered) ms[part].push_back(r.micros[part] / 1000.0);
  for (RenderPart part : kAllRenderParts) run.renderP50Ms[part] = percentile(ms[part], 50);
  run.renderP95Ms = percentile(ms[RenderPart::Total], 95);

  writeFrameCsv((out / "frames.csv").string(), f.records, run.renders);
  RunSummaryInfo info;
  info.scene = o.scene;
  info.script = scriptFile;
  if (!o.scriptText.empty()) writeFileAtomically(scriptFile, o.scriptText);
  info.method = run.method;
  info.dt = walker.dt;
  info.units = run.units;
  if (renderer) {
    const RenderOptions& view = rendering->view;
    nlohmann::ordered_json r;
    r["route"] = run.route;
    r["gl_renderer"] = run.glRenderer;
    r["size"] = {view.width, view.height};
    r["every"] = rendering->every;
    r["culling"] = view.nestedCulling ? "nested (outer AABB, then inner OBB)" : "osg bounding spheres";
    r["near_far"] = {renderer->nearPlane(), renderer->farPlane()};
    info.renderInfoJson = r.dump();
  }
  writeRunSummary((out / "summary.json").string(), info, f.records, f.expectations, run.renders);
  writeFrameTimePlot((out / "frame_times.png").string(), f.records, run.renders);
  writeTopDownMap((out / "top_down.png").string(), scene, f.records, f.expectations);
  writeAnimationPath((out / "camera.path").string(), f.camera);
  const auto layersStart = std::chrono::steady_clock::now();
  run.contacts = runContacts(scene, f.records, world.meshes().get());
  writeResultLayers((out / "results").string(), scene.terrain->crsWkt(), info, f.records, f.expectations, run.contacts, run.renders);
  run.layersSeconds = secondsSince(layersStart);
  run.seconds = secondsSince(runStart);
  return run;
}

}  // namespace nestwalk
