// Imagery at its own resolution (imagery_tiles.h).
#include "nestwalk/render/imagery_tiles.h"

#include "nestwalk/render/build_queue.h"
#include "nestwalk/render/paged_terrain.h"

#include <osg/Image>
#include <osg/TexMat>
#include <osg/Texture2D>
#include <osg/Timer>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

namespace nestwalk {

struct ImageryTiles::Tile {
  osg::ref_ptr<osg::Texture2D> texture;
  std::size_t bytes = 0;
  std::uint64_t lastUsed = 0;
  /// The states drawing chunks with it (the texture and the chunk's texture matrix), and the frame
  /// each was last used in: made once while a chunk keeps being drawn with the tile.
  std::unordered_map<terrain::ChunkKey, std::pair<osg::ref_ptr<osg::StateSet>, std::uint64_t>, terrain::ChunkKeyHash>
      states;
};

struct ImageryTiles::Built {
  ImageryTileKey key;
  Tile tile;
  double seconds = 0;
};

namespace {

/// Levels between a quadrant's area and its finest texels: kMaxImageryTileTexels / kImageryTileTexels = 2^4.
constexpr int kMaxTexelLevelsBelowArea = 4;

/// The distance from p to the box [lo, hi] (0 inside).
double distanceToBox(const Eigen::Vector3d& p, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  return (p.cwiseMax(lo).cwiseMin(hi) - p).norm();
}

}  // namespace

ImageryTiles::ImageryTiles(std::shared_ptr<const terrain::Heightfield> heightfield, const terrain::ChunkLayout& layout,
                           ImageryTilesOptions options)
    : hf_(std::move(heightfield)), layout_(layout), options_(std::move(options)) {
  if (!options_.imagery) throw std::invalid_argument("ImageryTiles: no imagery reader");
  if (!(options_.imageryPixelM > 0) || !(options_.finestTexelM >= 0))
    throw std::invalid_argument("ImageryTiles: the imagery's pixel size must be positive");
  top_ = layout_.levels() - 1;
  // The finest level: the coarsest whose texel is at most the imagery's pixel (with the slack),
  // within what a quadrant holds.
  const double pixel = std::max(options_.imageryPixelM, options_.finestTexelM) * kFinestTexelSlack;
  const double level = std::floor(std::log2(pixel * kImageryTileTexels / (layout_.chunkCells() * hf_->dx())));
  finest_ = int(std::clamp(level, double(-1 - kMaxTexelLevelsBelowArea), double(top_)));
  insert(build({top_, 0, 0, top_}));
  if (options_.loading == TerrainLoading::Background)
    loader_ = std::make_unique<BuildQueue<ImageryTileKey, Built>>(
        [this](const ImageryTileKey& key) { return build(key); },
        [](const ImageryTileKey& key) {
          return "imagery tile " + std::to_string(key.areaLevel) + "/" + std::to_string(key.x) + "/" +
                 std::to_string(key.y) + " at texel level " + std::to_string(key.texelLevel);
        });
}

ImageryTiles::~ImageryTiles() { loader_.reset(); }  // before the members its builds read

double ImageryTiles::texelSize(int texelLevel) const {
  return std::ldexp(layout_.chunkCells() * hf_->dx(), texelLevel) / kImageryTileTexels;
}

int ImageryTiles::texelLevelFor(const std::vector<terrain::ChunkBlock>& blocks, const Eigen::Vector3d& eye,
                                double pixelsPerRadian, const BoxInView& inView) const {
  // The finest footprint of a pixel over the blocks: metres along the screen's coarser axis.
  double footprint = std::numeric_limits<double>::infinity();
  for (const terrain::ChunkBlock& b : blocks) {
    if (!(b.min.x() <= b.max.x()) || (inView && !inView(b.min, b.max))) continue;
    const Eigen::Vector3d nearest = eye.cwiseMax(b.min).cwiseMin(b.max);
    const double d = std::max(distanceToBox(eye, b.min, b.max), kMinEyeDistanceM);
    // The view's direction there: towards the box's nearest point at the block's middle height (its
    // top or bottom would tilt a grazing view by the box's height).
    const Eigen::Vector3d ray = Eigen::Vector3d(nearest.x(), nearest.y(), 0.5 * (b.min.z() + b.max.z())) - eye;
    const double length = b.normalSum.norm() * ray.norm();
    const double c = d <= kMinEyeDistanceM || !(length > 0)
                         ? 1.0
                         : std::max(kMinImageryCosine, std::abs(ray.dot(b.normalSum)) / length);
    footprint = std::min(footprint, d / (pixelsPerRadian * c));
  }
  if (!std::isfinite(footprint)) return top_;
  const double spacing = std::max(hf_->dx(), hf_->dy());
  const double level = std::floor(std::log2(footprint * kImageryTileTexels / (layout_.chunkCells() * spacing)));
  return int(std::clamp(level, double(finest_), double(top_)));
}

ImageryTileKey ImageryTiles::wanted(int areaLevel, int x, int y, int texelLevel) {
  if (texelLevel >= areaLevel) {
    const int shift = texelLevel - areaLevel;
    return {texelLevel, x >> shift, y >> shift, texelLevel};
  }
  // Finer texels than the area's own: only a quadrant's area holds them (a coarser part refines its
  // geometry instead, paged_terrain.h).
  if (areaLevel >= 0) return {areaLevel, x, y, areaLevel};
  return {areaLevel, x, y, std::max(texelLevel, areaLevel - kMaxTexelLevelsBelowArea)};
}

std::size_t ImageryTiles::tileBytes(const ImageryTileKey& key) const {
  std::size_t side = std::size_t(kImageryTileTexels) << (key.areaLevel - key.texelLevel), bytes = 4 * side * side;
  if (options_.mipmaps)
    while (side > 1) side /= 2, bytes += 4 * side * side;
  return bytes;
}

ImageryTiles::Built ImageryTiles::build(const ImageryTileKey& key) const {
  const osg::Timer_t t0 = osg::Timer::instance()->tick();
  const int side = kImageryTileTexels << (key.areaLevel - key.texelLevel);
  const double spanX = std::ldexp(layout_.chunkCells() * hf_->dx(), key.areaLevel);
  const double spanY = std::ldexp(layout_.chunkCells() * hf_->dy(), key.areaLevel);
  const double texelX = spanX / side, texelY = spanY / side;
  // The area's north-west corner in the map frame; texel centres half a texel in.
  const double x0 = options_.mapOrigin.x() + key.x * spanX + 0.5 * texelX;
  const double y0 = options_.mapOrigin.y() - key.y * spanY - 0.5 * texelY;
  std::vector<std::uint8_t> rgba = options_.imagery(x0, y0, texelX, texelY, side, side);
  const std::size_t texels = std::size_t(side) * std::size_t(side);
  if (rgba.size() != 4 * texels) rgba.assign(4 * texels, 0);  // unreadable: the height ramp throughout
  // Holes: the imagery over the height ramp by its alpha.
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i) {
      std::uint8_t* p = &rgba[4 * (std::size_t(j) * std::size_t(side) + std::size_t(i))];
      if (p[3] == 255) continue;
      const std::optional<double> h = hf_->groundHeight(x0 + i * texelX, y0 - j * texelY);
      const Eigen::Vector3d ramp =
          h ? terrain::terrainRampColour(*h, options_.heightLo, options_.heightHi) : Eigen::Vector3d::Zero();
      const double a = p[3] / 255.0;
      for (int k = 0; k < 3; ++k) p[k] = std::uint8_t(std::lround(a * p[k] + (1 - a) * 255.0 * ramp[k]));
      p[3] = 255;
    }
  // The image's one buffer (tileBytes): the tile's texels, then its mip levels (see "Filtering"
  // above), each texel the mean of the four under it, down to 1 x 1.
  auto* data = new unsigned char[tileBytes(key)];
  std::copy(rgba.begin(), rgba.end(), data);
  rgba = {};
  osg::Image::MipmapDataType offsets;
  if (options_.mipmaps) {
    std::size_t at = 0;
    for (int s = side; s > 1; s /= 2) {
      const int h = s / 2;
      const std::size_t next = at + 4 * std::size_t(s) * std::size_t(s);
      offsets.push_back(unsigned(next));
      const unsigned char* above = data + at;
      unsigned char* level = data + next;
      for (int j = 0; j < h; ++j)
        for (int i = 0; i < h; ++i)
          for (int k = 0; k < 4; ++k) {
            auto texel = [&](int x, int y) { return unsigned(above[4 * (std::size_t(y) * std::size_t(s) + std::size_t(x)) + std::size_t(k)]); };
            level[4 * (std::size_t(j) * std::size_t(h) + std::size_t(i)) + std::size_t(k)] =
                static_cast<unsigned char>((texel(2 * i, 2 * j) + texel(2 * i + 1, 2 * j) + texel(2 * i, 2 * j + 1) + texel(2 * i + 1, 2 * j + 1) + 2) / 4);
          }
      at = next;
    }
  }
  osg::ref_ptr<osg::Image> image = new osg::Image;
  image->setImage(side, side, 1, GL_RGBA, GL_RGBA, GL_UNSIGNED_BYTE, data, osg::Image::USE_NEW_DELETE);
  if (!offsets.empty()) image->setMipmapLevels(offsets);
  Built b;
  b.key = key;
  b.tile.texture = new osg::Texture2D(image.get());
  osg::Texture2D& t = *b.tile.texture;
  t.setResizeNonPowerOfTwoHint(false);
  t.setWrap(osg::Texture::WRAP_S, osg::Texture::CLAMP_TO_EDGE);
  t.setWrap(osg::Texture::WRAP_T, osg::Texture::CLAMP_TO_EDGE);
  t.setFilter(osg::Texture::MAG_FILTER, osg::Texture::LINEAR);
  t.setFilter(osg::Texture::MIN_FILTER, options_.mipmaps ? osg::Texture::LINEAR_MIPMAP_LINEAR : osg::Texture::LINEAR);
  t.setUseHardwareMipMapGeneration(false);  // the levels are the image's
  // The GL's copy is the one kept: OSG lets go of the image once it is uploaded (one context draws
  // a tile; a tile evicted and wanted again is read again).
  t.setUnRefImageDataAfterApply(true);
  b.tile.bytes = tileBytes(key);
  b.seconds = osg::Timer::instance()->delta_s(t0, osg::Timer::instance()->tick());
  return b;
}

