// View-bounded terrain: an OpenSceneGraph node that draws a cut of the terrain's chunk quadtree
// (terrain/terrain_chunk.h), chunks built on demand from the heightfield on a background thread and
// kept in a cache with a memory budget, least recently used evicted first. What it costs grows with
// the view, not with the DEM.
//
// Selection (each cull): from the root down, a chunk outside the view frustum is skipped with all
// below it; each quadrant of a chunk (terrain_chunk.h) whose exact error projects to more than
// maxPixels is replaced by its child chunk when that is resident, else drawn itself (and the child
// is asked for). A drawn quadrant therefore shows at most maxPixels of vertical error, except where
// it stands in for a child still loading (Background) or that the budget cannot hold. Rule: the
// largest over the quadrant's blocks of error * pixelsPerRadian / distance, distance from the eye
// to the block's surface box (at least kMinEyeDistanceM): terrain/lod_rule.h's LodRule, block by block.
// Chunks are simplified within their exact error (simplifyFraction, terrain_chunk.h); at level 0 a
// quadrant whose simplified surface would show more than maxPixels draws its exact grid instead.
//
// Loading: Background (the interactive window and timed runs): loader threads (build_queue.h: one
// per core, up to kMaxChunkLoaders, all but the first at a lower priority so that they use the
// cores a frame leaves idle) build the chunks the last cull asked for, coarser levels first (then
// most visible error first), so the whole view refines a level at a time; a cull never waits for
// them, it draws what is resident (the root is built by the constructor, so there is always
// something). Follow-ups: while the view stands still (kFollowUpStillEyeM; a moving view's next
// cull asks anew), a chunk just built is judged at once against the last cull's view (its eye and
// frustum, the same rule as the selection's, the imagery's texel choice aside), and the children it
// would be refined into are queued behind the coarser levels, as far as the budget the cull's wants
// left holds them. The loaders so go down the whole cut without waiting a frame a level:
// bench render's 1 G-sample survey settled its first view after 13 culls before, 3 now (the merge
// bound below). A cull keeps the follow-ups of chunks not yet drawable (it cannot judge them) and
// replaces the rest of the queue. A cull makes at most mergeBytesPerFrame of
// built chunks drawable (coarser first; always at least one), the rest waiting for the next frames:
// the GL objects a frame creates and uploads stay bounded however many chunks the loader finished
// (after a jump of the eye, or a stall). Complete (tests, exact renders): a cull builds what it asks
// for on its own thread before drawing, so each frame is the error rule's full answer whatever the
// timing.
//
// Memory: each resident chunk costs twice the arrays its nodes hold (ChunkNodeMaker::bytes(): the
// vertex arrays and texture once, each surface's 16-bit indices; OSG keeps its copy and the GL
// driver another; with llvmpipe both live in the process). The cache holds at most
// budgetBytes: chunks are asked for only while they fit, and after each cull the chunks it did not
// use go, oldest first, leaves of the resident tree before their parents, until the cache fits. A
// budget smaller than the view needs keeps the view coarser; it never breaks it (the root stays).
//
// Frames: the node's children are in the mesh frame of terrain_chunk.h (metres from the heightfield's
// sample (0, 0)); the caller places it with a transform (view_graph.cpp).
//
// Ownership and threads: the node shares the heightfield (shared_ptr, read from every thread: it is
// immutable) and owns the imagery reader, which the loader threads (or, in Complete mode, the cull
// thread) call one at a time (a mutex: the reader is not thread-safe, terrain_imagery.h). Cull and
// draw on one thread (the viewers here are SingleThreaded); the
// destructor stops the loader thread.
#pragma once

#include "nestwalk/render/frame_stats.h"
#include "nestwalk/render/imagery_tiles.h"
#include "nestwalk/render/view_options.h"
#include "nestwalk/terrain/heightfield.h"
#include "nestwalk/terrain/terrain_chunk.h"
#include "nestwalk/terrain/terrain_pyramid.h"

#include <osg/BoundingBox>
#include <osg/MatrixTransform>
#include <osg/Node>
#include <osg/Polytope>
#include <osg/ref_ptr>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

