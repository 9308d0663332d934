// The offscreen renderer on the bundled mining-dump scene, against exact ray casts: the ID pass
// shows terrain where a ray through the pixel meets the terrain first (Heightfield::intersectRay)
// and sky where it meets nothing; a piece of equipment shows where its box is; the shaded frame is
// neither empty nor black, follows the walker, is stable across runs, keeps the near ground and
// near equipment, and nested culling draws exactly what OSG's own culling draws.
#include "tests/common/build_paths.h"
#include "nestwalk/render/view_renderer.h"

#include "nestwalk/core/ui_font.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/terrain/terrain_imagery.h"

#include <GL/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <thread>

namespace nestwalk {
namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;
const std::string kScenePath = std::string(nestwalk::test::build::bundledSceneDir()) + "/scene.json";

// Small frames keep the suite fast; the pixel checks do not depend on the size.
constexpr int kWidth = 320, kHeight = 180;

const Scene& bundledScene() {
  static std::unique_ptr<Scene> scene = [] {
    if (!std::filesystem::exists(kScenePath)) return std::unique_ptr<Scene>();
    return std::make_unique<Scene>(loadScene(kScenePath));
  }();
  if (!scene) throw std::runtime_error(std::string(kScenePath) + " is missing: build the bundled_scene target");
  return *scene;
}

RenderOptions smallOptions(bool idPass) {
  RenderOptions o;
  o.width = kWidth;
  o.height = kHeight;
  o.idPass = idPass;
  o.terrainLoading = TerrainLoading::Complete;  // every frame the error rule's full answer
  return o;
}

/// Ray against an oriented box (slab test in the box's frame): the entry parameter, if any.
std::optional<double> rayObb(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, const Obb<double>& box) {
  const Eigen::Vector3d o = box.axes.transpose() * (origin - box.center);
  const Eigen::Vector3d d = box.axes.transpose() * dir;
  double t0 = 0, t1 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const double h = box.halfExtents[k];
    if (std::abs(d[k]) < 1e-300) {
      if (std::abs(o[k]) > h) return std::nullopt;
      continue;
    }
    double a = (-h - o[k]) / d[k], b = (h - o[k]) / d[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 > t1) return std::nullopt;
  }
  return t0;
}

/// What the exact reference says a ray shows: the nearest instance box it enters (index), terrain
/// (-1) or sky (-2), with the distance of the nearest box and of the terrain.
struct RayTruth {
  int nearestBox = -1;
  double boxT = std::numeric_limits<double>::infinity();
  std::optional<double> terrainT;
};

RayTruth castReference(const Scene& scene, const Eigen::Vector3d& originMap, const Eigen::Vector3d& dir) {
  RayTruth truth;
  const Eigen::Vector3d local = scene.toLocal(originMap);
  for (std::size_t i = 0; i < scene.instances.size(); ++i)
    if (auto t = rayObb(local, dir, scene.instances[i].volume.inner); t && *t < truth.boxT) {
      truth.boxT = *t;
      truth.nearestBox = int(i);
    }
  if (auto hit = scene.terrain->intersectRay(originMap, dir)) truth.terrainT = hit->t;
  return truth;
}

/// A pose looking at instance `i` from `distance` metres (horizontally, towards `bearingDeg`
/// from the instance), the eye at eye height above the ground; nullopt when the instance's centre
/// cannot be seen from there (terrain or another box in the way, no ground).
std::optional<ViewPose> poseFacing(const Scene& scene, std::size_t i, double distance, double bearingDeg) {
  const Eigen::Vector3d target = scene.toMap(scene.instances[i].volume.inner.center);
  const double b = bearingDeg * kDegree;
  Eigen::Vector3d eye = target + distance * Eigen::Vector3d(std::sin(b), std::cos(b), 0);
  const auto ground = scene.terrain->groundHeight(eye.x(), eye.y());
  if (!ground) return std::nullopt;
  eye.z() = *ground + scene.spec.viewer.eyeHeight;
  const Eigen::Vector3d to = target - eye;
  const RayTruth truth = castReference(scene, eye, to.normalized());
  if (truth.nearestBox != int(i) || (truth.terrainT && *truth.terrainT < truth.boxT)) return std::nullopt;
  // The eye itself must be outside every box.
  for (const auto& inst : scene.instances)
    if (inst.volume.inner.contains(scene.toLocal(eye))) return std::nullopt;
  ViewPose pose;
  pose.eye = eye;
  pose.headingDeg = std::atan2(to.x(), to.y()) / kDegree;
  pose.pitchDeg = std::atan2(to.z(), std::hypot(to.x(), to.y())) / kDegree;
  return pose;
}

