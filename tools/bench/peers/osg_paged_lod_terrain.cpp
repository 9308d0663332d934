// View-bounded terrain through osg::PagedLOD and osgDB::DatabasePager (paged_lod_terrain.h).
#include "tools/bench/peers/osg_paged_lod_terrain.h"

#include "nestwalk/render/chunk_node.h"

#include <osg/Geode>
#include <osg/Geometry>
#include <osg/MatrixTransform>
#include <osg/PagedLOD>
#include <osg/Timer>
#include <osg/observer_ptr>
#include <osgDB/DatabasePager>
#include <osgDB/FileNameUtils>
#include <osgDB/Options>
#include <osgDB/ReaderWriter>
#include <osgDB/Registry>
#include <osgUtil/CullVisitor>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>

namespace nestwalk::bench {

using terrain::ChunkKey;

namespace {

/// The pseudo-loader's file extension: "<level>_<x>_<y>.nwchunk" names a chunk's children.
constexpr const char* kChunkExtension = "nwchunk";
/// Boxes are kept as floats, grown by this much so that they still hold what they bound: metres
/// (paged_terrain.cpp's padding: above float rounding of mesh-frame coordinates up to 16 km).
constexpr double kBoxPaddingM = 2e-3;
/// waitUntilIdle() looks at the pager this often: seconds (a chunk takes milliseconds to build).
constexpr double kIdlePollSeconds = 0.0005;
/// The largest range a PagedLOD can hold (float): "everywhere".
constexpr float kEverywhere = std::numeric_limits<float>::max();

osg::BoundingBox toBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  if (!(lo.x() <= hi.x())) return {};
  const Eigen::Vector3d a = lo.array() - kBoxPaddingM, b = hi.array() + kBoxPaddingM;
  return osg::BoundingBox(osg::Vec3(float(a.x()), float(a.y()), float(a.z())),
                          osg::Vec3(float(b.x()), float(b.y()), float(b.z())));
}

/// The distance from p to the box (0 inside).
double distanceToBox(const osg::Vec3d& p, const osg::BoundingBox& b) {
  const double dx = std::max({double(b.xMin()) - p.x(), 0.0, p.x() - double(b.xMax())});
  const double dy = std::max({double(b.yMin()) - p.y(), 0.0, p.y() - double(b.yMax())});
  const double dz = std::max({double(b.zMin()) - p.z(), 0.0, p.z() - double(b.zMax())});
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

std::string chunkFileName(const ChunkKey& k) {
  return std::to_string(k.level) + "_" + std::to_string(k.x) + "_" + std::to_string(k.y) + "." + kChunkExtension;
}

}  // namespace

// The terrain's shared state: what the pseudo-loader builds from, the ranges' rule, and the
// statistics. Reached from the PagedLODs' database options (user data).
class PagedLodTerrain::Source : public osg::Referenced {
 public:
  Source(std::shared_ptr<const terrain::Heightfield> heightfield, const PagedTerrainOptions& o)
      : hf(std::move(heightfield)),
        layout(hf ? hf->cols() : 0, hf ? hf->rows() : 0, o.chunkCells),
        pixelsPerRadian(o.pixelsPerRadian),
        maxPixels(o.maxPixels),
        simplifyFraction(o.simplifyFraction) {
    shading.shade = o.shade;
    if (o.imagery) {
      // The pager may run several database threads (OSG_NUM_DATABASE_THREADS): one read at a time.
      auto mutex = std::make_shared<std::mutex>();
      shading.imagery = [mutex, read = o.imagery](double x0, double y0, double sx, double sy, int w, int h) {
        std::lock_guard lock(*mutex);
        return read(x0, y0, sx, sy, w, h);
      };
    }
    shading.mapOrigin = o.mapOrigin;
    if (const auto range = hf->heightRange()) {
      shading.heightLo = range->first;
      shading.heightHi = range->second;
    }
  }

  /// Database options that lead the pager to this terrain's loader (not cached by osgDB).
  osg::ref_ptr<osgDB::Options> makeOptions() const {
    osg::ref_ptr<osgDB::Options> options = new osgDB::Options;
    options->setObjectCacheHint(osgDB::Options::CACHE_NONE);
    options->setUserData(const_cast<Source*>(this));
    return options;
  }

