// Imagery at its own resolution: the draped orthophoto as a quadtree of texture tiles over the
// terrain's chunk layout (terrain/terrain_chunk.h), independent of the DEM's spacing, each drawn
// terrain part textured from the level whose texel the view can just show there. The paged terrain
// (paged_terrain.h) owns one and asks it, part by part, which tile to lay over what it draws.
//
// Tiles: a tile covers the area of a chunk, ImageryTileKey (areaLevel, x, y): the area of chunk
// (areaLevel, x, y) of the layout for areaLevel >= 0, and for areaLevel -1 a level-0 chunk's
// quadrant (x = 2 chunk x + east, y = 2 chunk y + south), the smallest part the terrain draws. Its
// texels are all of one size, that of its texel level t (<= areaLevel):
//     texel(t) = 2^t chunkCells spacing / kImageryTileTexels   (map units; x and y each their own)
// so a tile has kImageryTileTexels texels a side when t = areaLevel, and only quadrant areas hold
// finer ones, up to kMaxImageryTileTexels a side. Texel (i, j) is the imagery's colour at its centre,
// read through the imagery's reader (terrain_imagery.h: a read at a spacing coarser than the
// imagery's pixels is filtered and comes from the coarsest overview still as fine, so a far tile
// costs what its texels cost and shows the average, not a sample, of what it covers: the distance
// filtering mipmaps would give, built once per tile, never per frame). Where the imagery has no data
// a texel takes the height ramp's colour at the ground under it (terrainRampColour), so holes show
// the terrain's own colours as before. Textures are linear, clamped to their edges, without mipmaps.
//
// Levels: the finest texel level is the coarsest whose texel is at most kFinestTexelSlack times the
// imagery's pixel (or finestTexelM where that is coarser: the benchmarks' DEM-resolution drape),
// never finer than kMaxImageryTileTexels on a quadrant; the coarsest is the layout's top (the root's area, built by the
// constructor so that there is always a tile to draw).
//
// Choice (texelLevelFor): a GPU's mipmap selection, done for a part's nearest point per block in
// view (a block outside the frustum shows nothing, however near the eye it lies): the texel that
// covers one pixel along the screen's coarser axis there. A pixel at distance d covers
// d / pixelsPerRadian metres across the view and that over c along it, c the cosine of the angle
// between the view's ray and the block's mean normal (ChunkBlock::normalSum), at least
// kMinImageryCosine. The level is the coarsest whose texel is at most that footprint, within
// [finest, top]: a GPU's mip level, rounded towards the sharper, where the block's surface is its
// mean plane (rounding to the nearest level instead was measured to draw parts up to 1.4 levels
// coarser than the GPU, blurring what it would show sharp). Measured
// against the GPU's own choice (tests/render/imagery_tiles_test.cpp): where the surface under the
// nearest pixel tilts away from the mean (waves, the toe of a face) or the block's nearest point
// lies nearer than the nearest pixel it shows, the rule is finer than the GPU.
//
// Loading: like the chunks (paged_terrain.h): a loader thread of its own builds the tiles the last
// frame asked for, coarser first, and a frame draws the nearest resident ancestor of a tile still
// loading (Background); or every wanted tile is built before the frame is drawn (Complete).
//
// Memory: a tile costs its RGBA texels once: OSG lets go of its image once the GL has its copy
// (llvmpipe keeps that copy in the process, so it is the resident cost). The paged terrain
// counts tiles and chunks in one budget: tiles are asked for only while they fit, and those a frame
// did not draw go, oldest first, when the budget is short (never the top one).
//
// Frames: tiles are placed in the mesh frame (metres from the heightfield's sample (0, 0)); the
// reader is asked for map coordinates (mapOrigin + (x, y)).
//
// Threads: the reader is called on the loader thread only (Complete: on the cull thread); the rest
// on the cull thread.
#pragma once

#include "nestwalk/render/view_options.h"
#include "nestwalk/terrain/heightfield.h"
#include "nestwalk/terrain/terrain_chunk.h"

#include <osg/StateSet>
#include <osg/ref_ptr>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

