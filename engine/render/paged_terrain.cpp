// View-bounded terrain (paged_terrain.h).
#include "nestwalk/render/paged_terrain.h"

#include "nestwalk/render/build_queue.h"
#include "nestwalk/render/chunk_node.h"

#include <osg/Geode>
#include <osg/Geometry>
#include <osg/Timer>
#include <osgUtil/CullVisitor>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>

namespace nestwalk {

using terrain::ChunkKey;

const char* terrainLoadingName(TerrainLoading l) {
  return l == TerrainLoading::Complete ? "complete" : "background";
}

std::optional<terrain::ChunkPyramidData> chunkPyramidDataFor(const terrain::TerrainPyramid* pyramid,
                                                             const ChunkKey& key, int fromLevel, double heightShift) {
  if (!pyramid || key.level < 1) return std::nullopt;
  terrain::ChunkPyramidData d = pyramid->chunkPyramidData(key, heightShift);
  if (key.level < fromLevel) {  // its level page and lows only: the errors are evaluated exactly
    d.error.clear();
    d.blocksX = d.blocksY = 0;
  }
  return d;
}

std::size_t defaultTerrainBudgetBytes() {
  constexpr std::size_t kMiB = std::size_t(1) << 20;
  const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGE_SIZE);
  const std::size_t physical = pages > 0 && pageSize > 0 ? std::size_t(pages) * std::size_t(pageSize) : 4096 * kMiB;
  return std::clamp(physical / 16, 256 * kMiB, 1024 * kMiB);
}

// A resident chunk: per quadrant (terrain_chunk.h) its surfaces, coarsest first: its own (simplified
// or grid), then at level 0 its refinements and its exact grid; each a node, its blocks' errors (m)
// and surface boxes, its error and triangles (skirts included). No surface: a quadrant without
// triangles.
struct PagedTerrain::Entry {
  struct Surface {
    osg::ref_ptr<osg::Node> node;
    std::vector<std::pair<float, osg::BoundingBox>> blocks;  // none for the exact grid (error 0)
    double error = 0;
    std::size_t triangles = 0;
  };
  struct Quadrant {
    std::vector<Surface> surfaces;
    std::size_t skirtTriangles = 0;  // on the chunk's own edges, drawn with every surface
    /// Its skirts on both midlines (ChunkQuadrant::midlineSkirts; null: none), drawn with it when a
    /// quadrant beside it is not drawn from this chunk. One node for both: a node costs some 1.5 KB
    /// beside its indices, and drawing the other midline's skirt too is what every quadrant did
    /// before they were split off.
    osg::ref_ptr<osg::Node> midlineSkirts;
    std::size_t midlineSkirtTriangles = 0;
    osg::BoundingBox box;  // everything any of its surfaces draws (skirts included), for frustum culling
    /// Every node: its surfaces' and its midline skirts'.
    std::vector<osg::Node*> nodes() const {
      std::vector<osg::Node*> all;
      for (const Surface& s : surfaces) all.push_back(s.node.get());
      if (midlineSkirts) all.push_back(midlineSkirts.get());
      return all;
    }
    std::vector<terrain::ChunkBlock> texelBlocks;  // its primary surface's blocks, for the imagery's texel choice
  };
  std::array<Quadrant, 4> quadrants;
  bool empty = true;     // no triangle at all (holes)
  osg::BoundingBox box;  // surface and skirts, for frustum culling
  std::size_t bytes = 0;
  std::uint64_t lastUsed = 0;
  int residentChildren = 0;
};

struct PagedTerrain::Built {
  ChunkKey key;
  Entry entry;
  double seconds = 0;
};

namespace {

/// Boxes are kept as floats, grown by this much so that they still hold what they bound: metres,
/// above float rounding of mesh-frame coordinates up to 16 km (1 mm), far below what it changes of a
/// distance.
constexpr double kBoxPaddingM = 2e-3;

osg::BoundingBox toBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  if (!(lo.x() <= hi.x())) return {};
  const Eigen::Vector3d a = lo.array() - kBoxPaddingM, b = hi.array() + kBoxPaddingM;
  return osg::BoundingBox(osg::Vec3(float(a.x()), float(a.y()), float(a.z())), osg::Vec3(float(b.x()), float(b.y()), float(b.z())));
}