void ImageryTiles::insert(Built&& b) {
  if (tiles_.count(b.key)) return;
  b.tile.lastUsed = frame_;
  residentBytes_ += b.tile.bytes;
  ++stats_.tilesLoaded;
  stats_.loadSeconds += b.seconds;
  tiles_.emplace(b.key, std::move(b.tile));
}

void ImageryTiles::beginFrame() {
  ++frame_;
  missing_.clear();
  if (!loader_) return;
  std::vector<Built> merging;
  loader_->locked([&](BuildQueue<ImageryTileKey, Built>::Shared& shared) {
    std::vector<Built>& done = shared.done;
    std::stable_sort(done.begin(), done.end(),
                     [](const Built& a, const Built& b) { return a.key.texelLevel > b.key.texelLevel; });
    std::size_t taken = 0, bytes = 0;
    for (; taken < done.size(); ++taken) {
      if (bytes > 0 && bytes + done[taken].tile.bytes > kChunkMergeBytesPerFrame) break;
      bytes += done[taken].tile.bytes;
      merging.push_back(std::move(done[taken]));
    }
    done.erase(done.begin(), done.begin() + std::ptrdiff_t(taken));
  });
  for (Built& b : merging) insert(std::move(b));
}

osg::StateSet* ImageryTiles::stateFor(const terrain::ChunkKey& chunk, const ImageryTileKey& wanted,
                                                   ImageryTileKey& drawn) {
  ImageryTileKey k = wanted;
  auto it = tiles_.find(k);
  if (it == tiles_.end()) {
    missing_.push_back(wanted);
    while (it == tiles_.end() && k.areaLevel < top_) {
      k = k.texelLevel < k.areaLevel ? ImageryTileKey{k.areaLevel, k.x, k.y, k.texelLevel + 1}
                                     : ImageryTileKey{k.areaLevel + 1, k.x >> 1, k.y >> 1, k.areaLevel + 1};
      it = tiles_.find(k);
    }
    if (it == tiles_.end()) it = tiles_.find(k = ImageryTileKey{top_, 0, 0, top_});
  }
  drawn = k;
  Tile& tile = it->second;
  tile.lastUsed = frame_;
  auto& [state, used] = tile.states[chunk];
  used = frame_;
  if (!state) {
    // The chunk's imagery coordinates (chunk_node.h: its area from 0 to 1) onto the tile's: the
    // chunk's area is 2^(level - areaLevel) tile areas across.
    const double ratio = std::ldexp(1.0, chunk.level - k.areaLevel);
    state = new osg::StateSet;
    state->setTextureAttributeAndModes(0, tile.texture.get(), osg::StateAttribute::ON);
    state->setTextureAttribute(0, new osg::TexMat(osg::Matrixd::scale(ratio, ratio, 1) *
                                                  osg::Matrixd::translate(chunk.x * ratio - k.x, chunk.y * ratio - k.y, 0)));
  }
  return state.get();
}