/// Instances of a kind with a clear view from some bearing at `distance`.
std::vector<std::pair<std::size_t, ViewPose>> viewsOf(const Scene& scene, const std::string& kind, double distance,
                                                      std::size_t wanted) {
  std::vector<std::pair<std::size_t, ViewPose>> out;
  for (std::size_t i = 0; i < scene.instances.size() && out.size() < wanted; ++i) {
    if (scene.spec.equipment[scene.instances[i].spec].kind != kind) continue;
    for (double bearing : {180.0, 90.0, 0.0, 270.0, 135.0, 315.0})
      if (auto pose = poseFacing(scene, i, distance, bearing)) {
        out.emplace_back(i, *pose);
        break;
      }
  }
  return out;
}

std::uint32_t instanceId(std::size_t i) { return std::uint32_t(i) + 2; }
constexpr std::uint32_t kSkyId = 0, kTerrainId = 1;

class RenderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(kScenePath)) GTEST_SKIP() << kScenePath << " is missing: build the bundled_scene target";
  }
};

TEST_F(RenderTest, ContextNeedsNoDisplay) {
  const char* display = std::getenv("DISPLAY");
  const std::string saved = display ? display : "";
  unsetenv("DISPLAY");
  auto context = OffscreenContext::create(64, 64);
  if (!saved.empty()) setenv("DISPLAY", saved.c_str(), 1);
  EXPECT_EQ(context->route(), OffscreenRoute::EglSurfaceless);
  EXPECT_FALSE(context->glRenderer().empty());
  std::printf("offscreen context: %s, %s, GL %s\n", offscreenRouteName(context->route()),
              context->glRenderer().c_str(), context->glVersion().c_str());
}

namespace {

/// Threads of this process whose name starts with "llvmpipe-": Mesa's software rasteriser threads.
int llvmpipeThreads() {
  int n = 0;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
    std::ifstream comm(task.path() / "comm");
    std::string name;
    std::getline(comm, name);
    n += name.rfind("llvmpipe-", 0) == 0;
  }
  return n;
}

}  // namespace

TEST_F(RenderTest, ContextsOutliveEachOther) {
  auto first = OffscreenContext::create(64, 64);
  if (first->route() != OffscreenRoute::EglSurfaceless) GTEST_SKIP() << "the EGL route is not in use";
  auto second = OffscreenContext::create(64, 64);
  first.reset();
  second->makeCurrent();
  EXPECT_NE(glGetString(GL_RENDERER), nullptr) << "the second context is no longer usable once the first is destroyed";
}

TEST_F(RenderTest, RendererMadeAfterAnotherKeepsItsRasteriserThreads) {
  const Scene& scene = bundledScene();
  const auto views = viewsOf(scene, "container", 25.0, 1);
  ASSERT_FALSE(views.empty()) << "no container with a clear view in the bundled scene";
  auto first = std::make_unique<ViewRenderer>(scene, smallOptions(false));
  if (first->route() != OffscreenRoute::EglSurfaceless) GTEST_SKIP() << "the EGL route is not in use";
  if (first->glRenderer().rfind("llvmpipe", 0) != 0 || std::thread::hardware_concurrency() < 2)
    GTEST_SKIP() << "not Mesa's llvmpipe on several cores: " << first->glRenderer();
  first->render(views.front().second);
  const int threadsOfFirst = llvmpipeThreads();
  EXPECT_GT(threadsOfFirst, 0);
  first.reset();
  // After an eglTerminate of the shared display, Mesa 22.3's llvmpipe started none for the next
  // renderer's context, which then drew on the calling thread alone.
  ViewRenderer second(scene, smallOptions(false));
  second.render(views.front().second);
  const int threadsOfSecond = llvmpipeThreads();
  EXPECT_GE(threadsOfSecond, threadsOfFirst);
}