/// The distance from p to the box (0 inside).
double distanceToBox(const osg::Vec3d& p, const osg::BoundingBox& b) {
  const double dx = std::max({double(b.xMin()) - p.x(), 0.0, p.x() - double(b.xMax())});
  const double dy = std::max({double(b.yMin()) - p.y(), 0.0, p.y() - double(b.yMax())});
  const double dz = std::max({double(b.zMin()) - p.z(), 0.0, p.z() - double(b.zMax())});
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

/// The mesh-frame box of the vertices an index range of the chunk draws (refinements draw a subset of
/// the exact grid's vertices and the same skirts).
osg::BoundingBox rangeBox(const terrain::ChunkMesh& m, std::size_t firstIndex, std::size_t indexCount) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(kInf), hi = Eigen::Vector3d::Constant(-kInf);
  for (std::size_t k = firstIndex; k < firstIndex + indexCount; ++k) {
    const std::uint32_t v = m.indices[k];
    const Eigen::Vector3d p = Eigen::Vector3d(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]) + m.offset;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return toBox(lo, hi);
}

std::vector<std::pair<float, osg::BoundingBox>> blocksOf(const std::vector<terrain::ChunkBlock>& blocks) {
  std::vector<std::pair<float, osg::BoundingBox>> out;
  for (const terrain::ChunkBlock& block : blocks)
    if (block.min.x() <= block.max.x() && block.error > 0) out.emplace_back(float(block.error), toBox(block.min, block.max));
  return out;
}

}  // namespace

PagedTerrain::PagedTerrain(std::shared_ptr<const terrain::Heightfield> heightfield, PagedTerrainOptions options)
    : hf_(std::move(heightfield)),
      options_(std::move(options)),
      layout_(hf_ ? hf_->cols() : 0, hf_ ? hf_->rows() : 0, options_.chunkCells) {
  if (!(options_.pixelsPerRadian > 0) || !(options_.maxPixels >= 0) || options_.loaderThreads < 0)
    throw std::invalid_argument("PagedTerrain: pixelsPerRadian must be positive, maxPixels and loaderThreads not negative");
  if (options_.pyramid && (options_.chunkCells != terrain::kPyramidTopCells ||
                           options_.pyramid->layout().cols != hf_->cols() || options_.pyramid->layout().rows != hf_->rows()))
    throw std::invalid_argument("PagedTerrain: the pyramid is not of the heightfield's grid and 64-cell chunks");
  budget_ = options_.budgetBytes > 0 ? options_.budgetBytes : defaultTerrainBudgetBytes();
  shading_.shade = options_.shade;
  if (options_.imagery) {
    // Called from every loader thread: one at a time (see "Ownership and threads").
    shading_.imagery = [reader = options_.imagery, reading = std::make_shared<std::mutex>()](
                           double x0, double y0, double sx, double sy, int width, int height) {
      const std::lock_guard lock(*reading);
      return reader(x0, y0, sx, sy, width, height);
    };
  }
  shading_.mapOrigin = options_.mapOrigin;
  if (const auto range = hf_->heightRange()) {
    shading_.heightLo = range->first;
    shading_.heightHi = range->second;
  }
  if (options_.imagery && options_.imageryPixelM > 0) {
    ImageryTilesOptions tiles;
    tiles.imagery = options_.imagery;
    tiles.imageryPixelM = options_.imageryPixelM;
    tiles.finestTexelM = options_.imageryFinestTexelM;
    tiles.mipmaps = options_.imageryMipmaps;
    tiles.mapOrigin = options_.mapOrigin;
    tiles.heightLo = shading_.heightLo;
    tiles.heightHi = shading_.heightHi;
    tiles.loading = options_.loading;
    tiles_ = std::make_unique<ImageryTiles>(hf_, layout_, std::move(tiles));
    shading_.baseColours = false;  // the tiles give the colour, the chunks the light
  }
  setCullingActive(false);  // the selection culls chunk by chunk
  setDataVariance(osg::Object::DYNAMIC);
  Built root = build(layout_.root());
  const osg::BoundingBox box = root.entry.box;
  if (box.valid()) bound_ = osg::BoundingSphere(box);
  insert(std::move(root));
  if (options_.loading == TerrainLoading::Background)
    loader_ = std::make_unique<BuildQueue<ChunkKey, Built>>([this](const ChunkKey& key) { return build(key); },
                                                            [](const ChunkKey& key) {
                                                              return "terrain chunk " + std::to_string(key.level) + "/" +
                                                                     std::to_string(key.x) + "/" + std::to_string(key.y);
                                                            },
                                                            options_.loaderThreads > 0 ? options_.loaderThreads
                                                                                       : builderWorkers(kMaxChunkLoaders),
                                                            [this](const Built& built, BuildQueue<ChunkKey, Built>::Shared& shared) {
                                                              followUp(built, shared);
                                                            });
}