  /// The chunk's PagedLOD (null for a chunk that is all holes); `bytes` its count (see the header).
  osg::ref_ptr<osg::Node> makeChunk(const ChunkKey& key, osgDB::Options* options, std::size_t* bytes = nullptr) const;

  /// The threshold between a chunk's two children: metres from its centre (see the header).
  float threshold(double maxError, double radius) const {
    if (!(maxPixels > 0)) return kEverywhere;
    return float(std::min(maxError * pixelsPerRadian.load() / maxPixels + radius, double(kEverywhere)));
  }

  std::shared_ptr<const terrain::Heightfield> hf;
  terrain::ChunkLayout layout;
  terrain::ChunkShading shading;
  std::atomic<double> pixelsPerRadian;  // set by the cull's thread, read by the pager's too
  double maxPixels, simplifyFraction;

  // The cull's figures for the frame in progress (cull thread only; the chunks' nodes add to them).
  mutable PagedLodTerrainStats frame;
  mutable std::vector<ChunkKey> drawn;
  osg::observer_ptr<osgDB::DatabasePager> pager;

  // Since the node was made (pager thread and cull thread).
  mutable std::atomic<std::size_t> residentChunks{0}, residentBytes{0};
  mutable std::atomic<std::uint64_t> loaded{0}, loadNanos{0};
};

namespace {

using Source = PagedLodTerrain::Source;

/// What replaces a chunk's mesh near the eye: nothing (level 0 exact, or no error), its children
/// (the file child, paged), or level 0's exact grid (terrain_chunk.h's simplification; in memory).
enum class Finer { None, Children, ExactGrid };

// A chunk's PagedLOD: keeps its two ranges on the rule (the pixels per radian may change), counts
// itself wanted when its children are in range and not loaded, and counts itself resident.
class ChunkLod : public osg::PagedLOD {
 public:
  ChunkLod(const Source* source, double maxError, double radius, std::size_t bytes, Finer finer)
      : source_(source), maxError_(maxError), radius_(radius), bytes_(bytes), finer_(finer) {
    source_->residentChunks += 1;
    source_->residentBytes += bytes_;
  }
  ~ChunkLod() override {
    source_->residentChunks -= 1;
    source_->residentBytes -= bytes_;
  }

  void traverse(osg::NodeVisitor& nv) override {
    if (finer_ != Finer::None && nv.getVisitorType() == osg::NodeVisitor::CULL_VISITOR) {
      const float split = source_->threshold(maxError_, radius_);
      if (_rangeList[0].first != split) {
        setRange(0, split, kEverywhere);
        setRange(1, 0.0f, split);
      }
      if (getNumChildren() < 2 && nv.getDistanceToViewPoint(getCenter(), true) < split)
        ++source_->frame.chunksWanted;
    }
    osg::PagedLOD::traverse(nv);
  }

 private:
  osg::ref_ptr<const Source> source_;
  double maxError_, radius_;
  std::size_t bytes_;
  Finer finer_;
};

// On a chunk's mesh node: the cull reached it inside the frustum, so the chunk is drawn. Records it
// with its triangles and errors (the projected one by PagedTerrain's block measure).
class DrawnChunk : public osg::NodeCallback {
 public:
  /// The mesh's primary surface (exact = false: its errors and blocks) or level 0's exact grid
  /// (error 0).
  DrawnChunk(const Source* source, const terrain::ChunkMesh& m, std::size_t triangles, std::size_t skirtTriangles,
             bool exact)
      : source_(source), key_(m.key), offset_(m.offset.x(), m.offset.y(), m.offset.z()),
        maxError_(exact ? 0.0 : m.maxError), triangles_(triangles), skirtTriangles_(skirtTriangles) {
    if (exact) return;
    for (const terrain::ChunkQuadrant& q : m.quadrants)
      for (const terrain::ChunkBlock& b : q.blocks)
        if (b.min.x() <= b.max.x() && b.error > 0) blocks_.emplace_back(float(b.error), toBox(b.min, b.max));
  }

