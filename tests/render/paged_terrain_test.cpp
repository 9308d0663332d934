// The paged terrain's selection (render/paged_terrain.h), through real OSG cull traversals (no GL
// needed): a complete frame draws the coarsest cut of the chunk tree whose every chunk shows at most
// a pixel of error (checked against the chunks' own errors and boxes, recomputed here); background
// loading settles to the same cut; a tiny budget is kept while the view stays covered, coarser;
// chunks that are all holes are never drawn; simplified chunks keep every drawn part within a pixel
// of the fine surface (brute force over the drawn triangles) with fewer triangles.
#include "nestwalk/render/paged_terrain.h"
#include "nestwalk/terrain/heightfield.h"
#include "nestwalk/terrain/terrain_chunk.h"
#include "nestwalk/terrain/terrain_import.h"
#include "nestwalk/terrain/terrain_pyramid.h"
#include "tests/common/temp_folder.h"
#include "tests/render/hills_terrain.h"
#include "tests/render/terrain_checks.h"

#include <osgUtil/SceneView>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <set>
#include <vector>

namespace nestwalk {
namespace {

using terrain::ChunkKey;

constexpr double kPixelsPerRadian = 623.5;

using test::hills;
using test::terraces;

using test::View;
using test::viewFrom;

void cullOnce(osg::Node* root, const View& v) {
  osg::ref_ptr<osgUtil::SceneView> sv = new osgUtil::SceneView;
  sv->setDefaults();
  sv->setComputeNearFarMode(osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);
  sv->setCullingMode(osg::CullSettings::VIEW_FRUSTUM_CULLING);
  sv->setViewport(0, 0, 1280, 720);
  sv->setSceneData(root);
  sv->setViewMatrix(v.view);
  sv->setProjectionMatrix(v.projection);
  sv->cull();
}

PagedTerrainOptions options(TerrainLoading loading, std::size_t budget = 0) {
  PagedTerrainOptions o;
  o.chunkCells = 16;
  o.pixelsPerRadian = kPixelsPerRadian;
  o.maxPixels = 1.0;
  o.loading = loading;
  o.budgetBytes = budget;
  o.simplifyFraction = 0;  // the level grids, whose surface chunkHeightAt gives (simplified: below)
  return o;
}

/// The fine sample range [c0, c1] x [r0, r1] of a chunk's quadrant (a + 2b): its child's cells.
struct PartRange {
  int c0, c1, r0, r1;
};
PartRange partRange(const terrain::ChunkLayout& l, const ChunkKey& k, int q) {
  const std::vector<int> cols = l.columns(k), rows = l.rowsOf(k);
  const std::size_t half = std::size_t(l.chunkCells() / 2);
  const int cm = half < cols.size() ? cols[half] : cols.back(), rm = half < rows.size() ? rows[half] : rows.back();
  return {(q & 1) ? cm : cols.front(), (q & 1) ? cols.back() : cm, (q >> 1) ? rm : rows.front(),
          (q >> 1) ? rows.back() : rm};
}

/// The largest projected error of a chunk quadrant's grid surface from the eye (terrain_checks.h;
/// this grid has 512 cells a side, so every level's cells are square).
double projectedPixels(const terrain::Heightfield& hf, const terrain::ChunkLayout& l, const ChunkKey& k, int quadrant,
                       const osg::Vec3d& eye) {
  const PartRange p = partRange(l, k, quadrant);
  return test::projectedPixels(hf, l, k, p.c0, p.c1, p.r0, p.r1, eye, kPixelsPerRadian);
}

/// Whether part a stands for (covers) part b: the same, or b lies in the child chunk a's quadrant
/// replaces.
bool covers(const DrawnPart& a, const DrawnPart& b) {
  if (a == b) return true;
  if (a.key.level <= b.key.level) return false;
  const ChunkKey child{a.key.level - 1, 2 * a.key.x + (a.quadrant & 1), 2 * a.key.y + (a.quadrant >> 1)};
  const int shift = child.level - b.key.level;
  return (b.key.x >> shift) == child.x && (b.key.y >> shift) == child.y;
}

std::vector<DrawnPart> sorted(std::vector<DrawnPart> v) {
  for (DrawnPart& p : v) p.node = nullptr;
  std::sort(v.begin(), v.end());
  return v;
}

const View kLowView = viewFrom({120, -140, 345}, {300, -330, 300});

TEST(PagedTerrain, ACompleteFrameIsTheCoarsestCutWithinAPixel) {
  const auto hf = hills();
  osg::ref_ptr<PagedTerrain> node = new PagedTerrain(hf, options(TerrainLoading::Complete));
  cullOnce(node.get(), kLowView);
  const std::vector<DrawnPart> drawn = node->drawnParts();
  ASSERT_GT(drawn.size(), 10u);
  EXPECT_EQ(node->lastStats().standIns, 0u);
  EXPECT_LE(node->lastStats().maxErrorPx, 1.0 + 1e-9);
  EXPECT_LT(node->lastStats().finestLevel, node->lastStats().coarsestLevel);
  const terrain::ChunkLayout& l = node->layout();
  std::size_t parentsGoodEnough = 0;
  for (const DrawnPart& p : drawn) {
    const ChunkKey& k = p.key;
    EXPECT_LE(projectedPixels(*hf, l, k, p.quadrant, kLowView.eye), 1.0 + 1e-6)
        << k.level << " " << k.x << " " << k.y << " quadrant " << p.quadrant;
    if (k.level + 1 < l.levels()) {
      const ChunkKey parent{k.level + 1, k.x / 2, k.y / 2};
      parentsGoodEnough += projectedPixels(*hf, l, parent, (k.x & 1) + 2 * (k.y & 1), kLowView.eye) <= 1.0;
    }
    for (const DrawnPart& o : drawn)
      if (!(o == p)) {
        EXPECT_FALSE(covers(o, p)) << "a part drawn with one that stands for it";
      }
  }
  // The rule bounds the error block by block, so now and then a parent's quadrant that would have
  // done is refined; rarely, or the bound would be loose.
  EXPECT_LE(parentsGoodEnough, drawn.size() / 10) << "of " << drawn.size();
}

TEST(PagedTerrain, AMidlineSkirtIsDrawnOnlyBesideAQuadrantNotDrawnFromTheSameChunk) {
  // The whole terrain in view from above (nothing culled), nearer at its centre: a quadrant not
  // drawn from its chunk is replaced by finer parts, and the quadrants beside it close the gap with
  // their skirts on the chunk's midlines; quadrants of one chunk drawn side by side share the
  // midlines' vertices and need none (terrain_chunk.h, "Cracks").
  const auto hf = hills();
  osg::ref_ptr<PagedTerrain> node = new PagedTerrain(hf, options(TerrainLoading::Complete));
  cullOnce(node.get(), viewFrom({256, -256, 800}, {256, -256.01, 300}));
  const std::vector<DrawnPart>& drawn = node->drawnParts();
  const terrain::ChunkLayout& l = node->layout();
  long long area = 0;
  for (const DrawnPart& p : drawn) {
    const PartRange r = partRange(l, p.key, p.quadrant);
    area += (long long)(r.c1 - r.c0) * (r.r1 - r.r0);
  }
  ASSERT_EQ(area, (long long)(hf->cols() - 1) * (hf->rows() - 1)) << "the view must see all of the terrain";
  ASSERT_LT(node->lastStats().finestLevel, node->lastStats().coarsestLevel);
  std::size_t withSkirts = 0, withoutSkirts = 0, skirtTriangles = 0;
  for (const DrawnPart& p : drawn) {
    const terrain::ChunkMesh m = terrain::buildChunk(*hf, l, p.key, {}, 0.0);
    const terrain::ChunkQuadrant& quad = m.quadrants[std::size_t(p.quadrant)];
    skirtTriangles += quad.skirtTriangles;
    bool besideAnother = false;  // a quadrant beside it on a midline drawn from another chunk
    for (const int across : {p.quadrant ^ 1, p.quadrant ^ 2})
      besideAnother = besideAnother || std::none_of(drawn.begin(), drawn.end(), [&](const DrawnPart& o) {
                        return o.key == p.key && o.quadrant == across;
                      });
    // This grid has no holes and whole chunks: every quadrant has skirts on both midlines.
    ASSERT_GT(quad.midlineSkirts[0].indexCount, 0u);
    ASSERT_GT(quad.midlineSkirts[1].indexCount, 0u);
    EXPECT_EQ(p.midlineSkirts != nullptr, besideAnother)
        << p.key.level << " " << p.key.x << " " << p.key.y << " quadrant " << p.quadrant;
    if (p.midlineSkirts) skirtTriangles += (quad.midlineSkirts[0].indexCount + quad.midlineSkirts[1].indexCount) / 3;
    ++(p.midlineSkirts ? withSkirts : withoutSkirts);
  }
  EXPECT_GT(withSkirts, 0u);
  EXPECT_GT(withoutSkirts, withSkirts);
  EXPECT_EQ(node->lastStats().skirtTrianglesDrawn, skirtTriangles);
}

TEST(PagedTerrain, QuadrantsOutOfViewAreNeitherDrawnNorRefined) {
  // Every drawn part's box, taken here from the heightfield over its samples (down to the lowest
  // sample within the skirts' reach: a span's bottom takes the lowest of the vertices of the spans
  // around it, each within its segments and kSkirtReachSteps beyond), has a corner on the inner side
  // of each frustum plane in clip space: no part lies wholly outside one plane. Looking along a
  // chunk's edge makes some quadrants of chunks in view lie outside it.
  const auto hf = hills();
  osg::ref_ptr<PagedTerrain> node = new PagedTerrain(hf, options(TerrainLoading::Complete));
  const View v = viewFrom({40, -250, 330}, {40, -60, 310});
  cullOnce(node.get(), v);
  const terrain::ChunkLayout& l = node->layout();
  const osg::Matrixd clip = v.view * v.projection;
  ASSERT_GT(node->drawnParts().size(), 4u);
  for (const DrawnPart& p : node->drawnParts()) {
    const PartRange r = partRange(l, p.key, p.quadrant);
    const int reach = int(terrain::kSkirtSpanSegments + 1 + terrain::kSkirtReachSteps) << p.key.level;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int row = std::max(0, r.r0 - reach); row <= std::min(hf->rows() - 1, r.r1 + reach); ++row)
      for (int col = std::max(0, r.c0 - reach); col <= std::min(hf->cols() - 1, r.c1 + reach); ++col) {
        if (!hf->valid(col, row)) continue;
        lo = std::min(lo, double(hf->sample(col, row)));
        if (col >= r.c0 && col <= r.c1 && row >= r.r0 && row <= r.r1) hi = std::max(hi, double(hf->sample(col, row)));
      }
    // Each plane: x <= w, -x <= w, y <= w, -y <= w, z <= w, -z <= w in clip coordinates.
    for (int plane = 0; plane < 6; ++plane) {
      bool inside = false;
      for (int corner = 0; corner < 8; ++corner) {
        const osg::Vec4d c = osg::Vec4d(corner & 1 ? r.c1 : r.c0, -(corner & 2 ? r.r1 : r.r0), corner & 4 ? hi : lo - 1.0, 1.0) * clip;
        const double value = (plane & 1 ? -1.0 : 1.0) * c[plane / 2];
        inside = inside || value <= c.w();
      }
      EXPECT_TRUE(inside) << "part " << p.key.level << "/" << p.key.x << "/" << p.key.y << " quadrant " << p.quadrant
                          << " lies outside frustum plane " << plane;
    }
  }
}

TEST(PagedTerrain, BackgroundLoadingSettlesToTheCompleteFrame) {
  const auto hf = hills();
  osg::ref_ptr<PagedTerrain> complete = new PagedTerrain(hf, options(TerrainLoading::Complete));
  cullOnce(complete.get(), kLowView);
  osg::ref_ptr<PagedTerrain> background = new PagedTerrain(hf, options(TerrainLoading::Background));
  cullOnce(background.get(), kLowView);
  // The first frame has only the root: its quadrants stand in for everything.
  EXPECT_LE(background->drawnParts().size(), 4u);
  EXPECT_GE(background->lastStats().standIns, 1u);
  EXPECT_GT(background->lastStats().chunksWanted, 0u);
  int frames = 1;
  while (background->lastStats().chunksWanted > 0 && frames < 50) {
    background->waitUntilIdle();
    cullOnce(background.get(), kLowView);
    ++frames;
  }
  EXPECT_LE(frames, background->layout().levels() + 1);  // one level a frame at most
  EXPECT_EQ(sorted(background->drawnParts()), sorted(complete->drawnParts()));
  EXPECT_EQ(background->lastStats().standIns, 0u);
}

TEST(PagedTerrain, TheLoadersFollowUpsBuildTheWholeCutForOneCull) {
  // The loader queues the children a chunk it built needs for the last cull's view (paged_terrain.h,
  // "Loading"), so one cull and one wait build the whole cut, and the next cull draws it.
  const auto hf = hills();
  osg::ref_ptr<PagedTerrain> complete = new PagedTerrain(hf, options(TerrainLoading::Complete));
  cullOnce(complete.get(), kLowView);
  PagedTerrainOptions o = options(TerrainLoading::Background);
  o.mergeBytesPerFrame = std::size_t(1) << 40;  // every built chunk drawable at the next cull
  osg::ref_ptr<PagedTerrain> background = new PagedTerrain(hf, o);
  cullOnce(background.get(), kLowView);
  ASSERT_GT(background->lastStats().chunksWanted, 0u);
  background->waitUntilIdle();
  cullOnce(background.get(), kLowView);
  const PagedTerrainStats& s = background->lastStats();
  EXPECT_EQ(s.chunksWanted, 0u);
  EXPECT_EQ(s.standIns, 0u);
  EXPECT_EQ(sorted(background->drawnParts()), sorted(complete->drawnParts()));
  // The cut is several levels deep: without follow-ups a cull asks for one level.
  std::set<int> levels;
  for (const DrawnPart& p : complete->drawnParts()) levels.insert(p.key.level);
  EXPECT_LE(*levels.begin() + 2, background->layout().levels() - 1);
  EXPECT_EQ(s.chunksResident, complete->lastStats().chunksResident);
}

TEST(PagedTerrain, AMovingViewIsNotFollowedUpAndAStillOneIs) {
  // After a cull from a view other than the cull before's, the loaders build what that cull asked
  // for and nothing more (paged_terrain.h, kFollowUpStillEyeM); once the view stands still, they
  // go down its whole cut again.
  const auto hf = hills();
  PagedTerrainOptions o = options(TerrainLoading::Background);
  o.mergeBytesPerFrame = std::size_t(1) << 40;
  osg::ref_ptr<PagedTerrain> background = new PagedTerrain(hf, o);
  const View there = viewFrom({40, -250, 330}, {40, -60, 310});
  cullOnce(background.get(), kLowView);
  background->waitUntilIdle();
  cullOnce(background.get(), there);  // moved: its wants only
  const std::size_t asked = background->lastStats().chunksWanted;
  ASSERT_GT(asked, 0u);
  background->waitUntilIdle();
  cullOnce(background.get(), there);  // still
  EXPECT_EQ(background->lastStats().chunksMerged, asked);
  ASSERT_GT(background->lastStats().chunksWanted, 0u);  // the cut goes deeper than one level more
  background->waitUntilIdle();
  cullOnce(background.get(), there);
  osg::ref_ptr<PagedTerrain> complete = new PagedTerrain(hf, options(TerrainLoading::Complete));
  cullOnce(complete.get(), there);
  EXPECT_EQ(background->lastStats().chunksWanted, 0u);
  EXPECT_EQ(sorted(background->drawnParts()), sorted(complete->drawnParts()));
}

TEST(PagedTerrain, ACullMakesAtMostItsMergeBoundDrawableAndStillSettlesToTheCompleteFrame) {
  // A bound of one byte: one built chunk a cull, however many the loader finished meanwhile.
  const auto hf = hills();
  osg::ref_ptr<PagedTerrain> complete = new PagedTerrain(hf, options(TerrainLoading::Complete));
  cullOnce(complete.get(), kLowView);
  PagedTerrainOptions o = options(TerrainLoading::Background);
  o.mergeBytesPerFrame = 1;
  osg::ref_ptr<PagedTerrain> background = new PagedTerrain(hf, o);
  cullOnce(background.get(), kLowView);
  int frames = 1;
  std::size_t merged = 0;
  while (background->lastStats().chunksWanted > 0 && frames < 2000) {
    const std::uint64_t loadedBefore = background->lastStats().chunksLoaded;
    background->waitUntilIdle();
    cullOnce(background.get(), kLowView);
    ++frames;
    const PagedTerrainStats& s = background->lastStats();
    ASSERT_LE(s.chunksMerged, 1u) << "frame " << frames;
    EXPECT_EQ(s.chunksLoaded - loadedBefore, s.chunksMerged);
    merged += s.chunksMerged;
  }
  EXPECT_EQ(sorted(background->drawnParts()), sorted(complete->drawnParts()));
  EXPECT_EQ(background->lastStats().standIns, 0u);
  EXPECT_EQ(merged + 1, background->lastStats().chunksResident);  // the root was built by the constructor
  // Without the bound it settles in a frame a level (the test above); one chunk a frame takes a
  // frame for each chunk.
  EXPECT_GT(frames, background->layout().levels() + 1);
  EXPECT_EQ(std::size_t(frames - 1), merged);
}

TEST(PagedTerrain, ATinyBudgetIsKeptAndTheViewStaysCoveredCoarser) {
  const auto hf = hills();
  osg::ref_ptr<PagedTerrain> full = new PagedTerrain(hf, options(TerrainLoading::Complete));
  const std::size_t budget = 300 * 1024;  // the root and ten more chunks of 16 x 16 cells (about 28 KiB each)
  osg::ref_ptr<PagedTerrain> tiny = new PagedTerrain(hf, options(TerrainLoading::Complete, budget));
  for (int i = 0; i < 12; ++i) {  // low over the ground, from the north-west corner to the south-east
    const osg::Vec3d eye(40 + 36 * i, -40 - 36 * i, 335);
    const View v = viewFrom(eye, eye + osg::Vec3d(60, -60, -25));
    cullOnce(full.get(), v);
    cullOnce(tiny.get(), v);
    EXPECT_LE(tiny->lastStats().residentBytes, budget) << "view " << i;
    EXPECT_GE(tiny->lastStats().maxErrorM, full->lastStats().maxErrorM);
    EXPECT_LT(tiny->drawnParts().size(), full->drawnParts().size());
    // Covered: every part the full cut draws is drawn, or stood in for by an ancestor's quadrant.
    for (const DrawnPart& p : full->drawnParts()) {
      const bool covered = std::any_of(tiny->drawnParts().begin(), tiny->drawnParts().end(),
                                       [&](const DrawnPart& t) { return covers(t, p); });
      EXPECT_TRUE(covered) << "view " << i << " chunk " << p.key.level << " " << p.key.x << " " << p.key.y;
    }
  }
  EXPECT_GT(tiny->lastStats().chunksEvicted, 0u) << tiny->lastStats().chunksLoaded << " loaded, " << tiny->lastStats().residentBytes << " bytes";
  EXPECT_EQ(full->lastStats().chunksEvicted, 0u);
}

/// Simplified chunks of `hf` seen from `view`: every drawn part against the fine surface; how many
/// parts were level 0's exact grids and how many its refinements.
/// With `pyramid`: 64-cell chunks whose errors from level 1 up come from it (paged_terrain.h).
std::pair<std::size_t, std::size_t> checkSimplifiedWithinAPixel(
    std::shared_ptr<const terrain::Heightfield> hf, const View& view,
    std::shared_ptr<const terrain::TerrainPyramid> pyramid = nullptr) {
  PagedTerrainOptions plain = options(TerrainLoading::Complete);
  if (pyramid) plain.chunkCells = terrain::kPyramidTopCells;
  PagedTerrainOptions o = plain;
  o.simplifyFraction = kTerrainSimplifyFraction;
  o.pyramid = pyramid;
  o.pyramidErrorsFromLevel = 1;
  osg::ref_ptr<PagedTerrain> grid = new PagedTerrain(hf, plain);
  osg::ref_ptr<PagedTerrain> simple = new PagedTerrain(hf, o);
  cullOnce(grid.get(), view);
  cullOnce(simple.get(), view);
  EXPECT_LT(simple->lastStats().trianglesDrawn, grid->lastStats().trianglesDrawn);
  EXPECT_LE(simple->lastStats().maxErrorPx, 1.0 + 1e-9);
  // Every drawn part against the fine surface at every fine sample under it: the drawn triangles are
  // the part's range of the chunk built again here (level 0's refinement or exact grid where its node
  // says so).
  const terrain::ChunkLayout& l = simple->layout();
  std::size_t exactParts = 0, refinedParts = 0, samples = 0;
  for (const DrawnPart& part : simple->drawnParts()) {
    std::optional<terrain::ChunkPyramidData> errors;
    if (pyramid && part.key.level > 0) errors = pyramid->chunkPyramidData(part.key);
    const terrain::ChunkMesh m =
        terrain::buildChunk(*hf, l, part.key, {}, o.simplifyFraction, errors ? &*errors : nullptr);
    const terrain::ChunkQuadrant& quad = m.quadrants[std::size_t(part.quadrant)];
    const std::string& name = part.node->getName();
    const bool exact = name.find(" exact") != std::string::npos;
    const std::size_t refined = name.find(" refinement ");
    std::size_t first = exact ? quad.exactFirstIndex : quad.firstIndex;
    std::size_t count = exact ? quad.exactSurfaceTriangles : quad.surfaceTriangles;
    if (refined != std::string::npos) {
      const terrain::ChunkRefinement& r = quad.refinements.at(std::stoul(name.substr(refined + 12)));
      first = r.firstIndex;
      count = r.surfaceTriangles;
      ++refinedParts;
    }
    exactParts += exact ? 1 : 0;
    for (std::size_t t = 0; t < count; ++t) {
      Eigen::Vector3d v[3];
      for (std::size_t k = 0; k < 3; ++k) {
        const std::uint32_t i = m.indices[first + 3 * t + k];
        v[k] = Eigen::Vector3d(m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]) + m.offset;
      }
      const double area = (v[1].x() - v[0].x()) * (v[2].y() - v[0].y()) - (v[1].y() - v[0].y()) * (v[2].x() - v[0].x());
      if (std::abs(area) < 1e-9) continue;
      const int c0 = int(std::floor(std::min({v[0].x(), v[1].x(), v[2].x()}))),
                c1 = int(std::ceil(std::max({v[0].x(), v[1].x(), v[2].x()})));
      const int r0 = int(std::floor(-std::max({v[0].y(), v[1].y(), v[2].y()}))),
                r1 = int(std::ceil(-std::min({v[0].y(), v[1].y(), v[2].y()})));
      for (int r = r0; r <= r1; ++r)
        for (int c = c0; c <= c1; ++c) {
          if (!hf->valid(c, r)) continue;
          const double x = c, y = -r;
          const double w1 = ((x - v[0].x()) * (v[2].y() - v[0].y()) - (y - v[0].y()) * (v[2].x() - v[0].x())) / area;
          const double w2 = ((v[1].x() - v[0].x()) * (y - v[0].y()) - (v[1].y() - v[0].y()) * (x - v[0].x())) / area;
          if (w1 < -1e-9 || w2 < -1e-9 || w1 + w2 > 1 + 1e-9) continue;
          const double z = (1 - w1 - w2) * v[0].z() + w1 * v[1].z() + w2 * v[2].z();
          const double d = std::max((osg::Vec3d(x, y, z) - view.eye).length(), kMinEyeDistanceM);
          EXPECT_LE(std::abs(double(hf->sample(c, r)) - z) * kPixelsPerRadian / d, 1.0 + 1e-6)
              << "chunk " << part.key.level << "/" << part.key.x << "/" << part.key.y << " at " << c << " " << r;
          ++samples;
        }
    }
  }
  EXPECT_GT(samples, 100000u);
  return {exactParts, refinedParts};
}