TEST_F(RenderTest, IdPassShowsWhatExactRaysHit) {
  const Scene& scene = bundledScene();
  const auto views = viewsOf(scene, "container", 25.0, 2);
  ASSERT_FALSE(views.empty()) << "no container with a clear view in the bundled scene";
  ViewRenderer renderer(scene, smallOptions(true));
  for (const auto& [target, pose0] : views) {
    for (double pitch : {pose0.pitchDeg, -25.0}) {  // at the container, then down at the near ground
      ViewPose pose = pose0;
      pose.pitchDeg = pitch;
      renderer.render(pose);
      const osg::Image& image = renderer.image();
      std::size_t decided = 0, agree = 0, terrain = 0, sky = 0;
      for (int y = 1; y < kHeight; y += 3)
        for (int x = 1; x < kWidth; x += 3) {
          const auto [origin, dir] = renderer.pixelRay(x + 0.5, y + 0.5);
          const RayTruth truth = castReference(scene, origin, dir);
          // Decided pixels: no box in front of the terrain (equipment need not fill its box).
          if (truth.nearestBox >= 0 && (!truth.terrainT || truth.boxT < *truth.terrainT)) continue;
          const std::uint32_t expected = truth.terrainT ? kTerrainId : kSkyId;
          ++decided;
          (expected == kTerrainId ? terrain : sky) += 1;
          agree += ViewRenderer::idAt(image, x, y) == expected;
        }
      ASSERT_GT(decided, 1000u);
      EXPECT_GT(terrain, 300u) << "the view shows little terrain";
      const double rate = double(agree) / double(decided);
      EXPECT_GE(rate, 0.99) << "instance " << target << " pitch " << pitch << ": " << decided - agree << " of "
                            << decided << " pixels disagree with the exact ray cast (" << terrain << " terrain, "
                            << sky << " sky)";
      if (pitch == pose0.pitchDeg) {
        // The container's centre is where the camera looks: the middle pixel.
        const auto p = renderer.project(scene.toMap(scene.instances[target].volume.inner.center));
        ASSERT_TRUE(p.has_value());
        EXPECT_NEAR(p->x(), kWidth / 2.0, 1e-6);
        EXPECT_NEAR(p->y(), kHeight / 2.0, 1e-6);
        EXPECT_EQ(ViewRenderer::idAt(image, kWidth / 2, kHeight / 2), instanceId(target));
      } else {
        // Looking down: the ground right in front of the walker is drawn, not cut away.
        EXPECT_EQ(ViewRenderer::idAt(image, kWidth / 2, kHeight - 2), kTerrainId);
      }
    }
  }
}

TEST_F(RenderTest, CameraFollowsTheWalker) {
  const Scene& scene = bundledScene();
  const auto views = viewsOf(scene, "container", 30.0, 1);
  ASSERT_FALSE(views.empty());
  const auto& [target, pose] = views.front();
  ViewRenderer renderer(scene, smallOptions(true));
  const Eigen::Vector3d centre = scene.toMap(scene.instances[target].volume.inner.center);
  // Step sideways (to the walker's right) and keep the heading: the container moves left on screen
  // by as much as the projection says, and is drawn there.
  ViewPose moved = pose;
  const double h = pose.headingDeg * kDegree;
  moved.eye += 1.5 * Eigen::Vector3d(std::cos(h), -std::sin(h), 0);
  renderer.render(pose);
  const auto before = renderer.project(centre);
  EXPECT_EQ(ViewRenderer::idAt(renderer.image(), int(before->x()), int(before->y())), instanceId(target));
  renderer.render(moved);
  const auto after = renderer.project(centre);
  ASSERT_TRUE(after.has_value());
  EXPECT_LT(after->x(), before->x() - 5.0);
  EXPECT_EQ(ViewRenderer::idAt(renderer.image(), int(after->x()), int(after->y())), instanceId(target));
  // Expected shift from the pinhole model: f * dx / depth, f = (H / 2) / tan(fov / 2).
  const double f = 0.5 * kHeight / std::tan(30.0 * kDegree);
  const double depth = (centre - pose.eye).head<2>().norm();
  EXPECT_NEAR(before->x() - after->x(), f * 1.5 / depth, 1.0);
}