PagedTerrain::~PagedTerrain() { loader_.reset(); }  // before the members its builds read

std::size_t PagedTerrain::chunkBudget() const {
  const std::size_t tiles = tiles_ ? tiles_->residentBytes() : 0;
  return budget_ > tiles ? budget_ - tiles : 0;
}

osg::BoundingSphere PagedTerrain::computeBound() const { return bound_; }

void PagedTerrain::resizeGLObjectBuffers(unsigned maxSize) {
  for (auto& [key, e] : cache_)
    for (auto& q : e.quadrants)
      for (osg::Node* n : q.nodes()) n->resizeGLObjectBuffers(maxSize);
}

void PagedTerrain::releaseGLObjects(osg::State* state) const {
  for (const auto& [key, e] : cache_)
    for (const auto& q : e.quadrants)
      for (osg::Node* n : q.nodes()) n->releaseGLObjects(state);
  if (tiles_) tiles_->releaseGLObjects(state);
}

PagedTerrain::Built PagedTerrain::build(const ChunkKey& key) const {
  const osg::Timer_t t0 = osg::Timer::instance()->tick();
  std::optional<terrain::ChunkPyramidData> gridErrors;
  if (!pyramidFailed_) {
    try {
      gridErrors = chunkPyramidDataFor(options_.pyramid.get(), key, options_.pyramidErrorsFromLevel,
                                       options_.pyramidHeightShift);
    } catch (const std::exception&) {
      pyramidFailed_ = true;  // computed from now on (exact errors: still within the rule, only slower)
    }
  }
  const terrain::ChunkMesh m = terrain::buildChunk(*hf_, layout_, key, shading_, options_.simplifyFraction,
                                                   gridErrors ? &*gridErrors : nullptr);
  Built b;
  b.key = key;
  if (!m.empty()) {
    const ChunkNodeMaker node = tiles_ ? ChunkNodeMaker(m, std::ldexp(layout_.chunkCells() * hf_->dx(), key.level),
                                                        std::ldexp(layout_.chunkCells() * hf_->dy(), key.level))
                                       : ChunkNodeMaker(m);
    for (std::size_t q = 0; q < 4; ++q) {
      const terrain::ChunkQuadrant& mq = m.quadrants[q];
      if (mq.empty()) continue;
      Entry::Quadrant& quad = b.entry.quadrants[q];
      const std::string name = " quadrant " + std::to_string(q);
      quad.skirtTriangles = mq.skirtTriangles;
      quad.box = rangeBox(m, mq.firstIndex, mq.indexCount);
      if (mq.exactIndexCount > 0) quad.box.expandBy(rangeBox(m, mq.exactFirstIndex, mq.exactIndexCount));
      std::vector<IndexRange> midlines;
      for (const terrain::ChunkSkirt& skirt : mq.midlineSkirts)
        if (skirt.indexCount > 0) {
          midlines.push_back({skirt.firstIndex, skirt.indexCount});
          quad.midlineSkirtTriangles += skirt.indexCount / 3;
          quad.box.expandBy(rangeBox(m, skirt.firstIndex, skirt.indexCount));
        }
      if (!midlines.empty()) quad.midlineSkirts = node(midlines, name + " midline skirts");
      if (tiles_) quad.texelBlocks = mq.blocks;
      quad.surfaces.push_back({node({{mq.firstIndex, mq.indexCount}}, name), blocksOf(mq.blocks), mq.maxError,
                               mq.surfaceTriangles + mq.skirtTriangles});
      for (std::size_t r = 0; r < mq.refinements.size(); ++r) {
        const terrain::ChunkRefinement& refined = mq.refinements[r];
        quad.surfaces.push_back({node({{refined.firstIndex, refined.indexCount}}, name + " refinement " + std::to_string(r)),
                                 blocksOf(refined.blocks), refined.maxError,
                                 refined.surfaceTriangles + mq.skirtTriangles});
      }
      if (mq.exactIndexCount > 0)
        quad.surfaces.push_back({node({{mq.exactFirstIndex, mq.exactIndexCount}}, name + " exact"), {}, 0.0,
                                 mq.exactSurfaceTriangles + mq.skirtTriangles});
    }
    b.entry.bytes = 2 * node.bytes();  // OSG's arrays and the GL's copy (see "Memory")
  }
  b.entry.empty = m.empty();
  b.entry.box = toBox(m.boxMin, m.boxMax);
  b.seconds = osg::Timer::instance()->delta_s(t0, osg::Timer::instance()->tick());
  return b;
}