TEST(PagedTerrain, SimplifiedChunksStayWithinAPixelWithFewerTriangles) {
  const auto [exactParts, refinedParts] = checkSimplifiedWithinAPixel(hills(), kLowView);
  EXPECT_GT(exactParts, 0u);  // the view reaches level 0's exact grids near the eye
}

TEST(PagedTerrain, LevelZeroRefinementsAreDrawnWithinAPixelOnTerraces) {
  const auto [exactParts, refinedParts] =
      checkSimplifiedWithinAPixel(terraces(), viewFrom({200, -250, 306}, {330, -380, 285}));
  EXPECT_GT(refinedParts, 0u);  // between the exact grids at the eye and the simplified further out
}

TEST(PagedTerrain, ChunksWithThePyramidsErrorsStayWithinAPixel) {
  // The hills written as a terrain file with its pyramid; every level from 1 up takes its errors
  // (and its simplified triangles' bounds) from it.
  const auto hf = hills();
  test::TempFolder dir;
  const std::string file = (dir / "hills.tif").string();
  std::vector<float> heights;
  for (int r = 0; r < hf->rows(); ++r)
    for (int c = 0; c < hf->cols(); ++c) heights.push_back(hf->sample(c, r));
  terrain::writeTerrainCog(file, hf->cols(), hf->rows(), heights, hf->origin().x(), hf->origin().y(), hf->dx(),
                           hf->dy(), "EPSG:32633", false);
  const auto pyramid = std::make_shared<const terrain::TerrainPyramid>(file);
  const auto [exactParts, refinedParts] = checkSimplifiedWithinAPixel(hf, kLowView, pyramid);
  EXPECT_GT(exactParts, 0u);
}