void ImageryTiles::buildMissing(const std::vector<ImageryTileKey>& wanted, std::size_t budgetLeft) {
  for (const ImageryTileKey& key : wanted) {
    if (tiles_.count(key)) {
      tiles_[key].lastUsed = frame_;
      continue;
    }
    const std::size_t bytes = tileBytes(key);
    if (residentBytes_ + bytes > budgetLeft && bytes <= budgetLeft) evictUnused(budgetLeft - bytes);
    if (residentBytes_ + bytes > budgetLeft) continue;
    Built b = build(key);
    insert(std::move(b));
  }
}

void ImageryTiles::endFrame(std::size_t budgetLeft) {
  stats_.tilesWanted = missing_.size();
  if (loader_) {
    std::vector<ImageryTileKey> wants = missing_;
    std::stable_sort(wants.begin(), wants.end(),
                     [](const ImageryTileKey& a, const ImageryTileKey& b) { return a.texelLevel > b.texelLevel; });
    loader_->locked([&](BuildQueue<ImageryTileKey, Built>::Shared& shared) {
      std::size_t planned = residentBytes_;
      for (const Built& b : shared.done) planned += b.tile.bytes;
      shared.queue.clear();
      for (const ImageryTileKey& key : wants) {
        if (shared.known(key) || std::find(shared.queue.begin(), shared.queue.end(), key) != shared.queue.end()) continue;
        if (planned + tileBytes(key) > budgetLeft) break;
        planned += tileBytes(key);
        shared.queue.push_back(key);
      }
    });
  }
  // The states of chunks this frame did not draw with a tile go (a chunk drawn again makes its own).
  for (auto& [key, tile] : tiles_)
    for (auto s = tile.states.begin(); s != tile.states.end();)
      s = s->second.second < frame_ ? tile.states.erase(s) : std::next(s);
  evictUnused(budgetLeft);
  stats_.tilesResident = tiles_.size();
  stats_.residentBytes = residentBytes_;
}

void ImageryTiles::evictUnused(std::size_t target) {
  while (residentBytes_ > target) {
    auto victim = tiles_.end();
    for (auto it = tiles_.begin(); it != tiles_.end(); ++it) {
      if (it->second.lastUsed >= frame_ || it->first.areaLevel == top_) continue;
      if (victim == tiles_.end() || it->second.lastUsed < victim->second.lastUsed) victim = it;
    }
    if (victim == tiles_.end()) return;
    victim->second.texture->releaseGLObjects(nullptr);
    residentBytes_ -= victim->second.bytes;
    tiles_.erase(victim);
    ++stats_.tilesEvicted;
  }
}

void ImageryTiles::waitUntilIdle() {
  if (loader_) loader_->waitUntilIdle();
}

std::string ImageryTiles::loadError() const { return loader_ ? loader_->error() : std::string(); }

void ImageryTiles::releaseGLObjects(osg::State* state) const {
  for (const auto& [key, tile] : tiles_) tile.texture->releaseGLObjects(state);
}

}  // namespace nestwalk
