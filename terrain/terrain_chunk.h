// Terrain chunks for view-bounded rendering: a quadtree over the heightfield's grid in which every
// node (a chunk) holds the same number of cells per side at its own level, so that what is drawn
// grows with the view, not with the DEM. The renderer (engine/render/paged_terrain.h) builds chunks
// on demand from the heightfield that the walker already holds and draws a cut of the tree.
//
// Layout: with C = chunkCells (a power of two), the chunk (level L, x, y) covers the fine samples
// cols [x C 2^L, min((x + 1) C 2^L, cols - 1)] and rows [y C 2^L, min((y + 1) C 2^L, rows - 1)],
// keeping every s-th of them (s = 2^L, counted from sample 0 of the whole grid, so every coarser
// grid line is also a line of every finer level) plus the grid's last column and row where they
// fall between two kept ones. The root is the one chunk of the top level; a chunk's children are the
// (up to four) chunks of the level below inside it. Level 0 is exactly the heightfield's
// triangulation (heightfield.h); every coarser cell is split along its north-west to south-east
// diagonal like the fine ones, and a coarse triangle exists only when its three samples are valid.
//
// Error: maxError is max |fine(p) - coarse(p)| over every point p where both surfaces exist,
// exact: square coarse cells follow fine edges, so the maximum lies at fine samples (the argument
// is at the top of terrain_chunk.cpp); the last column's and row's narrower cells have a diagonal that crosses fine
// cells, and there the crossings of that diagonal with the fine edges are evaluated as well (the
// difference is linear on every piece of the two triangulations' common refinement).
//
// Quadrants: a chunk's cells fall into four quadrants, those of its four children. The renderer
// replaces a chunk quadrant by quadrant (a chunk near the eye on one side only sends one quadrant
// down a level), so a quadrant's triangles and its skirts on the chunk's own edges are one range of
// the index array, and its skirts on the chunk's midlines two more (see "Cracks").
//
// Blocks: each quadrant's cells are grouped into blocks of chunkBlockCells() cells a side (aligned
// on the level's grid: 8 x 8 cells for 64-cell chunks, the terrain pyramid's blocks), at most
// kChunkBlocksPerSide / 2 a side, each with the maximum error of its own cells and the box of its cells' surface vertices. Every
// point of the coarse surface lies in a block whose box holds it and whose error bounds its own, so
// max over blocks of (error / distance from the eye to the box) bounds the projected error of a
// quadrant far more tightly than one error at its nearest point.
//
// Simplification (when asked): a quadrant's grid triangles are simplified with meshoptimizer
// (quadric error, no vertex moved, borders locked: the quadrant's edges and the borders of holes keep
// every vertex, so its skirts and its neighbours meet it as before) to a target of a fraction of the
// grid's own error (at level 0, of the error level 1's grid has over the same cells). The result is
// kept only when every triangle still faces up (zero-area slivers along a locked border are kept:
// they close the border to its polyline) and has fewer triangles. Its error is then exact again, and
// vertical: the difference of a triangle's plane and the fine surface is linear on every piece of the
// triangle cut by the fine cells, so its largest value lies at a fine sample inside the triangle or
// where an edge crosses a fine column, row or diagonal; all of them are evaluated. A triangle goes to
// the block holding its centroid (the block's box grows to hold it), so the blocks' bound still
// holds. Level 0 keeps its exact grid beside the simplified one (ChunkQuadrant::exact*), drawn where
// the simplified one's error would show; coarser levels have their children for that. On the bundled
// dump the renderer draws about two thirds of the grids' triangles at the same 1 px (bench render).
//
// Errors from the pyramid (when buildChunk is given what the terrain pyramid knows of the chunk,
// ChunkPyramidData, terrain_pyramid.h): a coarse chunk is then built from its level's samples alone
// (the pyramid's level page: heights, and the hillshade's neighbours; no fine sample is read),
// its skirts reach at least down to the lowest sample of the pyramid's blocks they lie in. Its
// grid's block errors are the given ones (the pyramid's exact errors, rounded up to float), and a
// simplified triangle's error is bounded instead of evaluated at fine samples: over each piece of
// the triangle cut by the level grid's triangles, |fine - simplified| <= |fine - level grid| +
// |level grid - simplified|, the first at most the piece's block error, the second linear on the
// piece and so largest at a corner of it (the level triangle clipped to the simplified one). The
// bound is at least the exact error and at most the exact error plus twice the largest grid error
// of the blocks the triangle crosses; the 1 px rule stays a guarantee, a quadrant is only replaced
// by its children sooner (bench render's 100 M terrain: 18 % more triangles when settled).
// Given without errors (the finer levels, where that bound would cost triangles: kPyramidErrorsFromLevel,
// paged_terrain.h), the level page and the blocks' lows are used as above and the errors are
// evaluated exactly at the fine samples under the chunk, which are then the only fine samples read:
// the hillshade's neighbours and the skirts' reach beyond the chunk would otherwise read the tiles
// around it (over a paged heightfield a level-3 chunk read 9 to 16 tiles instead of its own 4).
//
// Refinements: near the eye a level-0 quadrant's simplified surface can show more than the allowed
// error while the exact grid would draw far more triangles than needed. Level 0 therefore also keeps
// up to kMaxRefinements simplifications at smaller targets (each kRefinementTargetDivisor below the
// last, while it saves enough triangles; a target at or above the error meshoptimizer says the last
// simplification reached is skipped, as it would give that surface again: 191 of 960 refinements'
// simplifications on bench render's 1 G-sample survey), every one with its own exact error and
// blocks; the renderer draws the coarsest of the quadrant's surfaces whose projected error is within
// the rule. They share the chunk's vertices (an index range each) and keep every border vertex, so
// they meet their neighbours as the quadrant's own surface does.
//
// Cracks: a chunk's edge and a neighbour's edge of another level meet on the same grid line but not
// at the same vertices. Every quadrant edge inside the grid (the chunk's own, and the midlines
// between its quadrants) hangs a skirt: a wall from the edge that reaches, under each edge vertex,
// at least down to the lowest fine sample on that grid line within kSkirtReachSteps of the chunk's
// steps on either side of the vertex's two segments (less kSkirtMarginM). A neighbour's edge is a
// polyline through fine samples of the same line, every point of it no lower than the lower end of
// its segment; so wherever the neighbour's level is at most log2(kSkirtReachSteps) levels away, the
// higher of the two edges has a skirt reaching down to the lower one, and no gap shows. The wall
// hangs in spans of kSkirtSpanSegments segments, each a polygon of the span's edge vertices and two
// bottoms, one under each end, at the least of those lowest samples over the aligned spans around
// that end: the straight bottom between them lies below each of the span's. Split at its lowest
// edge vertex again and again, a span of n segments is n + 1 triangles, none reaching above the
// edge (a bottom under every vertex made 2n: a 32-segment edge is 36 triangles instead of 64, and
// bench render's settled 1 G finer views drew 71,169 skirt triangles instead of 126,514; its first
// view, 144,612 instead of 257,088).
// Two quadrants of one chunk drawn side by side need no skirt between them: every surface keeps its
// quadrant's border vertices, so both draw the midline as the same segments between the same
// vertices (one vertex array, one transform: no rounding apart). Their midline skirts are therefore
// ranges of their own (ChunkQuadrant::midlineSkirts), drawn only beside a quadrant that is not drawn
// from the chunk (replaced by its child, or without triangles): at 3.2 cm cells they were half of
// a settled view's skirts (bench render: 207,922 skirt triangles of 524,860, then 126,514 of 443,452,
// and 71,169 of 388,107 in spans).
// Skirts face outward (front faces away from the chunk), so the terrain's back-face culling drops
// the half that could never be seen.
//
// Shading: each vertex carries a colour: the base colour (draped imagery where given, else a ramp by
// height) times the light of Horn's hillshade (hillshade.h) on the level's own samples (neighbours
// s samples apart; one off the level's lattice, beside the grid's irregular last column or row,
// counts as missing, as one beyond the grid does), with the renderer's sun: kAmbientLight + kSunLight * shade, at most 1. The same
// colours, one texel per kept sample, form the chunk's texture: a simplified surface's large
// triangles still show the imagery and the hillshade at the level's resolution. Without base colours
// (ChunkShading::baseColours false: the renderer drapes imagery tiles at the imagery's own resolution
// over the chunk) a vertex's colour is the light alone and there is no texture.
//
// Frames: the terrain's mesh frame, x = col * dx, y = -row * dy, z = height: metres from sample
// (0, 0) for a projected CRS (the drawing side places it on the map). A chunk's vertices are stored
// relative to its `offset` (its first sample's x and y, z 0) as floats, so they stay small whatever
// the DEM's size.
//
// Reading: a chunk whose errors come from the fine samples reads each of them several times (the
// grid's error, the simplified surface's, shading, skirts); from a paged heightfield it first copies
// its fine window (at most 2^20 samples: levels 0 to 3 of 64-cell chunks) tile by tile, the same
// samples, so those reads cost no tile lookup (a simplified triangle's edge crossings too: they
// interpolate the two samples of the fine line they cross, as the heightfield's ground does there).
//
// Ownership: a ChunkMesh owns its arrays. Thread safety: ChunkLayout is immutable; buildChunk only
// reads the heightfield and may run on several threads at once (the colour reader is called on the
// calling thread and must itself be safe there).
#pragma once