void PagedTerrain::insert(Built&& built) {
  if (cache_.count(built.key)) return;
  built.entry.lastUsed = frame_;
  residentBytes_ += built.entry.bytes;
  ++stats_.chunksLoaded;
  stats_.loadSeconds += built.seconds;
  if (built.key.level + 1 < layout_.levels()) {
    const ChunkKey parent = terrain::parentOf(built.key);
    if (auto p = cache_.find(parent); p != cache_.end()) ++p->second.residentChildren;
  }
  cache_.emplace(built.key, std::move(built.entry));
}

void PagedTerrain::mergeLoaded() {
  // Coarser first (a parent before its children), up to the frame's bytes (at least one chunk); the
  // rest stay with the loader, which does not build them again.
  if (!loader_) return;
  std::vector<Built> merging;
  loader_->locked([&](BuildQueue<ChunkKey, Built>::Shared& shared) {
    std::vector<Built>& done = shared.done;
    std::stable_sort(done.begin(), done.end(), [](const Built& a, const Built& b) { return a.key.level > b.key.level; });
    std::size_t taken = 0, bytes = 0;
    for (; taken < done.size(); ++taken) {
      Built& b = done[taken];
      // A chunk whose parent went while it was loading cannot be reached: dropped (so is a copy). Its
      // parent may be merging with it (the loader's follow-ups).
      const ChunkKey parent = terrain::parentOf(b.key);
      const bool orphan = b.key.level + 1 < layout_.levels() && !cache_.count(parent) &&
                          std::none_of(merging.begin(), merging.end(), [&](const Built& m) { return m.key == parent; });
      if (orphan || cache_.count(b.key)) continue;
      if (bytes > 0 && bytes + b.entry.bytes > options_.mergeBytesPerFrame) break;
      bytes += b.entry.bytes;
      merging.push_back(std::move(b));
    }
    done.erase(done.begin(), done.begin() + std::ptrdiff_t(taken));
  });
  for (Built& b : merging) {
    ++stats_.chunksMerged;
    stats_.bytesMerged += b.entry.bytes;
    insert(std::move(b));
  }
}

std::size_t PagedTerrain::estimatedBytes(const ChunkKey& key) const {
  // A chunk not built yet costs about its parent's bytes (the chunks of one tree have about the
  // same number of vertices).
  const auto p = cache_.find(terrain::parentOf(key));
  return p != cache_.end() ? p->second.bytes : 0;
}

void PagedTerrain::sortByPriority(std::vector<Want>& wants) {
  std::stable_sort(wants.begin(), wants.end(), [](const Want& a, const Want& b) {
    return a.key.level != b.key.level ? a.key.level > b.key.level : a.priority > b.priority;
  });
}

double PagedTerrain::projectedPixels(const Entry& entry, std::size_t quadrant, std::size_t surface, const osg::Vec3d& eye,
                                     double pixelsPerRadian) {
  // The largest of its blocks' (terrain_chunk.h).
  double pixels = 0;
  for (const auto& [error, box] : entry.quadrants[quadrant].surfaces[surface].blocks)
    pixels = std::max(pixels, error * pixelsPerRadian / std::max(distanceToBox(eye, box), kMinEyeDistanceM));
  return pixels;
}

template <class Shared>
void PagedTerrain::followUp(const Built& built, Shared& shared) {
  LoaderView& view = loaderView_;
  if (!view.valid || !view.followUps || built.key.level == 0 || built.entry.empty) return;
  for (std::size_t q = 0; q < 4; ++q) {
    const Entry::Quadrant& quad = built.entry.quadrants[q];
    if (quad.surfaces.empty()) continue;
    osg::Polytope frustum = view.frustum;
    frustum.setupMask();
    // As select() would decide once the chunk is drawable: in view and over the rule (the imagery's
    // texel choice aside: the cull asks for what that adds).
    if (!frustum.contains(quad.box) || projectedPixels(built.entry, q, 0, view.eye, view.pixelsPerRadian) <= view.maxPixels)
      continue;
    const ChunkKey child{built.key.level - 1, 2 * built.key.x + int(q & 1), 2 * built.key.y + int(q >> 1)};
    if (shared.known(child) || std::find(shared.queue.begin(), shared.queue.end(), child) != shared.queue.end()) continue;
    if (built.entry.bytes > view.bytesLeft) return;  // a child costs about its parent (estimatedBytes)
    view.bytesLeft -= built.entry.bytes;
    // After every queued key of its level or coarser: coarser levels first, as the cull asks.
    const auto at = std::find_if(shared.queue.begin(), shared.queue.end(),
                                 [&](const ChunkKey& k) { return k.level < child.level; });
    shared.queue.insert(at, child);
  }
}

