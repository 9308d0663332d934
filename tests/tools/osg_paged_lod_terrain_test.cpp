// The osg::PagedLOD terrain, the peer of `bench render` (tools/bench/peers/osg_paged_lod_terrain.h), paged by a real osgDB::DatabasePager
// through OSG cull traversals (osgUtil::SceneView, no GL needed): the first frame draws the root and
// asks for more; paging settles within a frame a level; then every drawn chunk shows at most a pixel
// of projected vertical error (recomputed here by brute force over its fine samples), no drawn chunk
// overlaps another, the view is covered, and the drawn error by PagedTerrain's block measure is
// within the pixel too; chunks of holes are never drawn. At UTM magnitudes (the heightfield's origin
// is at 500 km, 6900 km; the graph works in the mesh frame). And in the offscreen renderer
// (through its terrain hook, render/terrain_node.h): the ID pass along the bundled flythroughs, each pose settled, shows
// no sky below the terrain's silhouette (terrain_cracks_test.cpp's check: whole-chunk replacement
// leaves no gap the skirts do not close) and the frames are complete.
#include "nestwalk/render/paged_terrain.h"
#include "nestwalk/render/view_graph.h"
#include "nestwalk/render/view_renderer.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/terrain/heightfield.h"
#include "nestwalk/terrain/terrain_chunk.h"
#include "tests/render/hills_terrain.h"
#include "tests/render/terrain_checks.h"
#include "nestwalk/walker/flythrough.h"
#include "nestwalk/walker/script_file.h"

#include "tests/common/test_data.h"
#include "tools/bench/peers/osg_paged_lod_terrain.h"

#include <osg/FrameStamp>
#include <osg/Polytope>
#include <osgDB/DatabasePager>
#include <osgDB/WriteFile>
#include <osgUtil/CullVisitor>
#include <osgUtil/SceneView>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <optional>
#include <random>
#include <set>
#include <vector>

namespace nestwalk {
namespace {

using bench::PagedLodTerrain;
using terrain::ChunkKey;

constexpr double kPixelsPerRadian = 623.5;
constexpr int kChunkCells = 16;
/// The pager is given this long to load what one frame asked for: seconds (a 16-cell chunk builds
/// in well under a millisecond).
constexpr double kPagerWaitSeconds = 20.0;
/// Projected errors are compared with this much slack: pixels (float boxes and positions).
constexpr double kPixelSlack = 1e-6;

using test::hills;

using test::View;
using test::viewFrom;

/// A scene view whose cull visitor asks a DatabasePager of its own for files, as osgViewer's does;
/// frame() merges what the pager has loaded (the update traversal's part), then culls.
class PagedCull {
 public:
  explicit PagedCull(osg::Node* root) : pager_(osgDB::DatabasePager::create()), stamp_(new osg::FrameStamp) {
    sv_ = new osgUtil::SceneView;
    sv_->setDefaults();
    sv_->setComputeNearFarMode(osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);
    sv_->setCullingMode(osg::CullSettings::VIEW_FRUSTUM_CULLING);
    sv_->setViewport(0, 0, 1280, 720);
    sv_->setFrameStamp(stamp_.get());
    sv_->getCullVisitor()->setDatabaseRequestHandler(pager_.get());
    sv_->setSceneData(root);
    pager_->registerPagedLODs(root);
  }
  ~PagedCull() { pager_->cancel(); }

  void frame(const View& v) {
    stamp_->setFrameNumber(stamp_->getFrameNumber() + 1);
    stamp_->setReferenceTime(stamp_->getReferenceTime() + 1.0 / 60.0);
    stamp_->setSimulationTime(stamp_->getReferenceTime());
    pager_->signalBeginFrame(stamp_.get());
    pager_->updateSceneGraph(*stamp_);
    sv_->setViewMatrix(v.view);
    sv_->setProjectionMatrix(v.projection);
    sv_->cull();
    pager_->signalEndFrame();
  }

  /// Frames until one wants nothing (or maxFrames); returns the frames culled.
  int settle(PagedLodTerrain& node, const View& v, int maxFrames = 50) {
    int frames = 0;
    for (;;) {
      frame(v);
      ++frames;
      if (node.lastStats().chunksWanted == 0 || frames >= maxFrames) return frames;
      EXPECT_TRUE(node.waitUntilIdle(kPagerWaitSeconds));
    }
  }