  void operator()(osg::Node* node, osg::NodeVisitor* nv) override {
    if (osgUtil::CullVisitor* cv = nv->asCullVisitor()) {
      const Source& s = *source_;
      // Inside the chunk's transform: the eye in the chunk's frame, back to the mesh frame.
      const osg::Vec3d eye = osg::Vec3d(cv->getEyeLocal()) + offset_;
      const double ppr = s.pixelsPerRadian.load();
      double pixels = 0;
      for (const auto& [error, box] : blocks_)
        pixels = std::max(pixels, error * ppr / std::max(distanceToBox(eye, box), kMinEyeDistanceM));
      PagedLodTerrainStats& f = s.frame;
      ++f.chunksDrawn;
      f.trianglesDrawn += triangles_;
      f.skirtTrianglesDrawn += skirtTriangles_;
      f.maxErrorM = std::max(f.maxErrorM, maxError_);
      f.maxErrorPx = std::max(f.maxErrorPx, pixels);
      f.finestLevel = f.finestLevel < 0 ? key_.level : std::min(f.finestLevel, key_.level);
      f.coarsestLevel = std::max(f.coarsestLevel, key_.level);
      s.drawn.push_back(key_);
    }
    traverse(node, nv);
  }

 private:
  osg::ref_ptr<const Source> source_;
  ChunkKey key_;
  osg::Vec3d offset_;
  double maxError_;
  std::size_t triangles_, skirtTriangles_;
  std::vector<std::pair<float, osg::BoundingBox>> blocks_;  // mesh frame
};

// The pseudo-loader: "<level>_<x>_<y>.nwchunk" is the Group of that chunk's children's PagedLODs,
// built from the Source in the options' user data. Nothing is read from disk.
class ChunkChildrenLoader : public osgDB::ReaderWriter {
 public:
  ChunkChildrenLoader() { supportsExtension(kChunkExtension, "nestwalk terrain chunk children (pseudo-loader)"); }
  const char* className() const override { return "nestwalk terrain chunk pseudo-loader"; }