void PagedTerrain::select(const ChunkKey& key, osgUtil::CullVisitor& cv, std::vector<Want>& wants) {
  auto it = cache_.find(key);
  if (it == cache_.end()) return;
  Entry& e = it->second;
  e.lastUsed = frame_;
  if (e.empty) return;  // all holes, nothing below either
  if (cv.isCulled(e.box)) return;
  const osg::Vec3d eye = cv.getEyePoint();
  // What became of each quadrant, for the midline skirts (terrain_chunk.h, "Cracks"): drawn from
  // this chunk (its part in drawList_), out of view (nothing of it is seen, nor of a skirt on its
  // edge), or beside a gap a skirt must close (replaced by its child, or without triangles).
  enum class Fate { Drawn, OutOfView, Other };
  std::array<Fate, 4> fate{Fate::Other, Fate::Other, Fate::Other, Fate::Other};
  std::array<std::size_t, 4> partOf{};
  for (int q = 0; q < 4; ++q) {
    const Entry::Quadrant& quad = e.quadrants[std::size_t(q)];
    if (quad.surfaces.empty()) continue;
    // Out of view: neither drawn nor refined (its children are not asked for).
    if (cv.isCulled(quad.box)) {
      fate[std::size_t(q)] = Fate::OutOfView;
      continue;
    }
    auto projected = [&](std::size_t surface) {
      return projectedPixels(e, std::size_t(q), surface, eye, options_.pixelsPerRadian);
    };
    std::size_t drawn = 0;
    double pixels = projected(0);
    // Imagery tiles: the texel level the view asks for here; finer than the quadrant's own area's
    // tile holds, the child's geometry is drawn (a level-0 quadrant holds finer tiles itself).
    const int texelLevel =
        tiles_ ? tiles_->texelLevelFor(quad.texelBlocks, Eigen::Vector3d(eye.x(), eye.y(), eye.z()), options_.pixelsPerRadian,
                                       [&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) { return !cv.isCulled(toBox(lo, hi)); })
               : 0;
    const bool texelsFiner = tiles_ && texelLevel < key.level - 1;
    if ((pixels > options_.maxPixels || texelsFiner) && key.level > 0) {
      const ChunkKey child{key.level - 1, 2 * key.x + (q & 1), 2 * key.y + (q >> 1)};
      if (cache_.count(child)) {
        if (pixels <= options_.maxPixels) ++stats_.imageryRefinements;
        select(child, cv, wants);
        continue;
      }
      wants.push_back({child, pixels});
      ++stats_.standIns;
    }
    // Level 0 near the eye: the coarsest of its finer surfaces within the rule (the exact grid last).
    while (pixels > options_.maxPixels && drawn + 1 < quad.surfaces.size()) pixels = projected(++drawn);
    const Entry::Surface& surface = quad.surfaces[drawn];
    DrawnPart part;
    part.key = key;
    part.quadrant = q;
    part.node = surface.node.get();
    if (tiles_) {
      part.imageryTexelLevel = texelLevel;
      part.imageryWanted = ImageryTiles::wanted(key.level - 1, 2 * key.x + (q & 1), 2 * key.y + (q >> 1), texelLevel);
    }
    fate[std::size_t(q)] = Fate::Drawn;
    partOf[std::size_t(q)] = drawList_.size();
    drawList_.push_back(part);
    ++stats_.chunksDrawn;
    stats_.trianglesDrawn += surface.triangles;
    stats_.skirtTrianglesDrawn += quad.skirtTriangles;
    if (drawn > 0) (surface.error > 0 ? stats_.refinedTrianglesDrawn : stats_.exactTrianglesDrawn) += surface.triangles;
    if (surface.error > 0) {
      stats_.maxErrorM = std::max(stats_.maxErrorM, surface.error);
      stats_.maxErrorPx = std::max(stats_.maxErrorPx, pixels);
    }
    stats_.finestLevel = stats_.finestLevel < 0 ? key.level : std::min(stats_.finestLevel, key.level);
    stats_.coarsestLevel = std::max(stats_.coarsestLevel, key.level);
  }
  // A drawn quadrant's skirts on the midlines, where a quadrant across is neither drawn from this
  // chunk nor out of view.
  for (std::size_t q = 0; q < 4; ++q) {
    const Entry::Quadrant& quad = e.quadrants[q];
    auto across = [q](int k) { return std::size_t(terrain::quadrantAcrossMidline(int(q), k)); };
    if (fate[q] != Fate::Drawn || !quad.midlineSkirts || (fate[across(0)] != Fate::Other && fate[across(1)] != Fate::Other))
      continue;
    drawList_[partOf[q]].midlineSkirts = quad.midlineSkirts.get();
    stats_.trianglesDrawn += quad.midlineSkirtTriangles;
    stats_.skirtTrianglesDrawn += quad.midlineSkirtTriangles;
  }
}