TEST(PagedTerrain, ChunksOfHolesAreNeverDrawnAndHolesDoNotBreakTheCut) {
  const auto hf = hills(0.01, true);
  osg::ref_ptr<PagedTerrain> node = new PagedTerrain(hf, options(TerrainLoading::Complete));
  const View v = viewFrom({330, -200, 320}, {330, -260, 290});  // above the big hole
  cullOnce(node.get(), v);
  const terrain::ChunkLayout& l = node->layout();
  ASSERT_GT(node->drawnParts().size(), 0u);
  for (const DrawnPart& p : node->drawnParts()) {
    const terrain::ChunkMesh m = terrain::buildChunk(*hf, l, p.key);
    EXPECT_GT(m.quadrants[std::size_t(p.quadrant)].surfaceTriangles, 0u);
    EXPECT_LE(projectedPixels(*hf, l, p.key, p.quadrant, v.eye), 1.0 + 1e-6);
  }
  // A chunk wholly inside the hole (cols 256..400, rows 100..300) has no triangle: never drawn.
  const ChunkKey inHole{0, 17, 8};  // cols 272..288, rows 128..144
  EXPECT_TRUE(terrain::buildChunk(*hf, l, inHole).empty());
  EXPECT_FALSE(std::any_of(node->drawnParts().begin(), node->drawnParts().end(),
                           [&](const DrawnPart& p) { return p.key == inHole; }));
}

}  // namespace
}  // namespace nestwalk
