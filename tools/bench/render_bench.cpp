// The rendering benchmark (render_bench.h).
#include "tools/bench/render_bench.h"

#include "nestwalk/render/view_renderer.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/walker/flythrough.h"
#include "tools/bench/bench_runner.h"

#include <osg/Timer>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <numeric>

namespace nestwalk::bench {
namespace {

struct Config {
  std::string name;
  double lodPixels;
  bool nestedCulling;
};

struct ConfigResult {
  Config config;
  std::size_t frames = 0;
  double firstFrameMs = 0, setupMs = 0;
  double p50 = 0, p95 = 0, cull = 0, draw = 0, readback = 0;  // ms (cull/draw/readback: medians)
  double meanTriangles = 0, maxTriangles = 0, maxErrorPx = 0, maxErrorM = 0;
};

struct CullComparison {
  std::size_t frames = 0;
  double nestedKept = 0, nestedAabbCulled = 0, nestedObbCulled = 0, nestedObbTested = 0, nestedMicros = 0;
  double sphereKept = 0, sphereMicros = 0;
  std::size_t framesNestedKeptMore = 0;
};

double median(std::vector<double> v) { return percentile(std::move(v), 50); }

}  // namespace

int runRenderBench(const RenderBenchOptions& o, std::ostream& out) {
  const Scene scene = loadScene(o.scene);
  const int width = o.quick ? 320 : o.width, height = o.quick ? 180 : o.height;
  const int perScript = o.quick ? 8 : o.framesPerScript;

  // The poses: each flythrough walked once (no rendering), sampled evenly.
  std::vector<ViewPose> poses;
  std::vector<std::pair<std::string, std::size_t>> scriptFrames;
  {
    WalkerOptions wo;
    wo.viewer = scene.spec.viewer;
    wo.timeParts = false;
    const CollisionWorld world = CollisionWorld::fromScene(scene, scene.spec.method);
    for (const std::string& path : o.scripts) {
      const FlythroughResult r = runFlythrough(scene, world, readScript(path), wo);
      const std::size_t n = r.records.size();
      const std::size_t take = std::min<std::size_t>(n, std::size_t(perScript));
      for (std::size_t k = 0; k < take; ++k) {
        const FrameRecord& f = r.records[k * n / take];
        poses.push_back({f.eye, f.headingDeg, f.pitchDeg, f.blocked, f.blockedBy});
      }
      scriptFrames.emplace_back(std::filesystem::path(path).stem().string(), take);
    }
  }

  std::vector<Config> configs = {{"LOD 1 px, nested culling", 1.0, true}, {"LOD 1 px, OSG sphere culling", 1.0, false}};
  if (!o.quick) {
    configs.push_back({"full resolution (no LOD), nested", 0.0, true});
    configs.push_back({"LOD 0.5 px, nested", 0.5, true});
    configs.push_back({"LOD 2 px, nested", 2.0, true});
    configs.push_back({"LOD 4 px, nested", 4.0, true});
  }

  std::string route, glRenderer;
  std::vector<ConfigResult> results;
  CullComparison cull;
  for (const Config& c : configs) {
    RenderOptions ro;
    ro.width = width;
    ro.height = height;
    ro.lodMaxPixels = c.lodPixels;
    ro.nestedCulling = c.nestedCulling;
    const osg::Timer_t t0 = osg::Timer::instance()->tick();
    ViewRenderer renderer(scene, ro);
    ConfigResult res;
    res.config = c;
    res.setupMs = osg::Timer::instance()->delta_m(t0, osg::Timer::instance()->tick());
    route = offscreenRouteName(renderer.route());
    glRenderer = renderer.glRenderer();
    res.firstFrameMs = renderer.render(poses.front()).totalMs;  // warm-up, reported apart
    std::vector<double> total, cullMs, draw, readback, triangles;
    const std::vector<osg::BoundingSphere> spheres = renderer.instanceSpheres();
    for (const ViewPose& pose : poses) {
      const RenderFrameStats& s = renderer.render(pose);
      total.push_back(s.totalMs);
      cullMs.push_back(s.cullMs);
      draw.push_back(s.drawMs);
      readback.push_back(s.readbackMs);
      triangles.push_back(double(s.triangles));
      res.maxErrorPx = std::max(res.maxErrorPx, s.terrainErrorPx);
      res.maxErrorM = std::max(res.maxErrorM, s.terrainErrorM);
      if (results.empty()) {  // the culling comparison, on the first configuration's frames
        const CullCounts sphere = sphereCull(spheres, renderer.frustumLocal());
        ++cull.frames;
        cull.nestedKept += double(s.cull.visible);
        cull.nestedAabbCulled += double(s.cull.aabbOutside);
        cull.nestedObbTested += double(s.cull.obbTested);
        cull.nestedObbCulled += double(s.cull.obbOutside);
        cull.nestedMicros += s.cull.micros;
        cull.sphereKept += double(sphere.visible);
        cull.sphereMicros += sphere.micros;
        cull.framesNestedKeptMore += s.cull.visible > sphere.visible;
      }
    }
    res.frames = poses.size();
    res.p50 = median(total);
    res.p95 = percentile(total, 95);
    res.cull = median(cullMs);
    res.draw = median(draw);
    res.readback = median(readback);
    res.meanTriangles = std::accumulate(triangles.begin(), triangles.end(), 0.0) / double(triangles.size());
    res.maxTriangles = *std::max_element(triangles.begin(), triangles.end());
    results.push_back(res);
  }
  const double n = double(std::max<std::size_t>(cull.frames, 1));
  const double fps = 1000.0 / results.front().p50;
  const std::vector<Target> targets = {
      {"frame rate", ">= 30 frames per second at " + std::to_string(width) + "x" + std::to_string(height) +
                         " (LOD 1 px, median)", fps, fps >= 30.0}};

  if (o.json) {
    nlohmann::ordered_json j;
    j["benchmark"] = "render";
    j["cpu"] = cpuModelName();
    j["route"] = route;
    j["gl_renderer"] = glRenderer;
    j["size"] = {width, height};
    j["scene"] = o.scene;
    nlohmann::ordered_json scripts = nlohmann::ordered_json::array();
    for (const auto& [name, frames] : scriptFrames) scripts.push_back({{"script", name}, {"frames", frames}});
    j["flythroughs"] = scripts;
    nlohmann::ordered_json rows = nlohmann::ordered_json::array();
    for (const ConfigResult& r : results)
      rows.push_back({{"config", r.config.name},      {"lod_max_px", r.config.lodPixels},
                      {"nested_culling", r.config.nestedCulling},
                      {"frames", r.frames},           {"ms_p50", r.p50},
                      {"ms_p95", r.p95},              {"cull_ms_p50", r.cull},
                      {"draw_ms_p50", r.draw},        {"readback_ms_p50", r.readback},
                      {"fps_p50", 1000.0 / r.p50},    {"mean_triangles", r.meanTriangles},
                      {"max_triangles", r.maxTriangles}, {"max_terrain_error_px", r.maxErrorPx},
                      {"max_terrain_error_m", r.maxErrorM}, {"first_frame_ms", r.firstFrameMs},
                      {"setup_ms", r.setupMs}});
    j["configs"] = rows;
    j["view_culling"] = {{"frames", cull.frames},
                         {"instances", scene.instances.size()},
                         {"nested_kept_mean", cull.nestedKept / n},
                         {"nested_aabb_culled_mean", cull.nestedAabbCulled / n},
                         {"nested_obb_tested_mean", cull.nestedObbTested / n},
                         {"nested_obb_culled_mean", cull.nestedObbCulled / n},
                         {"nested_us_mean", cull.nestedMicros / n},
                         {"osg_spheres_kept_mean", cull.sphereKept / n},
                         {"osg_spheres_us_mean", cull.sphereMicros / n},
                         {"frames_nested_kept_more", cull.framesNestedKeptMore}};
    j["targets"] = targetsJson(targets);
    out << j.dump(2) << "\n";
    return 0;
  }

  char line[512];
  out << "nestwalk bench render: " << o.scene << "\n";
  std::snprintf(line, sizeof line, "%dx%d, %s (%s), cpu %s\n", width, height, glRenderer.c_str(), route.c_str(),
                cpuModelName().c_str());
  out << line << "frames:";
  for (const auto& [name, frames] : scriptFrames) out << " " << name << " " << frames;
  out << " (poses sampled evenly along each flythrough; the first frame is a warm-up, shown apart)\n\n";
  std::snprintf(line, sizeof line, "%-34s %7s %7s %6s %7s %8s %6s %10s %10s %9s %9s %8s\n", "configuration", "ms p50",
                "ms p95", "cull", "draw", "readback", "fps", "triangles", "max tris", "err px", "err m", "first");
  out << line;
  for (const ConfigResult& r : results) {
    std::snprintf(line, sizeof line, "%-34s %7.1f %7.1f %6.2f %7.1f %8.2f %6.1f %10.0f %10.0f %9.3f %9.3f %8.0f\n",
                  r.config.name.c_str(), r.p50, r.p95, r.cull, r.draw, r.readback, 1000.0 / r.p50, r.meanTriangles,
                  r.maxTriangles, r.maxErrorPx, r.maxErrorM, r.firstFrameMs);
    out << line;
  }
  out << "(cull: event, update and cull traversals; draw: until glFinish; readback: glReadPixels; err px / err m:\n"
         " the largest vertical error of a drawn terrain level, projected on screen / in metres)\n\n";
  std::snprintf(line, sizeof line,
                "view culling of %zu instances, mean per frame over %zu frames:\n"
                "  nested volumes: keep %.1f (outer AABB culls %.1f; %.1f undecided go to the inner OBB, which culls "
                "%.2f), %.2f us\n"
                "  OSG bounding spheres: keep %.1f, %.2f us; frames where nested kept more: %zu\n",
                scene.instances.size(), cull.frames, cull.nestedKept / n, cull.nestedAabbCulled / n,
                cull.nestedObbTested / n, cull.nestedObbCulled / n, cull.nestedMicros / n, cull.sphereKept / n,
                cull.sphereMicros / n, cull.framesNestedKeptMore);
  out << line;
  printTargets(out, targets, 12, 50);
  return 0;
}

}  // namespace nestwalk::bench