void PagedTerrain::evictUnused(std::size_t target) {
  while (residentBytes_ > target) {
    // Oldest first among the unused leaves of the resident tree (finer first when as old).
    auto victim = cache_.end();
    for (auto it = cache_.begin(); it != cache_.end(); ++it) {
      const Entry& e = it->second;
      if (e.lastUsed >= frame_ || e.residentChildren > 0 || it->first == layout_.root()) continue;
      if (victim == cache_.end() || e.lastUsed < victim->second.lastUsed ||
          (e.lastUsed == victim->second.lastUsed && it->first.level < victim->first.level))
        victim = it;
    }
    if (victim == cache_.end()) return;
    const ChunkKey key = victim->first;
    for (const auto& q : victim->second.quadrants)
      for (osg::Node* n : q.nodes()) n->releaseGLObjects(nullptr);
    residentBytes_ -= victim->second.bytes;
    cache_.erase(victim);
    ++stats_.chunksEvicted;
    const ChunkKey parent = terrain::parentOf(key);
    if (auto p = cache_.find(parent); p != cache_.end()) --p->second.residentChildren;
  }
}

void PagedTerrain::publish(std::vector<Want> wants, const osg::Vec3d& eye, const osg::Polytope& frustum) {
  sortByPriority(wants);
  loader_->locked([&](BuildQueue<ChunkKey, Built>::Shared& shared) {
    // Only what fits, built chunks waiting to be merged included (they and the chunks being built
    // are not asked for again).
    std::size_t planned = residentBytes_ + (tiles_ ? tiles_->residentBytes() : 0);
    for (const Built& b : shared.done) planned += b.entry.bytes;
    // The follow-ups of chunks not merged yet: this cull could not ask for them, the loader's
    // follow-up did (for about the same view).
    std::vector<ChunkKey> followUps;
    for (const ChunkKey& k : shared.queue) {
      const ChunkKey parent = terrain::parentOf(k);
      const auto built = std::find_if(shared.done.begin(), shared.done.end(), [&](const Built& b) { return b.key == parent; });
      if (built != shared.done.end() && !cache_.count(parent)) {
        followUps.push_back(k);
        planned += built->entry.bytes;
      }
    }
    shared.queue.clear();
    for (const Want& w : wants) {
      if (shared.known(w.key)) continue;
      const std::size_t estimate = estimatedBytes(w.key);
      if (planned + estimate > budget_) break;
      planned += estimate;
      shared.queue.push_back(w.key);
    }
    shared.queue.insert(shared.queue.end(), followUps.begin(), followUps.end());
    std::stable_sort(shared.queue.begin(), shared.queue.end(),
                     [](const ChunkKey& a, const ChunkKey& b) { return a.level > b.level; });
    // Follow-ups only for a view standing still (or the first): a moving one's next cull asks anew,
    // and chunks for views already left would only crowd the cache.
    bool still = !loaderView_.valid || (eye - loaderView_.eye).length() <= kFollowUpStillEyeM;
    const osg::Polytope::PlaneList& planes = frustum.getPlaneList();
    const osg::Polytope::PlaneList& before = loaderView_.frustum.getPlaneList();
    if (loaderView_.valid) still = still && planes.size() == before.size();
    for (std::size_t k = 0; still && k < planes.size() && k < before.size(); ++k)
      still = (planes[k].getNormal() - before[k].getNormal()).length() <= kFollowUpStillTurnRad;
    loaderView_ = {true, still, eye, frustum, options_.pixelsPerRadian, options_.maxPixels,
                   budget_ > planned ? budget_ - planned : 0};
  });
}