namespace osgUtil {
class CullVisitor;
}

namespace nestwalk {

template <class Key, class Result>
class BuildQueue;

/// The eye's distance to a chunk is taken as at least this: metres, below any eye height above the
/// ground the walker allows, and keeps the projected error finite inside a chunk's box.
inline constexpr double kMinEyeDistanceM = 0.01;

/// The default simplification of chunk quadrants, a multiple of the level grid's own error (the drawn
/// error stays exact whatever it is: a coarser quadrant is only replaced by its children sooner).
/// Chosen by the triangles a settled frame draws at 1 px. Terrain-size sweep, 0.35 / 0.5 / 0.75 / 1 /
/// 1.5 / 2: 1 M terrain 105k / 102k / 93k / 74k / 75k / 80k, 100 M terrain 503k / 460k / 432k /
/// 409k / 370k / 357k; bench render's bundled flythroughs: 0.5 150k, 1 114k, 1.5 103k.
inline constexpr double kTerrainSimplifyFraction = 1.5;


/// Chunks of this level and coarser take their errors from the terrain pyramid (when there is one);
/// finer ones compute them exactly from the fine samples under them, which costs at most
/// (chunkCells 2^level)^2 samples a chunk whatever the DEM (256 K at level 3), and keeps the
/// simplified surfaces' exact errors (the pyramid's bound is looser) where the eye is near. Levels
/// 1 to 3 still take their level page and skirt lows from the pyramid, so they read no fine tile
/// but those under their cells (bench render's 1 G-sample survey, its first view settling: 26 ms a
/// level-3 chunk instead of 39, the loaders and the frames sharing 2 cores).
/// bench render, 100 M terrain, settled triangles: exact everywhere 370k; from the pyramid from
/// level 1 435k, from level 3 415k, from level 4 379k; settled in 0.2 s in all three.
inline constexpr int kPyramidErrorsFromLevel = 4;

/// What chunk `key` takes from the terrain pyramid: its data (TerrainPyramid::chunkPyramidData) when
/// there is a pyramid and the chunk is of level 1 or coarser, without the errors below level
/// fromLevel (they are then computed from the fine samples); nullopt otherwise. Throws what the
/// pyramid's read throws.
std::optional<terrain::ChunkPyramidData> chunkPyramidDataFor(const terrain::TerrainPyramid* pyramid,
                                                             const terrain::ChunkKey& key, int fromLevel,
                                                             double heightShift);

/// The loaders follow up a view only while it stands still (paged_terrain.h's "Loading"): its eye
/// within this many metres of the cull before's, and its frustum's planes turned by at most this
/// many radians (their unit normals that far apart). bench render's 600 timed poses over the 1 G
/// survey, each a jump: 2,735 chunks built with follow-ups for every view, 2,310 without, and a
/// peak of 1,434 MiB against 1,268.
inline constexpr double kFollowUpStillEyeM = 0.001;
inline constexpr double kFollowUpStillTurnRad = 1e-5;

/// The chunk bytes a cull makes drawable at most (paged_terrain.h's "Loading"): 64 MiB, about
/// 280 chunks of 64 cells over the 3.2 cm survey of bench render's sweep (level 0 with its
/// refinements), which the loaders' follow-ups finish at once. bench render, its first view: a
/// frame making 50 MiB drawable took 177 ms where the settled frame takes 130 (llvmpipe, 1280 x
/// 720), and the view settled in 3.2-3.6 s, against 5.2 s at 16 MiB (9 frames of merging).
inline constexpr std::size_t kChunkMergeBytesPerFrame = std::size_t(64) << 20;

/// Chunk loader threads at most (PagedTerrainOptions::loaderThreads): a chunk of levels 0-3 costs
/// 3-10 ms of CPU over the 1 G-sample survey, so a few threads settle a view in a fraction of the
/// time; more would mostly contend for the terrain file's reads, which one mutex serialises
/// (terrain_pyramid.h).
inline constexpr int kMaxChunkLoaders = 4;

/// The default cache budget: a sixteenth of the machine's memory, within [256 MiB, 1 GiB].
std::size_t defaultTerrainBudgetBytes();

struct PagedTerrainOptions {
  int chunkCells = 64;              // cells per chunk side, a power of two >= 2
  double pixelsPerRadian = 623.5;   // the screen's (LodRule::pixelsPerRadian; 1280 x 720 at 60 degrees)
  double maxPixels = 1.0;           // the largest vertical error drawn, pixels (0: full resolution)
  std::size_t budgetBytes = 0;      // 0: defaultTerrainBudgetBytes()
  std::size_t mergeBytesPerFrame = kChunkMergeBytesPerFrame;  // Background: built chunk bytes made drawable a cull
  TerrainLoading loading = TerrainLoading::Background;
  int loaderThreads = 0;            // Background: chunk loader threads (0: one per core, up to kMaxChunkLoaders)
  bool shade = true;                // bake Horn's hillshade into the colours
  /// Each chunk quadrant simplified to about this multiple of its level grid's error (exact error
  /// kept, terrain_chunk.h); 0: the level grids as they are.
  double simplifyFraction = kTerrainSimplifyFraction;
  terrain::ColourGridReader imagery;  // draped imagery (empty: colours by height)
  /// The imagery's pixel size (map units, TerrainImagery::pixelSize): > 0 drapes it as tiles at its
  /// own resolution (imagery_tiles.h: chunks then carry the light alone, and a part whose texel need
  /// is finer than its area's tile refines its geometry); 0 bakes it into each chunk's texture at the
  /// level's resolution (one texel per kept sample).
  double imageryPixelM = 0;
  double imageryFinestTexelM = 0;   // tiles: no texel finer than this (0: the imagery's own)
  bool imageryMipmaps = true;       // tiles: with their mip levels (imagery_tiles.h)
  Eigen::Vector2d mapOrigin = Eigen::Vector2d::Zero();  // map x, y of mesh-frame (0, 0) (for the imagery)
  /// The terrain's pyramid (the heightfield's grid; chunkCells must then be its kPyramidTopCells):
  /// coarse chunks take their grid errors from it instead of reading every fine sample under them
  /// (terrain_chunk.h, "Errors from the pyramid"). Null: computed. A read that fails (a page
  /// corrupted on disk) falls back to computing, for good.
  std::shared_ptr<const terrain::TerrainPyramid> pyramid;
  int pyramidErrorsFromLevel = kPyramidErrorsFromLevel;  // tests lower it to reach every level
  /// Metres the heightfield's heights lie above the pyramid's (Scene::terrainHeightShift).
  double pyramidHeightShift = 0;
};


/// A drawn part of the terrain: quadrant `quadrant` (a + 2b: the cells of child (2x + a, 2y + b)) of
/// chunk `key`.
struct DrawnPart {
  terrain::ChunkKey key;
  int quadrant = 0;
  osg::Node* node = nullptr;
  /// Its skirts on the chunk's midlines (terrain_chunk.h, ChunkQuadrant::midlineSkirts), drawn with
  /// it where a quadrant beside it (quadrant ^ 1, quadrant ^ 2) is neither drawn from the same chunk
  /// nor out of view; else null.
  osg::Node* midlineSkirts = nullptr;
  /// Imagery tiles: the texel level the part's view asks for, the tile that asks for (its area or an
  /// ancestor's) and the tile it was drawn with (that one, or a resident stand-in while it loads).
  int imageryTexelLevel = 0;
  ImageryTileKey imageryWanted, imageryDrawn;
  friend bool operator==(const DrawnPart& p, const DrawnPart& o) { return p.key == o.key && p.quadrant == o.quadrant; }
  friend bool operator<(const DrawnPart& p, const DrawnPart& o) {
    return p.key < o.key || (p.key == o.key && p.quadrant < o.quadrant);
  }
};

class PagedTerrain : public osg::Node {
 public:
  /// Builds the root chunk (so the first frame has terrain) and, for Background, starts the loader.
  /// Throws std::invalid_argument for bad options.
  PagedTerrain(std::shared_ptr<const terrain::Heightfield> heightfield, PagedTerrainOptions options);
  ~PagedTerrain() override;
  PagedTerrain(const PagedTerrain&) = delete;
  PagedTerrain& operator=(const PagedTerrain&) = delete;