#include "nestwalk/terrain/heightfield.h"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

namespace nestwalk::terrain {

/// Skirts reach the lowest fine sample this many of the chunk's own steps beyond each of its edge
/// vertices' segments: neighbours up to log2(8) = 3 levels finer or coarser are closed (a coarser
/// neighbour's vertices lie at most its step, 2^3 of ours, away; a finer one's skirt needs our step).
inline constexpr int kSkirtReachSteps = 8;
/// Skirts go this much deeper than the lowest sample they must reach: metres, far below any visible
/// size yet above float rounding of heights up to 9 km (0.5 mm).
inline constexpr double kSkirtMarginM = 0.01;
/// A skirt hangs in spans of at most this many segments of its line, each one polygon whose bottom
/// is a straight line under the span (see "Cracks" above): a span of n segments is n + 1 triangles
/// where a bottom under every vertex made 2n. A quadrant's edge of 32 segments is then 36 triangles
/// (spans of 32 would make it 33), while a bottom's lows come from the two spans around it (their
/// vertices span 16 of the level's steps, their reach 17 on either side of the bottom), so the walls
/// stay near the edge's own lows.
inline constexpr std::size_t kSkirtSpanSegments = 8;
/// The sun's light on the terrain: ambient and direct parts, the lit scene's own (view_graph.cpp:
/// ambient 0.30, diffuse 0.85), so a shaded chunk looks as the lit tiles did.
inline constexpr double kAmbientLight = 0.30;
inline constexpr double kSunLight = 0.85;
/// Refinements (level 0, see above): each one's target error is the last one's divided by this.
inline constexpr double kRefinementTargetDivisor = 3.0;
/// At most this many refinements a quadrant: each costs a simplification and an exact error pass
/// when the chunk is built.
inline constexpr int kMaxRefinements = 3;
/// No refinement aims below this many metres: the synthetic dump's roughness is centimetres, and so
/// close to the eye the exact grid is drawn anyway.
inline constexpr double kMinRefinementTargetM = 0.005;
/// A refinement with more than this share of the grid's triangles is not kept: the exact grid costs
/// little more.
inline constexpr double kRefinementMaxGridShare = 0.7;
/// Blocks per chunk side for the projected-error bound (see above): 8 x 8 blocks of 8 x 8 cells in a
/// chunk of 64 (4 x 4 a quadrant); 64 distances a visited chunk per cull.
inline constexpr int kChunkBlocksPerSide = 8;

struct ChunkKey {
  int level = 0, x = 0, y = 0;
  friend bool operator==(const ChunkKey&, const ChunkKey&) = default;
  friend auto operator<=>(const ChunkKey&, const ChunkKey&) = default;
};

/// The chunk one level up that holds `k` (whether it exists is the layout's question).
inline ChunkKey parentOf(const ChunkKey& k) { return {k.level + 1, k.x / 2, k.y / 2}; }

struct ChunkKeyHash {
  std::size_t operator()(const ChunkKey& k) const {
    return (std::size_t(k.level) << 56) ^ (std::size_t(std::uint32_t(k.x)) << 28) ^ std::size_t(std::uint32_t(k.y));
  }
};

class ChunkLayout {
 public:
  /// A grid of cols x rows samples (at least 2 x 2); chunkCells a power of two >= 2.
  /// Throws std::invalid_argument otherwise.
  ChunkLayout(int cols, int rows, int chunkCells);

