// nestwalk run SCENE --script FILE --headless --out DIR: plays a flythrough script on the scene's
// walker without any display and writes, in DIR: frames.csv (a record per step), summary.json,
// frame_times.png and camera.path (an OpenSceneGraph AnimationPath osgviewer replays over
// `nestwalk export`). Exits with 3 when an expectation of the script failed (each is printed with
// its frame and position), with 1 for bad input.
#include "engine/core/input_error.h"
#include "engine/scene/scene.h"
#include "engine/walker/flythrough.h"
#include "tools/nestwalk/commands.h"

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
  std::string volumes, hierarchy, splitAxis, splitPoint;
  int degree = 0;
};

MethodSpec methodFrom(const RunArgs& a, MethodSpec m) {
  if (!a.volumes.empty()) {
    if (a.volumes == "nested") m.volumes = VolumeMethod::Nested;
    else if (a.volumes == "aabb") m.volumes = VolumeMethod::Aabb;
    else if (a.volumes == "obb") m.volumes = VolumeMethod::Obb;
    else throw InputError("--method: expected nested, aabb or obb, got '" + a.volumes + "'");
  }
  if (!a.hierarchy.empty()) {
    if (a.hierarchy == "template") m.templateHierarchy = true;
    else if (a.hierarchy == "auto") m.templateHierarchy = false;
    else throw InputError("--hierarchy: expected auto or template, got '" + a.hierarchy + "'");
  }
  if (a.degree != 0) m.autoTree.degree = a.degree;
  if (!a.splitAxis.empty()) {
    if (a.splitAxis == "longest") m.autoTree.axis = SplitAxis::LongestSide;
    else if (a.splitAxis == "splatter") m.autoTree.axis = SplitAxis::Splatter;
    else throw InputError("--split-axis: expected longest or splatter, got '" + a.splitAxis + "'");
  }
  if (!a.splitPoint.empty()) {
    if (a.splitPoint == "mean") m.autoTree.point = SplitPoint::Mean;
    else if (a.splitPoint == "median") m.autoTree.point = SplitPoint::Median;
    else throw InputError("--split-point: expected mean or median, got '" + a.splitPoint + "'");
  }
  return m;
}

void runRun(const RunArgs& args) {
  namespace fs = std::filesystem;
  const fs::path out(args.out);
  const char* outputs[] = {"frames.csv", "summary.json", "frame_times.png", "camera.path"};
  if (!args.overwrite)
    for (const char* f : outputs)
      if (fs::exists(out / f))
        throw InputError((out / f).string() + ": exists; pass --overwrite to replace the run's outputs");

  const Script script = readScript(args.script);
  const Scene scene = loadScene(args.scene);
  const MethodSpec method = methodFrom(args, scene.spec.method);
  CollisionWorld world = CollisionWorld::fromScene(scene, method);
  world.setTiming(true);
  WalkerOptions options;
  options.viewer = scene.spec.viewer;
  options.dt = 1.0 / args.hz;
  options.slide = args.slide;

  const bool terminal = !args.quiet && isatty(fileno(stderr));
  const FlythroughResult result = runFlythrough(scene, world, script, options, [&](const FrameRecord& r) {
    if (terminal && r.frame % 30 == 0)
      std::fprintf(stderr, "\rframe %6llu  t %7.2f s  eye %.2f %.2f %.2f  %s\033[K",
                   static_cast<unsigned long long>(r.frame), r.time, r.eye.x(), r.eye.y(), r.eye.z(),
                   r.blocked ? ("blocked by " + r.blockedBy).c_str() : "");
  });
  if (terminal) std::fprintf(stderr, "\r\033[K");

  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw InputError(out.string() + ": cannot create the folder: " + ec.message());
  writeFrameCsv((out / "frames.csv").string(), result.records);
  RunSummaryInfo info;
  info.scene = args.scene;
  info.script = args.script;
  info.method = describe(method);
  info.dt = options.dt;
  info.units = world.size();
  writeRunSummary((out / "summary.json").string(), info, result.records, result.expectations);
  writeFrameTimePlot((out / "frame_times.png").string(), result.records);
  writeAnimationPath((out / "camera.path").string(), result.camera);

  std::vector<double> total;
  std::size_t blocked = 0;
  for (const auto& r : result.records) {
    total.push_back(r.micros[3]);
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
  std::printf("  expectations: %zu of %zu met\n", met, result.expectations.size());
  std::printf("  wrote %s/{frames.csv, summary.json, frame_times.png, camera.path}\n", out.string().c_str());
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
  cmd->add_flag("--headless", args->headless, "No display (the only mode until rendering lands)");
  cmd->add_flag("--overwrite", args->overwrite, "Replace the run's files in the output folder");
  cmd->add_flag("--slide", args->slide, "Slide along contact faces instead of stopping");
  cmd->add_flag("--quiet", args->quiet, "No progress line");
  cmd->add_option("--hz", args->hz, "Steps per second (fixed time step 1/hz; default 60)")->check(CLI::Range(1.0, 10000.0));
  cmd->add_option("--method", args->volumes, "Volumes: nested (default), aabb, obb (overrides the scene)");
  cmd->add_option("--hierarchy", args->hierarchy, "Broad phase: auto or template (overrides the scene)");
  cmd->add_option("--degree", args->degree, "Auto hierarchy: children per node, 2, 4 or 8")->check(CLI::IsMember({2, 4, 8}));
  cmd->add_option("--split-axis", args->splitAxis, "Auto hierarchy: longest or splatter");
  cmd->add_option("--split-point", args->splitPoint, "Auto hierarchy: mean or median");
  cmd->callback([args] { runRun(*args); });
}

}  // namespace nestwalk::tools
