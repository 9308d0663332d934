// The rendering benchmark (see render_bench.h).
#include "tools/bench/render_bench.h"

#include "tools/bench/bench_process.h"
#include "tools/bench/record_statistics.h"
#include "tools/bench/peers/osg_paged_lod_terrain.h"
#include "tools/bench/render_terrain_sweep.h"

#include "nestwalk/render/paged_terrain.h"
#include "nestwalk/render/texel_density.h"
#include "nestwalk/render/view_graph.h"
#include "nestwalk/render/view_renderer.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/scene/terrain_cache.h"
#include "nestwalk/walker/flythrough.h"
#include "nestwalk/walker/script_file.h"

#include <osg/Timer>

#include <malloc.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <ostream>
#include <string>

namespace nestwalk::bench {
namespace {

constexpr double kTargetFps = 30.0;  // frames per second, median, at the default configuration
/// A settled configuration waits at most this long for the pager between two frames: seconds.
constexpr double kSettleWaitSeconds = 10.0;
/// The time to the first complete frame gives up after this long: milliseconds.
constexpr double kFirstCompleteCapMs = 60000.0;
/// Texels per pixel (render/texel_density.h) on every this many-th pose, at every this many-th
/// pixel across and down: 3,600 pixels a pose at 1280x720, five ray casts each.
constexpr std::size_t kTexelPoseStep = 4;
constexpr int kTexelPixelStep = 16;

struct Config {
  std::string name;
  double lodPixels;
  bool nestedCulling;
  int chunkCells = RenderOptions{}.terrainChunkCells;
  bool osgPagedLod = false;  // the peer's terrain (peers/osg_paged_lod_terrain.h) instead of ours
  // Before each timed frame, render the pose until the terrain is the rule's full answer (the own
  // quadtree: once, it builds in the cull; PagedLOD: until the pager has loaded what the cull wants),
  // so the timed frame draws and loads nothing new. Also measures the time to the first complete
  // frame with background loading.
  bool settle = false;
  std::string imagery = {};  // draped instead of the scene's (empty: the scene's)
  bool demImagery = false;   // the imagery at the DEM's resolution (its finest texel the DEM's spacing), no mip levels
};

/// The view culling of the first configuration's timed frames, frame by frame: nested culling's
/// counts, and OSG's bounding spheres' on the same frustum.
struct CullComparison {
  std::vector<CullCounts> nested, spheres;
};

}  // namespace

std::vector<ViewPose> sampleFlythroughPoses(const Scene& scene, const RenderBenchOptions& o, int perScript,
                                            Json& flythroughs) {
  WalkerOptions wo;
  wo.viewer = scene.spec.viewer;
  wo.timeParts = false;
  const CollisionWorld world = CollisionWorld::fromScene(scene, scene.spec.method);
  std::vector<ViewPose> poses;
  for (const std::string& path : o.scripts) {
    const FlythroughResult r = runFlythrough(scene, world, readScript(path), wo);
    const std::size_t n = r.records.size(), take = std::min<std::size_t>(n, std::size_t(perScript));
    for (std::size_t k = 0; k < take; ++k) {
      const FrameRecord& f = r.records[k * n / take];
      poses.push_back({f.eye, f.headingDeg, f.pitchDeg, f.blocked, f.blockedBy});
    }
    flythroughs.push_back({{"script", std::filesystem::path(path).stem().string()}, {"frames", take}});
  }
  return poses;
}

Document renderDocument(const std::string& title, const std::string& benchmark, const RenderBenchOptions& o,
                        const Json& more) {
  Document doc(title);
  Json& j = doc.json;
  j["benchmark"] = benchmark;
  j["cpu"] = j["machine"]["cpu_model"];
  j["size"] = {o.runWidth(), o.runHeight()};
  j["scene"] = o.scene;
  j.update(more);
  j["flythroughs"] = Json::array();
  return doc;
}

void printRenderSetup(Document& doc, const std::string& legend) {
  const Json& j = doc.json;
  doc.text << j["size"][0] << "x" << j["size"][1];
  if (j.contains("gl_renderer"))
    doc.text << ", " << j["gl_renderer"].get<std::string>() << " (" << j["route"].get<std::string>() << ")";
  doc.text << "\nframes:";
  for (const Json& f : doc.json["flythroughs"]) doc.text << " " << f["script"].get<std::string>() << " " << f["frames"];
  doc.text << legend;
}

std::pair<int, bool> settlePose(ViewRenderer& renderer, const ViewPose& pose, bool (*done)(const RenderFrameStats&),
                                const std::function<void()>& wait, bool rendered) {
  int frames = 1;
  const int most = kMaxSettleFrames + (rendered ? 1 : 0);  // the frame rendered before does not count
  bool finished = done(rendered ? renderer.lastStats() : renderer.render(pose));
  for (; !finished && wait && frames < most; ++frames) {
    wait();
    finished = done(renderer.render(pose));
  }
  return {frames, finished};
}

namespace {

/// Frees what the allocator keeps and restarts the process's peak resident memory (Linux 4.0+:
/// "5" to clear_refs resets VmHWM); the resident memory now, MiB (nullopt where it cannot).
std::optional<double> restartPeakResident() {
  malloc_trim(0);
  std::ofstream clear("/proc/self/clear_refs");
  if (!(clear << "5" << std::flush)) return std::nullopt;
  return processStatusMiB("VmRSS");
}

/// Whether the last frame drew the terrain's full answer (nothing wanted, no stand-in).
bool complete(const RenderFrameStats& s) {
  return s.terrain.chunksWanted == 0 && s.terrain.standIns == 0 && s.terrain.imageryTilesWanted == 0;
}

/// From a renderer just made (background loading, as in the window), frames of one pose until one is
/// complete: milliseconds and frames (-1 ms when it gave up).
std::pair<double, int> firstCompleteFrame(const Scene& scene, RenderOptions ro, bool osgPagedLod, const ViewPose& pose) {
  ro.terrainLoading = TerrainLoading::Background;
  ViewRenderer renderer(scene, ro, osgPagedLod ? osgPagedLodMaker(nullptr) : TerrainNodeMaker());
  const osg::Timer_t t0 = osg::Timer::instance()->tick();
  for (int frames = 1;; ++frames) {
    const bool done = complete(renderer.render(pose));
    const double ms = osg::Timer::instance()->delta_m(t0, osg::Timer::instance()->tick());
    if (done) return {ms, frames};
    if (ms > kFirstCompleteCapMs) return {-1.0, frames};
  }
}

/// Renders every pose with configuration c: the configuration's row of the table.
Json renderConfig(const Scene& sceneAsLoaded, const Config& c, int width, int height, const std::vector<ViewPose>& poses,
                  CullComparison* cull, Json& doc) {
  std::optional<Scene> draped;  // the scene with the configuration's imagery
  if (!c.imagery.empty()) draped.emplace(sceneAsLoaded).drapedImagery = cachedImagery(c.imagery, sceneAsLoaded.terrain->crsWkt(), {});
  const Scene& scene = draped ? *draped : sceneAsLoaded;
  RenderOptions ro;
  if (c.demImagery) {  // today's drape: one texel a DEM sample, no mip levels
    ro.imageryFinestTexelM = std::max(scene.terrain->dx(), scene.terrain->dy());
    ro.imageryMipmaps = false;
  }
  ro.width = width;
  ro.height = height;
  ro.lodMaxPixels = c.lodPixels;
  ro.nestedCulling = c.nestedCulling;
  ro.terrainChunkCells = c.chunkCells;
  // Every frame the error rule's full answer: the steady state, whatever the loader's timing (the
  // own quadtree's Complete loading; the PagedLOD tree is settled before each frame instead).
  ro.terrainLoading = TerrainLoading::Complete;
  std::pair<double, int> firstComplete{0.0, 0};
  if (c.settle) firstComplete = firstCompleteFrame(scene, ro, c.osgPagedLod, poses.front());
  // Settled rows: the process's peak resident memory while this configuration renders, over what it
  // held before (the scene; earlier renderers gone and their memory given back).
  const std::optional<double> residentBefore = c.settle ? restartPeakResident() : std::nullopt;
  const osg::Timer_t t0 = osg::Timer::instance()->tick();
  osg::ref_ptr<PagedLodTerrain> lod;  // the peer's terrain, when it draws
  ViewRenderer renderer(scene, ro, c.osgPagedLod ? osgPagedLodMaker(&lod) : TerrainNodeMaker());
  const double setupMs = osg::Timer::instance()->delta_m(t0, osg::Timer::instance()->tick());
  doc["route"] = offscreenRouteName(renderer.route());
  doc["gl_renderer"] = renderer.glRenderer();
  const double firstFrameMs = renderer.render(poses.front()).totalMs;  // warm-up, reported apart
  std::vector<RenderFrameStats> frames;  // the timed frame of each pose
  TexelsPerPixel texelsPerPixel;         // settled imagery rows, every kTexelPoseStep-th pose
  const bool measureTexels = c.settle && !c.osgPagedLod && renderer.graph().pagedTerrain().imageryTiles();
  const std::vector<osg::BoundingSphere> spheres = renderer.instanceSpheres();
  const std::function<void()> waitForPager = [&lod] { lod->waitUntilIdle(kSettleWaitSeconds); };
  std::size_t settleFrames = 0, unsettled = 0;
  for (const ViewPose& pose : poses) {
    if (c.settle) {
      const auto [n, done] = settlePose(renderer, pose, complete, lod ? waitForPager : nullptr);
      settleFrames += std::size_t(n);
      unsettled += !done;
    }
    const RenderFrameStats& s = renderer.render(pose);
    if (measureTexels && (frames.size() % kTexelPoseStep) == 0)
      sampleTexelsPerPixel(renderer, *scene.terrain, kTexelPixelStep, texelsPerPixel);
    frames.push_back(s);
    if (cull) {
      cull->nested.push_back(s.cull);
      cull->spheres.push_back(sphereCull(spheres, renderer.frustumLocal()));
    }
  }
  using F = RenderFrameStats;
  using T = PagedTerrainStats;
  auto p50 = [&frames](auto figure) { return percentileOf(frames, 50, figure); };
  auto largest = [&frames](auto figure) { return percentileOf(frames, 100, figure); };
  Json row = {{"config", c.name},
          {"paging", c.osgPagedLod ? "osg-paged-lod" : "own-quadtree"},
          {"lod_max_px", c.lodPixels},
          {"nested_culling", c.nestedCulling},
          {"chunk_cells", c.chunkCells},
          {"terrain_resident_mib", double(renderer.graph().terrainStats().residentBytes) / (1 << 20)},
          {"imagery_mib", double(renderer.graph().terrainStats().imageryBytes) / (1 << 20)},
          {"frames", poses.size()},
          {"ms_p50", p50(&F::totalMs)},
          {"ms_p95", percentileOf(frames, 95, &F::totalMs)},
          {"cull_ms_p50", p50(&F::cullMs)},
          {"draw_ms_p50", p50(&F::drawMs)},
          {"readback_ms_p50", p50(&F::readbackMs)},
          {"fps_p50", 1000.0 / p50(&F::totalMs)},
          {"mean_triangles", meanOf(frames, &F::triangles)},
          {"max_triangles", largest(&F::triangles)},
          {"mean_skirt_triangles", meanOf(frames, terrainFigure(&T::skirtTrianglesDrawn))},
          {"mean_refined_level0_triangles", meanOf(frames, terrainFigure(&T::refinedTrianglesDrawn))},
          {"mean_exact_level0_triangles", meanOf(frames, terrainFigure(&T::exactTrianglesDrawn))},
          {"max_terrain_error_px", largest(&F::terrainErrorPx)},
          {"max_terrain_error_m", largest(&F::terrainErrorM)},
          {"first_frame_ms", firstFrameMs},
          {"setup_ms", setupMs}};
  if (const ImageryTiles* tiles = c.osgPagedLod ? nullptr : renderer.graph().pagedTerrain().imageryTiles()) {
    const double finest = percentileOf(frames, 0, terrainFigure(&T::finestTexelLevelDrawn));
    row["finest_texel_cm"] = 100 * tiles->texelSize(int(finest));  // the finest level drawn over the poses
  }
  auto median = [](const std::vector<double>& v) { return v.empty() ? Json() : Json(percentile(v, 50)); };
  if (measureTexels) {
    row["texels_per_px_near"] = median(texelsPerPixel.near);
    row["texels_per_px_middle"] = median(texelsPerPixel.middle);
    row["texels_per_px_far"] = median(texelsPerPixel.far);
  }
  if (c.settle) {
    row["settle_frames_mean"] = double(settleFrames) / double(std::max<std::size_t>(poses.size(), 1));
    row["poses_unsettled"] = unsettled;
    row["first_complete_ms"] = firstComplete.first < 0 ? Json() : Json(firstComplete.first);
    row["first_complete_frames"] = firstComplete.second;
    const std::optional<double> peak = processStatusMiB("VmHWM");
    row["peak_rss_growth_mib"] = residentBefore && peak ? Json(*peak - *residentBefore) : Json();
  }
  return row;
}

}  // namespace

int runBenchmark(const RenderBenchOptions& o, std::ostream& out) {
  if (!o.sweepChild.empty()) return runTerrainSweepChild(o.sweepChild);
  if (o.terrainSweep) return runTerrainSweep(o, out);
  const Scene scene = loadScene(o.scene);
  const int width = o.runWidth(), height = o.runHeight();
  Document doc = renderDocument("nestwalk bench render: " + o.scene, "render", o);
  Json& j = doc.json;
  const std::vector<ViewPose> poses = sampleFlythroughPoses(scene, o, o.runFramesPerScript(), j["flythroughs"]);

  std::vector<Config> configs = {{"LOD 1 px, nested culling", 1.0, true}, {"LOD 1 px, OSG sphere culling", 1.0, false}};
  if (!o.quick && o.imagery.empty()) {
    // The two ways of paging the terrain, each pose settled before its timed frame.
    configs.push_back({"LOD 1 px, own quadtree, settled", 1.0, true, 64, false, true});
    configs.push_back({"LOD 1 px, osg::PagedLOD + DatabasePager", 1.0, true, 64, true, true});
    // ... and with smaller chunks, where PagedLOD's whole-chunk refinement costs less.
    configs.push_back({"LOD 1 px, own quadtree, 32 cells, settled", 1.0, true, 32, false, true});
    configs.push_back({"LOD 1 px, PagedLOD + pager, 32 cells", 1.0, true, 32, true, true});
    configs.push_back({"full resolution (no LOD), nested", 0.0, true});
    configs.push_back({"LOD 0.5 px, nested", 0.5, true});
    configs.push_back({"LOD 2 px, nested", 2.0, true});
    configs.push_back({"LOD 4 px, nested", 4.0, true});
    configs.push_back({"LOD 1 px, chunks of 32 cells", 1.0, true, 32});
    configs.push_back({"LOD 1 px, chunks of 128 cells", 1.0, true, 128});
  }
  if (!o.imagery.empty()) {
    // Imagery at its own resolution against the drape at the DEM's (imagery_tiles.h), settled.
    Config dem{"imagery at the DEM's resolution, settled", 1.0, true, 64, false, true};
    dem.demImagery = true;
    configs.push_back(dem);
    for (const std::string& path : o.imagery) {
      Config c{"imagery " + std::filesystem::path(path).filename().string() + ", settled", 1.0, true, 64, false, true};
      c.imagery = path;
      configs.push_back(c);
    }
  }
  Table table;
  table.column({"configuration", "/config", 40, 0, true})
      .column({"ms p50", "/ms_p50", 8, 1})
      .column({"ms p95", "/ms_p95", 8, 1})
      .column({"cull", "/cull_ms_p50", 7, 2})
      .column({"draw", "/draw_ms_p50", 8, 1})
      .column({"readback", "/readback_ms_p50", 9, 2})
      .column({"fps", "/fps_p50", 7, 1})
      .column({"triangles", "/mean_triangles", 11, 0})
      .column({"max tris", "/max_triangles", 11, 0})
      .column({"err px", "/max_terrain_error_px", 10, 3})
      .column({"err m", "/max_terrain_error_m", 10, 3})
      .column({"MiB", "/terrain_resident_mib", 7, 0})
      .column({"img MiB", "/imagery_mib", 8, 0})
      .column({"texel cm", "/finest_texel_cm", 9, 1})
      .column({"tx/px near", "/texels_per_px_near", 11, 2})
      .column({"mid", "/texels_per_px_middle", 6, 2})
      .column({"far", "/texels_per_px_far", 6, 2})
      .column({"first", "/first_frame_ms", 9, 0})
      .column({"complete", "/first_complete_ms", 9, 0})
      .column({"+RSS MiB", "/peak_rss_growth_mib", 9, 0});
  CullComparison cull;
  for (const Config& c : configs)
    table.add(renderConfig(scene, c, width, height, poses, table.rows().empty() ? &cull : nullptr, j));

  printRenderSetup(doc, " (poses sampled evenly along each flythrough; the first frame is a warm-up, shown apart)\n\n");
  doc.table("configs", table);
  std::size_t keptMore = 0;  // frames where the nested volumes kept more than the spheres
  for (std::size_t k = 0; k < cull.nested.size(); ++k) keptMore += cull.nested[k].visible > cull.spheres[k].visible;
  using C = CullCounts;
  const double nestedKept = meanOf(cull.nested, &C::visible), aabbCulled = meanOf(cull.nested, &C::aabbOutside);
  const double obbTested = meanOf(cull.nested, &C::obbTested), obbCulled = meanOf(cull.nested, &C::obbOutside);
  const double nestedUs = meanOf(cull.nested, &C::micros), spheresKept = meanOf(cull.spheres, &C::visible);
  const double spheresUs = meanOf(cull.spheres, &C::micros);
  j["view_culling"] = {{"frames", cull.nested.size()},         {"instances", scene.instances.size()},
                       {"nested_kept_mean", nestedKept},        {"nested_aabb_culled_mean", aabbCulled},
                       {"nested_obb_tested_mean", obbTested},   {"nested_obb_culled_mean", obbCulled},
                       {"nested_us_mean", nestedUs},            {"osg_spheres_kept_mean", spheresKept},
                       {"osg_spheres_us_mean", spheresUs},      {"frames_nested_kept_more", keptMore}};
  char line[1024];
  std::snprintf(line, sizeof line,
                "(cull: event, update and cull traversals; draw: until glFinish; readback: glReadPixels; "
                "err px / err m:\n"
                " the largest vertical error of a drawn terrain level, projected on screen / in metres; "
                "first: the warm-up frame, ms;\n"
                " settled rows render each pose until the terrain is complete before timing it; complete: "
                "ms from a new\n renderer to the first complete frame of the first pose, loading in the "
                "background; +RSS MiB: the process's\n peak resident memory while the row renders, over what it "
                "held before)\n\n"
                "view culling of %zu instances, mean per frame over %zu frames:\n"
                "  nested volumes: keep %.1f (outer AABB culls %.1f; %.1f undecided go to the inner OBB, which culls "
                "%.2f), %.2f us\n"
                "  OSG bounding spheres: keep %.1f, %.2f us; frames where nested kept more: %zu\n",
                scene.instances.size(), cull.nested.size(), nestedKept, aabbCulled, obbTested, obbCulled, nestedUs,
                spheresKept, spheresUs, keptMore);
  doc.text << line;
  doc.target("frame rate", "", table.rows().front()["fps_p50"], ">=", kTargetFps,
             " frames per second at " + std::to_string(width) + "x" + std::to_string(height) + " (LOD 1 px, median)");
  return doc.write(out, o.json);
}

}  // namespace nestwalk::bench