  int cols() const { return cols_; }
  int rows() const { return rows_; }
  int chunkCells() const { return chunkCells_; }
  /// Levels 0 .. levels() - 1; the root is the one chunk of the top level.
  int levels() const { return levels_; }
  ChunkKey root() const { return {levels_ - 1, 0, 0}; }
  bool exists(const ChunkKey& k) const;
  /// The chunk's children (the chunks of the level below inside it; none at level 0).
  std::vector<ChunkKey> children(const ChunkKey& k) const;
  /// The chunk's kept sample columns (west to east) and rows (north to south), see above.
  std::vector<int> columns(const ChunkKey& k) const;
  std::vector<int> rowsOf(const ChunkKey& k) const;
  /// Chunks per side at a level.
  int chunksX(int level) const;
  int chunksY(int level) const;

 private:
  std::vector<int> kept(int first, int last, int step) const;
  int cols_, rows_, chunkCells_, levels_;
};

/// RGBA8 colours (row-major, row 0 north) at the map points (x0 + i sx, y0 - j sy), i < width,
/// j < height: the draped imagery's reader (alpha 0 where it has none).
using ColourGridReader =
    std::function<std::vector<std::uint8_t>(double x0, double y0, double sx, double sy, int width, int height)>;

/// Cells a side of a chunk's blocks: chunkCells / kChunkBlocksPerSide, at least 1.
inline int chunkBlockCells(const ChunkLayout& layout) { return std::max(1, layout.chunkCells() / kChunkBlocksPerSide); }

/// What the terrain pyramid (terrain_pyramid.h) knows of a chunk beforehand, so that a coarse chunk
/// is built without reading a fine sample (see "Errors from the pyramid" above):
/// - the level grid's exact errors of the chunk's blocks: blocksX x blocksY of them, row-major, the
///   chunk's blocks of chunkBlockCells() cells (fewer at the grid's east and south edges), metres;
///   none (empty, blocksX = blocksY = 0): the errors are evaluated at the fine samples, exactly;
/// - the level's own samples around the chunk (its level page): level columns [x0, x0 + width) and
///   rows [y0, y0 + height), row-major, holes NaN; the chunk's kept samples and their neighbours
///   one step out (the hillshade's); empty: the samples are read from the heightfield;
/// - the lowest valid fine sample of each of the level's blocks (kPyramidBlockCells = 8 cells of the
///   level a side) in the window [blockX0, blockX0 + blockWidth) x [blockY0, ...) (NaN for none):
///   the skirts reach at least down to the lowest of the blocks a skirt's reach lies in, at or below
///   the lowest fine sample of its grid line there; empty: the fine samples of the line are read.
struct ChunkPyramidData {
  int blocksX = 0, blocksY = 0;
  std::vector<float> error;
  int x0 = 0, y0 = 0, width = 0, height = 0;
  std::vector<float> heights;
  int blockX0 = 0, blockY0 = 0, blockWidth = 0, blockHeight = 0;
  std::vector<float> blockLow;
};

/// A block of a chunk's cells: their largest error (metres), the mesh-frame box of their surface
/// vertices (empty, min > max, when none of its cells has a triangle), and the sum of its triangles'
/// upward normals weighted by their areas (the direction of its mean normal: how obliquely a view
/// meets it, for the imagery's texel choice, imagery_tiles.h; zero with the box empty).
struct ChunkBlock {
  double error = 0;
  Eigen::Vector3d min, max;
  Eigen::Vector3d normalSum = Eigen::Vector3d::Zero();
};

/// Level 0: a quadrant's surface simplified within less error than its own, for nearer views (see
/// "Refinements" above); drawn with the quadrant's skirts, which its range repeats.
struct ChunkRefinement {
  std::size_t firstIndex = 0, indexCount = 0;  // into ChunkMesh::indices: its surface, then the skirts
  std::size_t surfaceTriangles = 0;
  double maxError = 0;                         // metres, exact
  std::vector<ChunkBlock> blocks;              // as the quadrant's
};

/// A skirt of a quadrant on a midline of its chunk (see "Cracks" above): `indexCount` indices from
/// `firstIndex` of ChunkMesh::indices (none where that edge has no skirt).
struct ChunkSkirt {
  std::size_t firstIndex = 0, indexCount = 0;
};

/// A quadrant of a chunk: the cells its child (2x + a, 2y + b) covers (a east, b south; index a + 2b),
/// drawn on its own while that child is not (see "Quadrants" above).
struct ChunkQuadrant {
  /// Into ChunkMesh::indices: its surface, then its skirts on the chunk's own edges.
  std::size_t firstIndex = 0, indexCount = 0;
  std::size_t surfaceTriangles = 0, skirtTriangles = 0;  // skirtTriangles: on the chunk's own edges
  /// Its skirts on the chunk's midlines, each needed only where the quadrant across is not drawn
  /// from this chunk: [0] on the vertical midline (beside quadrant index ^ 1), [1] on the horizontal one
  /// (beside index ^ 2). Every surface of the quadrant keeps the midline's vertices, so one range
  /// serves them all. They follow the quadrant's range in ChunkMesh::indices.
  std::array<ChunkSkirt, 2> midlineSkirts;
  double maxError = 0;                         // metres, exact
  std::vector<ChunkBlock> blocks;              // its cells' blocks (see "Blocks" above)
  /// Level 0, simplified: the exact grid's surface and the same skirts, drawn where the simplified
  /// one's error shows (exactIndexCount 0 otherwise).
  std::size_t exactFirstIndex = 0, exactIndexCount = 0, exactSurfaceTriangles = 0;
  /// Level 0, simplified: finer simplifications between the quadrant's own and the exact grid,
  /// coarsest first (errors falling, triangles rising).
  std::vector<ChunkRefinement> refinements;
  bool empty() const { return indexCount == 0; }
};

/// The quadrant across midline k (0 vertical, 1 horizontal; ChunkQuadrant::midlineSkirts) from
/// quadrant q of the same chunk.
constexpr int quadrantAcrossMidline(int q, int k) { return q ^ (k == 0 ? 1 : 2); }

struct ChunkMesh {
  ChunkKey key;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  // mesh frame position of the stored (0, 0, 0)
  std::vector<float> positions;        // x, y, z per vertex, relative to offset
  std::vector<std::uint8_t> colours;   // RGBA per vertex
  /// The same colours as a texture at the level's resolution (see "Shading" above): RGBA texels,
  /// textureWidth x textureHeight = the chunk's kept columns x rows, row 0 north; hole texels copy a
  /// neighbour's. texCoords: u, v per vertex, the centre of its sample's texel ((i + 0.5) / width,
  /// (j + 0.5) / height; a skirt bottom has its top's).
  std::vector<std::uint8_t> texture;
  int textureWidth = 0, textureHeight = 0;
  std::vector<float> texCoords;
  std::vector<std::uint32_t> indices;  // triangles (counter-clockwise), quadrant by quadrant
  std::array<ChunkQuadrant, 4> quadrants;
  std::size_t surfaceTriangles = 0, skirtTriangles = 0;  // over the quadrants (skirtTriangles: theirs)
  std::size_t midlineSkirtTriangles = 0;               // over the quadrants' midline skirts
  std::size_t surfaceVertices = 0;     // vertices [0, surfaceVertices) lie on the surface; the rest
                                       // are skirt bottoms
  double maxError = 0;                 // metres, exact (see above)
  /// Mesh-frame box of the surface vertices, and of everything (skirts included); empty (min > max)
  /// when the chunk has no triangle.
  Eigen::Vector3d surfaceMin, surfaceMax, boxMin, boxMax;
  bool empty() const { return indices.empty(); }
  std::size_t vertexCount() const { return positions.size() / 3; }
};

struct ChunkShading {
  bool shade = true;                       // Horn's hillshade baked in (else the base colour alone)
  Eigen::Vector3d sun{-0.5, 0.5, std::sqrt(0.5)};  // towards the sun, map axes: azimuth 315, altitude 45
  ColourGridReader imagery;                // draped imagery (empty: colours by height)
  /// false: each vertex's colour is the light alone (grey: the hillshade's, or white without shade)
  /// and the chunk has no texture: the drawing side lays the imagery's own tiles over it
  /// (engine/render/imagery_tiles.h). `imagery` is then not read.
  bool baseColours = true;
  double heightLo = 0, heightHi = 1;       // the height ramp's ends, metres (the DEM's range)
  /// The map position of mesh-frame (0, 0): the heightfield's sample (0, 0), for the imagery reader.
  Eigen::Vector2d mapOrigin = Eigen::Vector2d::Zero();
};

/// The colour of the terrain at height h where no imagery is draped: green valleys, brown slopes,
/// white tops, linear between, over [lo, hi] (metres); RGB in [0, 1].
Eigen::Vector3d terrainRampColour(double h, double lo, double hi);

/// Builds one chunk (see above). The layout must be the heightfield's (same cols and rows).
/// simplifyFraction > 0 simplifies each quadrant's surface (see "Simplification" above) to about
/// that fraction of its grid's own error; 0 keeps the level's grid. fromPyramid: what the pyramid
/// knows of the chunk (see "Errors from the pyramid" and ChunkPyramidData); null: everything from
/// the heightfield, errors exact. std::invalid_argument when its errors are not the chunk's blocks or
/// its windows do not cover the chunk.
ChunkMesh buildChunk(const Heightfield& hf, const ChunkLayout& layout, const ChunkKey& key,
                     const ChunkShading& shading = {}, double simplifyFraction = 0,
                     const ChunkPyramidData* fromPyramid = nullptr);

/// The coarse surface of a chunk at mesh-frame (x, y): the closed union of its existing triangles
/// (nullopt outside them). For tests and measurements; O(1).
std::optional<double> chunkHeightAt(const Heightfield& hf, const ChunkLayout& layout, const ChunkKey& key, double x,
                                    double y);

/// The grid surface of a whole level at mesh-frame (x, y): every chunk of the level together (the
/// level's kept samples are the same in every chunk layout: multiples of 2^level and the grid's
/// last column and row), the closed union of its existing triangles; nullopt outside them. O(1),
/// no allocation: what following the ground on that level would cost.
std::optional<double> levelHeightAt(const Heightfield& hf, int level, double x, double y);

/// A row of the chunk levels' table: over every chunk of one level, its grid surface (before any
/// simplification).
struct ChunkLevelStats {
  int level = 0;
  int step = 1;                 // 2^level samples
  std::size_t chunks = 0;       // chunks with at least one triangle
  std::size_t triangles = 0;    // their grids' surface triangles
  double maxError = 0;          // the largest of their exact errors, metres
};

/// Every level's row, each chunk of the layout built once (no shading, no simplification): about
/// levels x samples of work, for reports and benchmarks.
std::vector<ChunkLevelStats> chunkLevelTable(const Heightfield& hf, const ChunkLayout& layout);

}  // namespace nestwalk::terrain