TEST_F(RenderTest, NearEquipmentIsNotClipped) {
  // The eye as close to a container's side as the body lets it come (its half extent), looking
  // straight at it: the whole middle of the frame is the container.
  const Scene& scene = bundledScene();
  const double gap = scene.spec.viewer.bodyHalfExtents.x();
  const auto views = viewsOf(scene, "container", 25.0, 3);
  ASSERT_FALSE(views.empty());
  ViewRenderer renderer(scene, smallOptions(true));
  int checked = 0;
  for (const auto& [target, far] : views) {
    const Obb<double>& box = scene.instances[target].volume.inner;
    // Walk from the far pose towards the centre until the eye is `gap` from the box surface.
    const Eigen::Vector3d dir = (scene.toMap(box.center) - far.eye).normalized();
    const auto entry = rayObb(scene.toLocal(far.eye), dir, box);
    ASSERT_TRUE(entry.has_value());
    ViewPose near = far;
    near.eye = far.eye + (*entry - gap) * dir;
    renderer.render(near);
    int hits = 0, total = 0;
    for (int y = kHeight / 2 - 10; y <= kHeight / 2 + 10; y += 2)
      for (int x = kWidth / 2 - 10; x <= kWidth / 2 + 10; x += 2) {
        ++total;
        hits += ViewRenderer::idAt(renderer.image(), x, y) == instanceId(target);
      }
    EXPECT_EQ(hits, total) << "container " << target << " seen from " << gap << " m";
    ++checked;
  }
  EXPECT_GT(checked, 0);
}

TEST_F(RenderTest, NestedCullingDrawsWhatOsgCullingDraws) {
  const Scene& scene = bundledScene();
  const auto views = viewsOf(scene, "station", 40.0, 3);
  ASSERT_FALSE(views.empty());
  RenderOptions nestedOptions = smallOptions(true), osgOptions = smallOptions(true);
  osgOptions.nestedCulling = false;
  ViewRenderer nested(scene, nestedOptions), osg(scene, osgOptions);
  for (const auto& [target, pose] : views) {
    const RenderFrameStats& s = nested.render(pose);
    osg.render(pose);
    EXPECT_EQ(s.cull.instances, scene.instances.size());
    EXPECT_EQ(s.cull.visible, s.cull.instances - s.cull.aabbOutside - s.cull.obbOutside);
    EXPECT_GT(s.cull.aabbOutside, scene.instances.size() / 4) << "a ground-level view sees most equipment culled";
    std::size_t differ = 0;
    const osg::Image& a = nested.image();
    const osg::Image& b = osg.image();
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) differ += ViewRenderer::idAt(a, x, y) != ViewRenderer::idAt(b, x, y);
    EXPECT_EQ(differ, 0u) << "instance " << target << ": nested culling removed something visible";
    std::printf("view of %s: %llu instances, AABB culled %llu, AABB accepted %llu, OBB tested %llu, OBB culled %llu, "
                "drawn %llu\n",
                scene.spec.equipment[target].name.c_str(), (unsigned long long)s.cull.instances,
                (unsigned long long)s.cull.aabbOutside, (unsigned long long)s.cull.aabbInside,
                (unsigned long long)s.cull.obbTested, (unsigned long long)s.cull.obbOutside,
                (unsigned long long)s.cull.visible);
  }
}

/// Mean of each channel over a set of pixels.
Eigen::Vector3d meanColour(const osg::Image& image, const std::vector<std::pair<int, int>>& pixels) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& [x, y] : pixels) {
    const unsigned char* p = image.data(x, image.t() - 1 - y);
    sum += Eigen::Vector3d(p[0], p[1], p[2]);
  }
  return pixels.empty() ? sum : sum / double(pixels.size());
}