  ReadResult readNode(const std::string& file, const osgDB::Options* options) const override {
    if (!acceptsExtension(osgDB::getLowerCaseFileExtension(file))) return ReadResult::FILE_NOT_HANDLED;
    const Source* source = options ? dynamic_cast<const Source*>(options->getUserData()) : nullptr;
    if (!source) return ReadResult::FILE_NOT_HANDLED;  // not one of ours (no terrain to build from)
    ChunkKey key;
    char tail = 0;
    const std::string name = osgDB::getNameLessExtension(osgDB::getSimpleFileName(file));
    if (std::sscanf(name.c_str(), "%d_%d_%d%c", &key.level, &key.x, &key.y, &tail) != 3 || key.level < 1 ||
        !source->layout.exists(key))
      return ReadResult(file + ": not a terrain chunk of this layout");
    try {
      osg::ref_ptr<osgDB::Options> childOptions = source->makeOptions();
      osg::ref_ptr<osg::Group> group = new osg::Group;
      group->setName("children of " + name);
      for (const ChunkKey& child : source->layout.children(key))
        if (osg::ref_ptr<osg::Node> node = source->makeChunk(child, childOptions.get())) group->addChild(node.get());
      return ReadResult(group.get());
    } catch (const std::exception& e) {  // out of memory: the parent stays drawn
      return ReadResult(file + ": " + e.what());
    }
  }
};

}  // namespace

osg::ref_ptr<osg::Node> PagedLodTerrain::Source::makeChunk(const ChunkKey& key, osgDB::Options* options,
                                                            std::size_t* bytes) const {
  const osg::Timer_t t0 = osg::Timer::instance()->tick();
  const terrain::ChunkMesh m = terrain::buildChunk(*hf, layout, key, shading, simplifyFraction);
  osg::ref_ptr<ChunkLod> lod;
  if (bytes) *bytes = 0;  // a chunk without triangles holds nothing
  if (!m.empty()) {
    // The primary surface: every quadrant's range (surface and skirts; a midline's skirt only beside
    // a quadrant without triangles, as the own quadtree draws them); level 0 simplified also has
    // its exact grid (each simplified quadrant's exact range, the others' own).
    std::vector<IndexRange> primary, exact, midlineSkirts;
    std::size_t primaryTriangles = 0, exactTriangles = 0, midlineSkirtTriangles = 0;
    bool simplified = false;
    for (std::size_t i = 0; i < 4; ++i) {
      const terrain::ChunkQuadrant& q = m.quadrants[i];
      if (q.empty()) continue;
      for (std::size_t k = 0; k < 2; ++k)
        if (m.quadrants[std::size_t(terrain::quadrantAcrossMidline(int(i), int(k)))].empty() && q.midlineSkirts[k].indexCount > 0) {
          midlineSkirts.push_back({q.midlineSkirts[k].firstIndex, q.midlineSkirts[k].indexCount});
          midlineSkirtTriangles += q.midlineSkirts[k].indexCount / 3;
        }
      primary.push_back({q.firstIndex, q.indexCount});
      primaryTriangles += q.surfaceTriangles + q.skirtTriangles;
      if (q.exactIndexCount > 0) {
        simplified = true;
        exact.push_back({q.exactFirstIndex, q.exactIndexCount});
        exactTriangles += q.exactSurfaceTriangles + q.skirtTriangles;
      } else {
        exact.push_back({q.firstIndex, q.indexCount});
        exactTriangles += q.surfaceTriangles + q.skirtTriangles;
      }
    }
    primary.insert(primary.end(), midlineSkirts.begin(), midlineSkirts.end());
    exact.insert(exact.end(), midlineSkirts.begin(), midlineSkirts.end());
    primaryTriangles += midlineSkirtTriangles;
    exactTriangles += midlineSkirtTriangles;
    const Finer finer = !(m.maxError > 0) ? Finer::None
                        : key.level > 0   ? Finer::Children
                        : simplified      ? Finer::ExactGrid
                                          : Finer::None;
    const osg::BoundingBox box = toBox(m.boxMin, m.boxMax);
    const ChunkNodeMaker node(m);  // the mesh and the exact grid share the arrays
    osg::ref_ptr<osg::MatrixTransform> mesh = node(primary, " mesh");
    osg::ref_ptr<osg::MatrixTransform> grid = finer == Finer::ExactGrid ? node(exact, " exact grid") : nullptr;
    const std::size_t counted = 2 * node.bytes();  // as the own quadtree counts a chunk (paged_terrain.h)
    if (bytes) *bytes = counted;
    lod = new ChunkLod(this, m.maxError, box.radius(), counted, finer);
    lod->setName("chunk lod " + std::to_string(key.level) + "/" + std::to_string(key.x) + "/" + std::to_string(key.y));
    lod->setRangeMode(osg::LOD::DISTANCE_FROM_EYE_POINT);
    // The centre stays the box's (the rule measures from it); the bound grows with the loaded
    // children (finer levels can reach above the coarse box).
    lod->setCenterMode(osg::LOD::UNION_OF_BOUNDING_SPHERE_AND_USER_DEFINED);
    lod->setCenter(box.center());
    lod->setRadius(box.radius());
    mesh->setCullCallback(new DrawnChunk(this, m, primaryTriangles, m.skirtTriangles + midlineSkirtTriangles, false));
    const float split = threshold(m.maxError, box.radius());
    switch (finer) {
      case Finer::None:
        lod->addChild(mesh.get(), 0.0f, kEverywhere);
        break;
      case Finer::Children:
        lod->addChild(mesh.get(), split, kEverywhere);
        lod->setFileName(1, chunkFileName(key));
        lod->setRange(1, 0.0f, split);
        lod->setDatabaseOptions(options);
        break;
      case Finer::ExactGrid: {
        lod->addChild(mesh.get(), split, kEverywhere);
        grid->setCullCallback(new DrawnChunk(this, m, exactTriangles, m.skirtTriangles + midlineSkirtTriangles, true));
        lod->addChild(grid.get(), 0.0f, split);
        break;
      }
    }
    lod->setNumChildrenThatCannotBeExpired(finer == Finer::Children ? 1 : 2);  // only the children page
  }
  loaded += 1;
  loadNanos += std::uint64_t(osg::Timer::instance()->delta_n(t0, osg::Timer::instance()->tick()));
  return lod;
}

PagedLodTerrain::PagedLodTerrain(std::shared_ptr<const terrain::Heightfield> heightfield,
                                 PagedTerrainOptions options) {
  if (!heightfield) throw std::invalid_argument("PagedLodTerrain: no heightfield");
  if (!(options.pixelsPerRadian > 0) || !(options.maxPixels >= 0))
    throw std::invalid_argument("PagedLodTerrain: pixelsPerRadian must be positive and maxPixels not negative");
  static const bool registered = [] {
    osgDB::Registry::instance()->addReaderWriter(new ChunkChildrenLoader);
    return true;
  }();
  (void)registered;
  source_ = new Source(std::move(heightfield), options);
  budget_ = options.budgetBytes > 0 ? options.budgetBytes : defaultTerrainBudgetBytes();
  std::size_t rootBytes = 0;
  const osg::ref_ptr<osgDB::Options> rootOptions = source_->makeOptions();
  if (osg::ref_ptr<osg::Node> root = source_->makeChunk(source_->layout.root(), rootOptions.get(), &rootBytes))
    addChild(root.get());
  maxPagedLods_ = unsigned(std::clamp<std::size_t>(budget_ / std::max<std::size_t>(rootBytes, 1), 1,
                                                   std::numeric_limits<unsigned>::max()));
}

PagedLodTerrain::~PagedLodTerrain() = default;

const terrain::ChunkLayout& PagedLodTerrain::layout() const { return source_->layout; }

void PagedLodTerrain::setPixelsPerRadian(double pixelsPerRadian) {
  if (pixelsPerRadian > 0) source_->pixelsPerRadian = pixelsPerRadian;
}

void PagedLodTerrain::traverse(osg::NodeVisitor& nv) {
  osgUtil::CullVisitor* cv = nv.asCullVisitor();
  if (!cv) {
    osg::Group::traverse(nv);
    return;
  }
  Source& s = *source_;
  if (auto* pager = dynamic_cast<osgDB::DatabasePager*>(cv->getDatabaseRequestHandler()); pager && s.pager != pager) {
    s.pager = pager;
    pager->setTargetMaximumNumberOfPageLOD(maxPagedLods_);
  }
  s.frame = PagedLodTerrainStats{};
  s.drawn.clear();
  osg::Group::traverse(nv);
  stats_ = s.frame;
  stats_.chunksResident = s.residentChunks.load();
  stats_.residentBytes = s.residentBytes.load();
  stats_.chunksLoaded = s.loaded.load();
  stats_.loadSeconds = double(s.loadNanos.load()) * 1e-9;
  drawn_ = s.drawn;
}

PagedTerrainStats PagedLodTerrain::frameStats() const {
  PagedTerrainStats p;
  p.chunksDrawn = stats_.chunksDrawn;
  p.trianglesDrawn = stats_.trianglesDrawn;
  p.skirtTrianglesDrawn = stats_.skirtTrianglesDrawn;
  p.maxErrorM = stats_.maxErrorM;
  p.maxErrorPx = stats_.maxErrorPx;
  p.standIns = stats_.chunksWanted;
  p.chunksResident = stats_.chunksResident;
  p.residentBytes = stats_.residentBytes;
  p.chunksWanted = stats_.chunksWanted;
  p.chunksLoaded = stats_.chunksLoaded;
  p.loadSeconds = stats_.loadSeconds;
  p.finestLevel = stats_.finestLevel;
  p.coarsestLevel = stats_.coarsestLevel;
  return p;
}

bool PagedLodTerrain::waitUntilIdle(double maxSeconds) const {
  osg::ref_ptr<osgDB::DatabasePager> pager;
  if (!source_->pager.lock(pager)) return true;
  const osg::Timer_t t0 = osg::Timer::instance()->tick();
  for (;;) {
    // A database thread is active from before it takes a request until it has queued the result,
    // so an empty queue and no active thread mean everything asked for waits to be merged.
    bool busy = pager->getFileRequestListSize() > 0 || pager->getDataToCompileListSize() > 0;
    for (unsigned i = 0; !busy && i < pager->getNumDatabaseThreads(); ++i)
      busy = pager->getDatabaseThread(i)->getActive();
    if (!busy) return true;
    if (osg::Timer::instance()->delta_s(t0, osg::Timer::instance()->tick()) > maxSeconds) return false;
    std::this_thread::sleep_for(std::chrono::duration<double>(kIdlePollSeconds));
  }
}

TerrainNodeMaker osgPagedLodMaker(osg::ref_ptr<PagedLodTerrain>* made) {
  return [made](std::shared_ptr<const terrain::Heightfield> heightfield, const PagedTerrainOptions& options) {
    osg::ref_ptr<PagedLodTerrain> terrain = new PagedLodTerrain(std::move(heightfield), options);
    if (made) *made = terrain;
    return osg::ref_ptr<TerrainNode>(terrain.get());
  };
}

}  // namespace nestwalk::bench