 private:
  osg::ref_ptr<osgDB::DatabasePager> pager_;
  osg::ref_ptr<osg::FrameStamp> stamp_;
  osg::ref_ptr<osgUtil::SceneView> sv_;
};

PagedTerrainOptions options() {
  PagedTerrainOptions o;
  o.chunkCells = kChunkCells;
  o.pixelsPerRadian = kPixelsPerRadian;
  o.maxPixels = 1.0;
  o.simplifyFraction = 0;  // the level grids, whose surface the checks below take
  return o;
}

/// The largest projected error of a whole chunk's surface from the eye (terrain_checks.h).
double projectedPixels(const terrain::Heightfield& hf, const terrain::ChunkLayout& l, const ChunkKey& k,
                       const osg::Vec3d& eye) {
  const std::vector<int> cols = l.columns(k), rows = l.rowsOf(k);
  return test::projectedPixels(hf, l, k, cols.front(), cols.back(), rows.front(), rows.back(), eye, kPixelsPerRadian);
}

/// Whether chunk a holds chunk b (the same, or an ancestor of it).
bool holds(const ChunkKey& a, const ChunkKey& b) {
  if (a.level < b.level) return false;
  const int shift = a.level - b.level;
  return (b.x >> shift) == a.x && (b.y >> shift) == a.y;
}

const View kLowView = viewFrom({120, -140, 345}, {300, -330, 300});

TEST(PagedLodTerrain, TheFirstFrameDrawsTheRootAndPagingSettlesALevelAFrame) {
  const auto hf = hills();
  osg::ref_ptr<PagedLodTerrain> node = new PagedLodTerrain(hf, options());
  PagedCull cull(node.get());
  cull.frame(kLowView);
  ASSERT_EQ(node->drawnChunks().size(), 1u);
  EXPECT_EQ(node->drawnChunks().front(), node->layout().root());
  EXPECT_EQ(node->lastStats().chunksWanted, 1u);
  EXPECT_GE(node->lastStats().chunksResident, 1u);  // the pager may already be building the children
  ASSERT_TRUE(node->waitUntilIdle(kPagerWaitSeconds));
  const int frames = 1 + cull.settle(*node, kLowView);
  EXPECT_EQ(node->lastStats().chunksWanted, 0u);
  EXPECT_LE(frames, node->layout().levels() + 1);  // one level a frame
  EXPECT_GT(node->lastStats().chunksLoaded, node->drawnChunks().size());
  EXPECT_GT(node->lastStats().residentBytes, 0u);
  EXPECT_LT(node->lastStats().finestLevel, node->lastStats().coarsestLevel);
}

TEST(PagedLodTerrain, ASettledFrameDrawsEveryChunkWithinAPixelOnceAndCoversTheView) {
  const auto hf = hills();
  osg::ref_ptr<PagedLodTerrain> node = new PagedLodTerrain(hf, options());
  PagedCull cull(node.get());
  cull.settle(*node, kLowView);
  ASSERT_EQ(node->lastStats().chunksWanted, 0u);
  const std::vector<ChunkKey>& drawn = node->drawnChunks();
  ASSERT_GT(drawn.size(), 10u);
  const terrain::ChunkLayout& l = node->layout();
  // Within a pixel, by brute force; and by PagedTerrain's block bound, which the sphere rule implies
  // (every block's box lies in the chunk's sphere).
  for (const ChunkKey& k : drawn)
    EXPECT_LE(projectedPixels(*hf, l, k, kLowView.eye), 1.0 + kPixelSlack) << k.level << " " << k.x << " " << k.y;
  EXPECT_LE(node->lastStats().maxErrorPx, 1.0 + kPixelSlack);
  // Each drawn once, none with an ancestor or descendant.
  EXPECT_EQ(std::set<ChunkKey>(drawn.begin(), drawn.end()).size(), drawn.size());
  for (const ChunkKey& a : drawn)
    for (const ChunkKey& b : drawn)
      if (!(a == b)) {
        EXPECT_FALSE(holds(a, b)) << "chunk " << a.level << "/" << a.x << "/" << a.y << " drawn over " << b.level
                                  << "/" << b.x << "/" << b.y;
      }
  // Covered: the middle sample of every leaf chunk that shows well inside the screen (a margin of a
  // tenth of it, so the coarse surface there is in view too) lies in a drawn chunk.
  osg::Polytope inner;
  inner.setToUnitFrustum();
  inner.transformProvidingInverse(kLowView.view * kLowView.projection * osg::Matrixd::scale(1.0 / 0.8, 1.0 / 0.8, 1.0));
  std::size_t leavesInView = 0;
  for (int y = 0; y < l.chunksY(0); ++y)
    for (int x = 0; x < l.chunksX(0); ++x) {
      const ChunkKey leaf{0, x, y};
      const std::vector<int> cols = l.columns(leaf), rows = l.rowsOf(leaf);
      const int c = cols[cols.size() / 2], r = rows[rows.size() / 2];
      const osg::Vec3d p(c * hf->dx(), -r * hf->dy(), hf->sample(c, r));
      if (!inner.contains(osg::Vec3(p)) || (p - kLowView.eye).length() > 4000.0) continue;
      ++leavesInView;
      EXPECT_TRUE(std::any_of(drawn.begin(), drawn.end(), [&](const ChunkKey& k) { return holds(k, leaf); }))
          << "leaf " << x << " " << y;
    }
  EXPECT_GT(leavesInView, 20u);
}

TEST(PagedLodTerrain, DrawsAtLeastAsFineAsTheOwnQuadtreeWhereBothLook) {
  // The sphere rule is conservative against PagedTerrain's block rule: no drawn chunk of the
  // PagedLOD tree is coarser than the own quadtree's part over the same ground.
  const auto hf = hills();
  osg::ref_ptr<PagedLodTerrain> lod = new PagedLodTerrain(hf, options());
  PagedCull cull(lod.get());
  cull.settle(*lod, kLowView);
  PagedTerrainOptions o;
  o.chunkCells = kChunkCells;
  o.pixelsPerRadian = kPixelsPerRadian;
  o.maxPixels = 1.0;
  o.loading = TerrainLoading::Complete;
  o.simplifyFraction = 0;  // the same meshes as the PagedLOD tree's
  osg::ref_ptr<PagedTerrain> own = new PagedTerrain(hf, o);
  osg::ref_ptr<osgUtil::SceneView> sv = new osgUtil::SceneView;
  sv->setDefaults();
  sv->setComputeNearFarMode(osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);
  sv->setViewport(0, 0, 1280, 720);
  sv->setSceneData(own.get());
  sv->setViewMatrix(kLowView.view);
  sv->setProjectionMatrix(kLowView.projection);
  sv->cull();
  std::size_t compared = 0;
  for (const DrawnPart& p : own->drawnParts()) {
    const ChunkKey child{p.key.level - 1, 2 * p.key.x + (p.quadrant & 1), 2 * p.key.y + (p.quadrant >> 1)};
    for (const ChunkKey& k : lod->drawnChunks())
      if (p.key.level > 0 && holds(k, child)) {
        ++compared;
        EXPECT_LE(k.level, p.key.level) << "PagedLOD chunk " << k.level << "/" << k.x << "/" << k.y;
      }
  }
  EXPECT_GT(compared, 0u);
  RecordProperty("paged_lod_triangles", int(lod->lastStats().trianglesDrawn));
  RecordProperty("own_quadtree_triangles", int(own->lastStats().trianglesDrawn));
}

TEST(PagedLodTerrain, SimplifiedChunksKeepTheRuleAndLevelZeroSwitchesToItsExactGrid) {
  // Simplified surfaces (terrain_chunk.h) have their own exact errors and blocks: the settled frame
  // stays within the pixel by the block measure, and level-0 chunks near the eye draw their exact
  // grid (error 0).
  const auto hf = hills();
  PagedTerrainOptions o = options();
  o.simplifyFraction = kTerrainSimplifyFraction;
  osg::ref_ptr<PagedLodTerrain> node = new PagedLodTerrain(hf, o);
  PagedCull cull(node.get());
  const View v = viewFrom({120, -140, 312}, {300, -330, 290});  // a few metres above the ground
  cull.settle(*node, v);
  ASSERT_EQ(node->lastStats().chunksWanted, 0u);
  EXPECT_GT(node->drawnChunks().size(), 10u);
  EXPECT_LE(node->lastStats().maxErrorPx, 1.0 + kPixelSlack);
  EXPECT_EQ(node->lastStats().finestLevel, 0);
}

TEST(PagedLodTerrain, ChunksOfHolesAreNeverDrawnAndHolesDoNotBreakTheRule) {
  const auto hf = hills(0.01, true);
  osg::ref_ptr<PagedLodTerrain> node = new PagedLodTerrain(hf, options());
  PagedCull cull(node.get());
  const View v = viewFrom({330, -200, 320}, {330, -260, 290});  // above the big hole
  cull.settle(*node, v);
  ASSERT_EQ(node->lastStats().chunksWanted, 0u);
  const terrain::ChunkLayout& l = node->layout();
  ASSERT_GT(node->drawnChunks().size(), 0u);
  for (const ChunkKey& k : node->drawnChunks()) {
    EXPECT_GT(terrain::buildChunk(*hf, l, k).surfaceTriangles, 0u);
    EXPECT_LE(projectedPixels(*hf, l, k, v.eye), 1.0 + kPixelSlack);
  }
  const ChunkKey inHole{0, 17, 8};  // cols 272..288, rows 128..144: inside the hole (256..400, 100..300)
  EXPECT_TRUE(terrain::buildChunk(*hf, l, inHole).empty());
  EXPECT_FALSE(std::any_of(node->drawnChunks().begin(), node->drawnChunks().end(),
                           [&](const ChunkKey& k) { return k == inHole; }));
}


TEST(PagedLodTerrain, NoSkyBelowTheTerrainAlongTheBundledFlythroughsInTheRenderer) {
  if (!std::filesystem::exists(test::bundledSceneFile())) GTEST_SKIP() << test::bundledSceneFile() << " is absent";
  constexpr int kEvery = 120;        // one frame every two seconds of each flythrough
  constexpr int kMaxSettleFrames = 32;
  const Scene scene = loadScene(test::bundledSceneFile().string());
  const CollisionWorld world = CollisionWorld::fromScene(scene, scene.spec.method);
  WalkerOptions wo;
  wo.viewer = scene.spec.viewer;
  RenderOptions ro;
  ro.idPass = true;
  osg::ref_ptr<PagedLodTerrain> made;
  ViewRenderer renderer(scene, ro, bench::osgPagedLodMaker(&made));
  ASSERT_NE(made, nullptr);
  EXPECT_EQ(renderer.graph().madeTerrain(), made.get());
  EXPECT_EQ(renderer.graph().ownQuadtreeTerrain(), nullptr);
  EXPECT_THROW(renderer.graph().pagedTerrain(), std::logic_error);
  const PagedLodTerrain& lod = *made;
  std::size_t frames = 0, crackPixels = 0;
  for (const char* name : {"bench_patrol.txt", "ramp_descent.txt", "low_flight.txt", "equipment_walk.txt",
                           "equipment_fly.txt"}) {
    const Script script = readScript(test::bundledScript(name).string());
    runFlythrough(scene, world, script, wo, [&](const FrameRecord& r) {
      if ((r.frame - 1) % kEvery != 0) return;
      const ViewPose pose{r.eye, r.headingDeg, r.pitchDeg, false, {}};
      int n = 1;
      for (renderer.render(pose); renderer.lastStats().terrain.chunksWanted > 0 && n < kMaxSettleFrames; ++n) {
        EXPECT_TRUE(lod.waitUntilIdle(kPagerWaitSeconds));
        renderer.render(pose);
      }
      EXPECT_EQ(renderer.lastStats().terrain.chunksWanted, 0u) << name << " frame " << r.frame;
      EXPECT_GT(renderer.lastStats().terrain.trianglesDrawn, 0u);
      const std::size_t sky = test::skyBelowSilhouette(renderer.image());
      ++frames;
      crackPixels += sky;
      EXPECT_EQ(sky, 0u) << name << " frame " << r.frame;
      if (const char* dir = std::getenv("NESTWALK_CRACK_FRAMES"))
        osgDB::writeImageFile(renderer.image(), std::string(dir) + "/paged_lod_" + name + "_" + std::to_string(r.frame) +
                                                    ".png");
    });
  }
  std::printf("PagedLOD terrain: %zu sky pixels below the silhouette in %zu frames; %zu chunks resident\n",
              crackPixels, frames, lod.lastStats().chunksResident);
  EXPECT_GT(frames, 20u);
}

}  // namespace
}  // namespace nestwalk