TEST_F(RenderTest, ShadedFrameLooksLikeTheScene) {
  const Scene& scene = bundledScene();
  const auto views = viewsOf(scene, "container", 25.0, 1);
  ASSERT_FALSE(views.empty());
  ViewPose pose = views.front().second;
  pose.pitchDeg = 2.0;  // the horizon in view: sky above, terrain below
  ViewRenderer renderer(scene, smallOptions(false));
  const RenderFrameStats& stats = renderer.render(pose);
  const osg::Image& image = renderer.image();
  // Classify pixels by the exact reference and compare their colours.
  std::vector<std::pair<int, int>> skyPixels, terrainPixels;
  for (int y = 1; y < kHeight; y += 4)
    for (int x = 1; x < kWidth; x += 4) {
      const auto [origin, dir] = renderer.pixelRay(x + 0.5, y + 0.5);
      const RayTruth truth = castReference(scene, origin, dir);
      if (truth.nearestBox >= 0 && (!truth.terrainT || truth.boxT < *truth.terrainT)) continue;
      if (!truth.terrainT) skyPixels.emplace_back(x, y);
      else if (*truth.terrainT < 300) terrainPixels.emplace_back(x, y);  // near terrain: little haze
    }
  ASSERT_GT(skyPixels.size(), 50u);
  ASSERT_GT(terrainPixels.size(), 50u);
  const Eigen::Vector3d sky = meanColour(image, skyPixels), ground = meanColour(image, terrainPixels);
  EXPECT_GT(sky.z(), sky.x() + 20) << "the sky is blue: " << sky.transpose();
  EXPECT_GT((sky - ground).norm(), 40.0) << "terrain " << ground.transpose() << " looks like sky " << sky.transpose();
  EXPECT_GT(ground.maxCoeff(), 40.0) << "the lit terrain is not black";
  // Many distinct colours: shading, not a flat fill.
  std::set<std::uint32_t> colours;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) colours.insert(ViewRenderer::idAt(image, x, y));
  EXPECT_GT(colours.size(), 100u);
  // The statistics of the frame.
  EXPECT_GT(stats.triangles, 1000u);
  EXPECT_GT(stats.terrainChunks, 0u);
  EXPECT_GT(stats.terrainErrorPx, 0.0);
  EXPECT_LE(stats.terrainErrorPx, renderer.options().lodMaxPixels * (1 + 1e-6));
  EXPECT_GE(stats.cullMs, 0.0);
  EXPECT_GE(stats.drawMs, 0.0);
  EXPECT_GE(stats.readbackMs, 0.0);
  EXPECT_LE(stats.cullMs + stats.drawMs + stats.readbackMs, stats.totalMs * 1.001 + 0.01);
}

TEST_F(RenderTest, DrapedImageryColoursTheTerrain) {
  // The bundled scene drapes its synthetic orthophoto. Where a pixel shows near terrain, its hue is
  // the orthophoto's at the ground point the exact ray meets (the hillshade scales the three
  // channels alike, so the chromaticity r / (r + g + b), g / (r + g + b) is the imagery's).
  const Scene& scene = bundledScene();
  ASSERT_TRUE(scene.spec.imagery.has_value()) << "the bundled scene names no imagery";
  terrain::TerrainImagery ortho(*scene.spec.imagery, scene.terrain->crsWkt());
  const auto views = viewsOf(scene, "station", 40.0, 1);
  ASSERT_FALSE(views.empty());
  ViewPose pose = views.front().second;
  pose.pitchDeg = -25.0;  // mostly ground
  ViewRenderer renderer(scene, smallOptions(false));
  renderer.render(pose);
  const osg::Image& image = renderer.image();
  std::vector<double> errors;
  for (int y = 2; y < kHeight; y += 5)
    for (int x = 2; x < kWidth; x += 5) {
      const auto [origin, dir] = renderer.pixelRay(x + 0.5, y + 0.5);
      const RayTruth truth = castReference(scene, origin, dir);
      if (!truth.terrainT || *truth.terrainT > 150 || (truth.nearestBox >= 0 && truth.boxT < *truth.terrainT + 2))
        continue;
      const Eigen::Vector3d hit = origin + *truth.terrainT * dir;
      const std::vector<std::uint8_t> rgba = ortho.read(hit.x(), hit.y(), 1.0, 1.0, 1, 1);
      const unsigned char* p = image.data(x, image.t() - 1 - y);
      const double rs = p[0] + p[1] + p[2] + 1e-9, os = rgba[0] + rgba[1] + rgba[2] + 1e-9;
      errors.push_back(std::hypot(p[0] / rs - rgba[0] / os, p[1] / rs - rgba[1] / os));
    }
  ASSERT_GT(errors.size(), 200u);
  std::sort(errors.begin(), errors.end());
  const double median = errors[errors.size() / 2];
  // The orthophoto is sampled at the drawn level's spacing and blended over triangles, and carries
  // per-pixel noise: a pixel's hue strays, the median does not.
  EXPECT_LT(median, 0.02) << "over " << errors.size() << " pixels";
  // Nine pixels in ten too: the orthophoto's materials (bench, face, berm) change within a chunk, so
  // a chunk drawn in fewer colours than its samples strays on a large share of them (measured: 0.013
  // when right; 0.10 when a texture-filling bug drew each chunk in one colour, whose median was 0.009).
  const double ninetieth = errors[errors.size() * 9 / 10];
  EXPECT_LT(ninetieth, 0.04) << "over " << errors.size() << " pixels";
}