std::string PagedTerrain::loadError() const {
  std::string error = loader_ ? loader_->error() : std::string();
  return error.empty() && tiles_ ? tiles_->loadError() : error;
}

void PagedTerrain::waitUntilIdle() {
  if (options_.loading != TerrainLoading::Background) return;
  if (tiles_) tiles_->waitUntilIdle();
  loader_->waitUntilIdle();
}

void PagedTerrain::traverse(osg::NodeVisitor& nv) {
  osgUtil::CullVisitor* cv = nv.asCullVisitor();
  if (!cv) return;
  ++frame_;
  stats_.chunksMerged = stats_.bytesMerged = 0;
  mergeLoaded();
  if (tiles_) tiles_->beginFrame();
  std::vector<Want> wants;
  for (;;) {
    const std::uint64_t loaded = stats_.chunksLoaded, evicted = stats_.chunksEvicted;
    const std::size_t merged = stats_.chunksMerged, bytesMerged = stats_.bytesMerged;
    const double loadSeconds = stats_.loadSeconds;
    stats_ = PagedTerrainStats{};
    stats_.chunksLoaded = loaded;
    stats_.chunksEvicted = evicted;
    stats_.chunksMerged = merged;
    stats_.bytesMerged = bytesMerged;
    stats_.loadSeconds = loadSeconds;
    drawList_.clear();
    wants.clear();
    select(layout_.root(), *cv, wants);
    if (options_.loading != TerrainLoading::Complete || wants.empty()) break;
    // Complete: build what fits (making room from what this selection did not touch), select again.
    sortByPriority(wants);
    bool any = false;
    for (const Want& w : wants) {
      if (cache_.count(w.key)) continue;
      const std::size_t estimate = estimatedBytes(w.key), budget = chunkBudget();
      if (residentBytes_ + estimate > budget && estimate <= budget) evictUnused(budget - estimate);
      if (residentBytes_ + estimate > budget) break;
      insert(build(w.key));
      any = true;
    }
    if (!any) break;
  }
  const std::size_t tileBudget = budget_ > residentBytes_ ? budget_ - residentBytes_ : 0;
  if (tiles_ && options_.loading == TerrainLoading::Complete) {
    std::vector<ImageryTileKey> wantedTiles;
    for (const DrawnPart& part : drawList_) wantedTiles.push_back(part.imageryWanted);
    tiles_->buildMissing(wantedTiles, tileBudget);
  }
  drawn_.clear();
  for (DrawnPart& part : drawList_) {
    osg::StateSet* imagery = nullptr;
    if (tiles_) {
      imagery = tiles_->stateFor(part.key, part.imageryWanted, part.imageryDrawn);
      stats_.finestTexelLevelDrawn = drawn_.empty() ? part.imageryDrawn.texelLevel
                                                    : std::min(stats_.finestTexelLevelDrawn, part.imageryDrawn.texelLevel);
      cv->pushStateSet(imagery);
    }
    drawn_.push_back(part);
    part.node->accept(nv);
    if (part.midlineSkirts) part.midlineSkirts->accept(nv);
    if (imagery) cv->popStateSet();
  }
  stats_.chunksWanted = wants.size();
  if (options_.loading == TerrainLoading::Background) {
    // The frustum as the cull tests it (none: it does not cull by it).
    const osg::CullingSet& culling = cv->getCurrentCullingSet();
    publish(wants, cv->getEyePoint(),
            (culling.getCullingMask() & osg::CullingSet::VIEW_FRUSTUM_CULLING) ? culling.getFrustum() : osg::Polytope());
  }
  if (tiles_) {
    tiles_->endFrame(tileBudget);
    stats_.imageryTilesResident = tiles_->stats().tilesResident;
    stats_.imageryBytes = tiles_->residentBytes();
    stats_.imageryTilesWanted = tiles_->stats().tilesWanted;
  }
  evictUnused(chunkBudget());
  stats_.chunksResident = cache_.size();
  stats_.residentBytes = residentBytes_ + stats_.imageryBytes;
}

}  // namespace nestwalk