  const char* libraryName() const override { return "nestwalk"; }
  const char* className() const override { return "PagedTerrain"; }
  void traverse(osg::NodeVisitor& nv) override;
  osg::BoundingSphere computeBound() const override;
  void resizeGLObjectBuffers(unsigned maxSize) override;
  void releaseGLObjects(osg::State* state = nullptr) const override;

  const PagedTerrainStats& lastStats() const { return stats_; }
  const PagedTerrainOptions& options() const { return options_; }
  const terrain::ChunkLayout& layout() const { return layout_; }
  std::size_t budgetBytes() const { return budget_; }
  /// The screen changed (a resized window): the projection rule's pixels per radian.
  void setPixelsPerRadian(double pixelsPerRadian) { options_.pixelsPerRadian = pixelsPerRadian; }
  /// Waits until the loader has built everything asked for so far (Background; returns at once for
  /// Complete). For tests and for timing a settled view.
  void waitUntilIdle();
  /// The first chunk the loader could not build (empty: none), e.g. out of memory; that chunk's
  /// parent stays drawn.
  std::string loadError() const;
  /// The chunk quadrants the last cull drew.
  const std::vector<DrawnPart>& drawnParts() const { return drawn_; }
  /// The imagery tiles (null without tiled imagery).
  const ImageryTiles* imageryTiles() const { return tiles_.get(); }