TEST_F(RenderTest, StableAcrossRuns) {
  const Scene& scene = bundledScene();
  const auto views = viewsOf(scene, "station", 30.0, 1);
  ASSERT_FALSE(views.empty());
  std::vector<osg::ref_ptr<osg::Image>> images;
  for (int run = 0; run < 2; ++run) {
    ViewRenderer renderer(scene, smallOptions(false));
    renderer.render(views.front().second);
    images.push_back(new osg::Image(renderer.image(), osg::CopyOp::DEEP_COPY_ALL));
  }
  std::size_t close = 0, total = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      for (int c = 0; c < 3; ++c) {
        ++total;
        close += std::abs(int(images[0]->data(x, y)[c]) - int(images[1]->data(x, y)[c])) <= 2;
      }
  EXPECT_GE(double(close) / double(total), 0.999);
}

TEST_F(RenderTest, BlockedStateIsShown) {
  const Scene& scene = bundledScene();
  const auto views = viewsOf(scene, "container", 25.0, 1);
  ASSERT_FALSE(views.empty());
  ViewRenderer renderer(scene, smallOptions(false));
  ViewPose pose = views.front().second;
  auto isRed = [](const osg::Image& image, int x, int y) {
    const unsigned char* p = image.data(x, image.t() - 1 - y);
    return p[0] > 180 && p[1] < 80 && p[2] < 80;
  };
  renderer.render(pose);
  EXPECT_FALSE(isRed(renderer.image(), 1, kHeight / 2));
  pose.blocked = true;
  pose.blockedBy = scene.spec.equipment[views.front().first].name;
  renderer.render(pose);
  EXPECT_TRUE(isRed(renderer.image(), 1, kHeight / 2));
  EXPECT_TRUE(isRed(renderer.image(), kWidth / 2, 1));
}

TEST_F(RenderTest, BlockedTextIsSetInTheUiFont) {
  const Scene& scene = bundledScene();
  const auto views = viewsOf(scene, "container", 25.0, 1);
  ASSERT_FALSE(views.empty());
  EXPECT_EQ(ViewRenderer(scene, smallOptions(true)).overlayFontFile(), "");  // the ID pass has no overlay
  ViewRenderer renderer(scene, smallOptions(false));
  // The report's font, from its file (core/ui_font.h), not osgText's built-in one.
  EXPECT_EQ(renderer.overlayFontFile(), kUiFontPath);
  // "BLOCKED by <name>" lies inside the red frame at the top left: red-ish pixels there (text is
  // antialiased: red over the scene) that the unblocked frame does not have. The frame is
  // max(4, 0.6 % of the height) = 4 pixels wide; the text starts 2.5 frame widths in and is
  // max(12, 3.5 % of the height) = 12 pixels high.
  auto redInTextArea = [&](const osg::Image& image) {
    int n = 0;
    for (int y = 6; y < 6 + 24; ++y)
      for (int x = 6; x < kWidth / 2; ++x) {
        const unsigned char* p = image.data(x, image.t() - 1 - y);
        n += p[0] > 150 && p[0] > p[1] + 60 && p[0] > p[2] + 60;
      }
    return n;
  };
  ViewPose pose = views.front().second;
  renderer.render(pose);
  const int before = redInTextArea(renderer.image());
  pose.blocked = true;
  pose.blockedBy = scene.spec.equipment[views.front().first].name;
  renderer.render(pose);
  EXPECT_GT(redInTextArea(renderer.image()), before + 40) << "no blocked text drawn";
}

}  // namespace
}  // namespace nestwalk