namespace nestwalk {

template <class Key, class Result>
class BuildQueue;

/// Texels a side of a tile whose texel level is its area's: 256, a chunk's 64 cells at 4 texels each.
inline constexpr int kImageryTileTexels = 256;

/// The largest tile, texels a side (a level-0 quadrant at texel level areaLevel - 4): 4096 x 4096 x 4
/// bytes, 64 MiB. A quadrant of 32 cells at 1 m then holds 8 mm texels; finer imagery over such a DEM
/// is drawn at 8 mm.
inline constexpr int kMaxImageryTileTexels = 4096;

/// Dimensionless: the finest texels may be up to this much coarser than the imagery's pixels. Texel
/// sizes step by 2; without slack a 3 cm orthophoto over a 1 m DEM would be drawn at 1.56 cm (four
/// times the texture memory, no detail the file holds) rather than at 3.125 cm.
inline constexpr double kFinestTexelSlack = 1.3;

/// The cosine of the steepest view of a surface the texel choice counts (dimensionless): a view
/// more oblique than about 89 degrees from the normal is given the texel of that angle, at most
/// six levels coarser than a head-on view's. A GPU without anisotropic filtering goes on coarsening
/// to the horizon; 1/16 (four levels) drew 7 of 49 parts of the test's grazing views 1 to 2 levels
/// finer than it, 1/64 draws 2 (tests/render/imagery_tiles_test.cpp).
inline constexpr double kMinImageryCosine = 1.0 / 64.0;

struct ImageryTileKey {
  int areaLevel = 0, x = 0, y = 0;  // the area (see above)
  int texelLevel = 0;               // <= areaLevel
  friend bool operator==(const ImageryTileKey& a, const ImageryTileKey& b) {
    return a.areaLevel == b.areaLevel && a.x == b.x && a.y == b.y && a.texelLevel == b.texelLevel;
  }
};

struct ImageryTileKeyHash {
  std::size_t operator()(const ImageryTileKey& k) const {
    return std::hash<std::int64_t>()((std::int64_t(k.areaLevel + 8) << 56) ^ (std::int64_t(k.texelLevel + 8) << 48) ^
                                     (std::int64_t(k.x) << 24) ^ std::int64_t(k.y));
  }
};

struct ImageryTilesOptions {
  terrain::ColourGridReader imagery;  // the draped imagery, RGBA8 at map grid points
  double imageryPixelM = 1;           // its pixel size, map units (TerrainImagery::pixelSize)
  double finestTexelM = 0;            // no texel finer than this (0: the imagery's own)
  Eigen::Vector2d mapOrigin = Eigen::Vector2d::Zero();  // map x, y of mesh-frame (0, 0)
  double heightLo = 0, heightHi = 1;  // the height ramp's ends, for holes (metres)
  TerrainLoading loading = TerrainLoading::Background;
};

/// What the tiles did in the last frame.
struct ImageryTileStats {
  std::size_t tilesResident = 0, residentBytes = 0;
  std::size_t tilesWanted = 0;     // drawn parts whose tile was not resident (a coarser one stood in)
  std::uint64_t tilesLoaded = 0, tilesEvicted = 0;
  double loadSeconds = 0;
};

class ImageryTiles {
 public:
  /// Builds the top tile. std::invalid_argument without a reader or with a pixel size not positive.
  ImageryTiles(std::shared_ptr<const terrain::Heightfield> heightfield, const terrain::ChunkLayout& layout,
               ImageryTilesOptions options);
  ~ImageryTiles();
  ImageryTiles(const ImageryTiles&) = delete;
  ImageryTiles& operator=(const ImageryTiles&) = delete;

  int finestTexelLevel() const { return finest_; }
  int topTexelLevel() const { return top_; }
  /// The texel size of level t along x (map units).
  double texelSize(int texelLevel) const;
  /// Whether a mesh-frame box is in view (the cull's frustum test).
  using BoxInView = std::function<bool(const Eigen::Vector3d& min, const Eigen::Vector3d& max)>;
  /// The texel level for a part whose blocks are given (see "Choice" above), over the blocks in view
  /// (all when inView is empty); eye in the mesh frame.
  int texelLevelFor(const std::vector<terrain::ChunkBlock>& blocks, const Eigen::Vector3d& eye, double pixelsPerRadian,
                    const BoxInView& inView = {}) const;

  /// The tile a drawn part of chunk `chunk` covering area (areaLevel, x, y) wants at texel level t
  /// (clamped to the area: a coarser level is the ancestor's tile).
  static ImageryTileKey wanted(int areaLevel, int x, int y, int texelLevel);

  /// Frame: merge what the loader built; then for each drawn part the state to draw it with (the
  /// wanted tile or its nearest resident stand-in, mapped onto chunk `chunk`'s imagery coordinates;
  /// kept with the tile while frames draw that chunk with it) and the tile it got; then end (ask for
  /// what was missing within `budgetLeft` bytes, and evict).
  void beginFrame();
  osg::StateSet* stateFor(const terrain::ChunkKey& chunk, const ImageryTileKey& wanted,
                                       ImageryTileKey& drawn);
  /// Complete loading: builds the wanted tiles still missing that fit in `budgetLeft` (call between
  /// the parts' choices and stateFor).
  void buildMissing(const std::vector<ImageryTileKey>& wanted, std::size_t budgetLeft);
  void endFrame(std::size_t budgetLeft);
  /// Evicts tiles the frame did not draw, oldest first, until at most `target` bytes are resident.
  void evictUnused(std::size_t target);
  std::size_t residentBytes() const { return residentBytes_; }
  const ImageryTileStats& stats() const { return stats_; }
  void waitUntilIdle();
  std::string loadError() const;
  void releaseGLObjects(osg::State* state) const;

 private:
  struct Tile;
  struct Built;
  Built build(const ImageryTileKey& key) const;
  void insert(Built&& b);
  std::size_t tileBytes(const ImageryTileKey& key) const;

  std::shared_ptr<const terrain::Heightfield> hf_;
  const terrain::ChunkLayout layout_;
  ImageryTilesOptions options_;
  int finest_ = 0, top_ = 0;
  std::unordered_map<ImageryTileKey, Tile, ImageryTileKeyHash> tiles_;
  std::size_t residentBytes_ = 0;
  std::uint64_t frame_ = 0;
  ImageryTileStats stats_;
  std::vector<ImageryTileKey> missing_;  // wanted this frame, not resident
  std::unique_ptr<BuildQueue<ImageryTileKey, Built>> loader_;  // Background: the loader (build_queue.h)
};

}  // namespace nestwalk