 private:
  struct Entry;
  struct Built;
  struct Want {
    terrain::ChunkKey key;
    double priority;  // the parent's projected error, pixels
  };
  Built build(const terrain::ChunkKey& key) const;
  void insert(Built&& built);
  void mergeLoaded();
  void select(const terrain::ChunkKey& key, osgUtil::CullVisitor& cv, std::vector<Want>& wants);
  /// A surface's projected error seen from `eye` (mesh frame): the largest of its blocks', pixels.
  static double projectedPixels(const Entry& entry, std::size_t quadrant, std::size_t surface, const osg::Vec3d& eye,
                                double pixelsPerRadian);
  /// The loader's follow-up (build_queue.h): queues the children of a chunk just built that the last
  /// cull's view would ask for (see "Loading").
  template <class Shared>
  void followUp(const Built& built, Shared& shared);
  std::size_t estimatedBytes(const terrain::ChunkKey& key) const;
  /// Coarser levels first, then the larger projected error.
  static void sortByPriority(std::vector<Want>& wants);
  void evictUnused(std::size_t target);
  /// The budget left to chunks: what the imagery tiles do not hold.
  std::size_t chunkBudget() const;
  void publish(std::vector<Want> wants, const osg::Vec3d& eye, const osg::Polytope& frustum);

  std::shared_ptr<const terrain::Heightfield> hf_;
  PagedTerrainOptions options_;
  terrain::ChunkLayout layout_;
  terrain::ChunkShading shading_;
  std::size_t budget_ = 0;
  std::unordered_map<terrain::ChunkKey, Entry, terrain::ChunkKeyHash> cache_;
  std::size_t residentBytes_ = 0;
  std::uint64_t frame_ = 0;
  PagedTerrainStats stats_;
  std::vector<DrawnPart> drawn_, drawList_;
  osg::BoundingSphere bound_;
  std::unique_ptr<ImageryTiles> tiles_;

  /// The last cull's view, for the loader's follow-ups: its eye and frustum (mesh frame; no plane:
  /// the cull did not test it), its rule, and the budget's bytes its wants left. Read and written
  /// under the loader's lock.
  struct LoaderView {
    bool valid = false;
    bool followUps = false;  // the view stood still since the cull before (or is the first)
    osg::Vec3d eye;
    osg::Polytope frustum;
    double pixelsPerRadian = 0, maxPixels = 0;
    std::size_t bytesLeft = 0;
  } loaderView_;
  mutable std::atomic<bool> pyramidFailed_{false};  // a pyramid read failed: errors computed from then on
  std::unique_ptr<BuildQueue<terrain::ChunkKey, Built>> loader_;  // Background: the loader (build_queue.h)
};

}  // namespace nestwalk
