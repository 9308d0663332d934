#include "nestwalk/terrain/height_tiles.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

namespace nestwalk::terrain {
namespace {

std::atomic<std::uint64_t> nextCacheId{1};

/// Each thread's last kThreadTileSlots tiles, most recent first: a hit there takes no lock (see
/// height_tiles.h).
struct LastTile {
  std::uint64_t cache = 0, key = 0;
  std::shared_ptr<const HeightTile> tile;
  bool is(std::uint64_t c, std::uint64_t k) const { return cache == c && key == k && tile; }
};
thread_local std::array<LastTile, kThreadTileSlots> lastTiles;

/// Moves slot i to the front, the ones before it back by one (shared pointers moved, not copied:
/// no atomic operation).
void toFront(std::size_t i) {
  if (i > 0) std::rotate(lastTiles.begin(), lastTiles.begin() + std::ptrdiff_t(i), lastTiles.begin() + std::ptrdiff_t(i) + 1);
}
thread_local std::uint64_t waitsOfThisThread = 0;

int tilesFor(int samples) { return std::max(1, (samples - 2) / kHeightTileCells + 1); }

}  // namespace

std::vector<std::pair<int, int>> tilesByReach(const TileRequest& request) {
  std::vector<std::pair<int, int>> wanted;
  for (int ty = request.ty0; ty <= request.ty1; ++ty)
    for (int tx = request.tx0; tx <= request.tx1; ++tx) wanted.emplace_back(tx, ty);
  const double a[2] = {request.fromCol, request.fromRow};
  double b[2] = {request.toCol, request.toRow};
  if (!std::isfinite(std::hypot(b[0] - a[0], b[1] - a[1]))) b[0] = a[0], b[1] = a[1];  // no usable direction
  const double length = std::hypot(b[0] - a[0], b[1] - a[1]);
  const int steps = std::min(kTileReachPathPoints - 1, int(std::ceil(length / kTileReachPathStepCells)));
  auto gap = [](double at, int tile) {
    const double lo = double(tile) * kHeightTileCells, hi = lo + kHeightTileCells;
    return at < lo ? lo - at : at > hi ? at - hi : 0.0;
  };
  // Where the path a -> b enters tile t's cells, as a fraction of it (nullopt: it misses them).
  auto entry = [&](const std::pair<int, int>& t) -> std::optional<double> {
    double t0 = 0.0, t1 = 1.0;
    const int tile[2] = {t.first, t.second};
    for (int axis = 0; axis < 2; ++axis) {
      const double lo = double(tile[axis]) * kHeightTileCells, hi = lo + kHeightTileCells;
      const double d = b[axis] - a[axis];
      if (d == 0.0) {
        if (a[axis] < lo || a[axis] > hi) return std::nullopt;
        continue;
      }
      double enter = (lo - a[axis]) / d, leave = (hi - a[axis]) / d;
      if (enter > leave) std::swap(enter, leave);
      t0 = std::max(t0, enter), t1 = std::min(t1, leave);
      if (t0 > t1) return std::nullopt;
    }
    return t0;
  };
  struct Reach {
    bool offPath = true;
    double cells = std::numeric_limits<double>::infinity();
    bool operator<(const Reach& o) const { return offPath != o.offPath ? !offPath : cells < o.cells; }
  };
  auto reach = [&](const std::pair<int, int>& t) {
    if (const std::optional<double> at = entry(t)) return Reach{false, *at * length};
    Reach best;
    for (int k = 0; k <= steps; ++k) {
      const double along = steps == 0 ? 0.0 : double(k) / steps;
      const double px = a[0] + (b[0] - a[0]) * along, py = a[1] + (b[1] - a[1]) * along;
      best.cells = std::min(best.cells, along * length + std::hypot(gap(px, t.first), gap(py, t.second)));
    }
    return best;
  };
  std::vector<std::pair<Reach, std::pair<int, int>>> byReach;
  byReach.reserve(wanted.size());
  for (const auto& t : wanted) byReach.push_back({reach(t), t});
  std::stable_sort(byReach.begin(), byReach.end(), [](const auto& l, const auto& m) { return l.first < m.first; });
  for (std::size_t i = 0; i < wanted.size(); ++i) wanted[i] = byReach[i].second;
  return wanted;
}

HeightTileCache::HeightTileCache(int cols, int rows, std::optional<float> noData, Loader loader,
                                 std::vector<float> tileRanges, std::size_t budgetBytes)
    : cols_(cols),
      rows_(rows),
      tilesX_(tilesFor(cols)),
      tilesY_(tilesFor(rows)),
      noDataCompare_(noData ? *noData : std::numeric_limits<float>::quiet_NaN()),
      loader_(std::move(loader)),
      tileRanges_(std::move(tileRanges)),
      budget_(budgetBytes),
      id_(nextCacheId.fetch_add(1)) {
  if (cols < 2 || rows < 2) throw std::invalid_argument("HeightTileCache: need at least 2 x 2 samples");
  if (!loader_) throw std::invalid_argument("HeightTileCache: no loader");
  if (!tileRanges_.empty() && tileRanges_.size() != 2 * std::size_t(tilesX_) * std::size_t(tilesY_))
    throw std::invalid_argument("HeightTileCache: tileRanges must hold {min, max} per tile");
}

HeightTileCache::~HeightTileCache() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  if (prefetcher_.joinable()) prefetcher_.join();
}

std::pair<float, float> HeightTileCache::tileRange(int tx, int ty) const {
  if (tileRanges_.empty()) return {-std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity()};
  const std::size_t k = 2 * key(tx, ty);
  return {tileRanges_[k], tileRanges_[k + 1]};
}

std::shared_ptr<const HeightTile> HeightTileCache::read(int tx, int ty) const {
  auto tile = std::make_shared<HeightTile>();
  tile->c0 = tx * kHeightTileCells;
  tile->r0 = ty * kHeightTileCells;
  tile->cols = std::min(kHeightTileCells + 1, cols_ - tile->c0);
  tile->rows = std::min(kHeightTileCells + 1, rows_ - tile->r0);
  {
    const std::lock_guard lock(readMutex_);
    tile->clean = loader_(tile->c0, tile->r0, tile->cols, tile->rows);
  }
  if (tile->clean.size() != std::size_t(tile->cols) * std::size_t(tile->rows))
    throw std::logic_error("HeightTileCache: the loader returned a window of the wrong size");
  for (float& h : tile->clean)
    if (!std::isfinite(h) || h == noDataCompare_) h = std::numeric_limits<float>::quiet_NaN();
  // Ray blocks: the valid samples at the corners of the block's cells (heightfield.cpp's base level).
  constexpr int B = kHeightTileBlockCells;
  const int cells = tile->cols - 1, cellRows = tile->rows - 1;
  tile->blocksX = (cells + B - 1) / B;
  tile->blocksY = (cellRows + B - 1) / B;
  tile->blockRange.resize(2 * std::size_t(tile->blocksX) * std::size_t(tile->blocksY));
  tile->blockHoles.resize(std::size_t(tile->blocksX) * std::size_t(tile->blocksY));
  for (int j = 0; j < tile->blocksY; ++j)
    for (int i = 0; i < tile->blocksX; ++i) {
      float lo = std::numeric_limits<float>::infinity(), hi = -lo;
      bool hole = false;
      for (int r = j * B; r <= std::min((j + 1) * B, cellRows); ++r)
        for (int c = i * B; c <= std::min((i + 1) * B, cells); ++c) {
          const float h = tile->clean[std::size_t(r) * std::size_t(tile->cols) + std::size_t(c)];
          if (!std::isnan(h)) lo = std::min(lo, h), hi = std::max(hi, h);
          else hole = true;
        }
      const std::size_t b = std::size_t(j) * std::size_t(tile->blocksX) + std::size_t(i);
      tile->blockRange[2 * b] = lo;
      tile->blockRange[2 * b + 1] = hi;
      tile->blockHoles[b] = hole ? 1 : 0;
    }
  return tile;
}

void HeightTileCache::touch(Held& held) const { useOrder_.splice(useOrder_.begin(), useOrder_, held.use); }

void HeightTileCache::insert(std::uint64_t k, std::shared_ptr<const HeightTile> tile) const {
  if (const auto again = held_.find(k); again != held_.end()) {  // read twice (not expected): the new one stays
    stats_.bytesHeld -= again->second.tile->bytes();
    useOrder_.erase(again->second.use);
    held_.erase(again);
  }
  stats_.bytesHeld += tile->bytes();
  useOrder_.push_front(k);
  held_[k] = {std::move(tile), useOrder_.begin()};
  ++stats_.reads;
  while (stats_.bytesHeld > budget_ && held_.size() > 1) {
    const auto oldest = held_.find(useOrder_.back());  // never k: it is at the front
    stats_.bytesHeld -= oldest->second.tile->bytes();
    useOrder_.pop_back();
    held_.erase(oldest);
    ++stats_.evicted;
  }
  stats_.peakBytesHeld = std::max(stats_.peakBytesHeld, stats_.bytesHeld);
}

std::shared_ptr<const HeightTile> HeightTileCache::tile(int tx, int ty) const {
  if (tx < 0 || ty < 0 || tx >= tilesX_ || ty >= tilesY_) throw std::out_of_range("HeightTileCache::tile: no such tile");
  const std::uint64_t k = key(tx, ty);
  // The most recent slot only: a tile asked for by tile() again after others counts as used anew.
  if (lastTiles[0].is(id_, k)) return lastTiles[0].tile;  // its use was counted when it came in
  std::shared_ptr<const HeightTile> found;
  {
    std::unique_lock lock(mutex_);
    if (auto it = held_.find(k); it != held_.end()) {
      found = it->second.tile;
      touch(it->second);
    } else {
      ++stats_.waits;
      ++waitsOfThisThread;
      changed_.wait(lock, [&] { return !inFlight_.count(k); });  // the prefetch thread is reading it
      if (auto again = held_.find(k); again != held_.end()) {
        found = again->second.tile;
        touch(again->second);
      }
    }
    if (!found) {
      inFlight_.insert(k);
      lock.unlock();
      try {
        found = read(tx, ty);
      } catch (...) {
        lock.lock();
        inFlight_.erase(k);
        changed_.notify_all();
        throw;
      }
      lock.lock();
      inFlight_.erase(k);
      insert(k, found);
      changed_.notify_all();
    }
  }
  // Into the front slot: the same tile's older slot if it has one, else the least recent.
  std::size_t slot = kThreadTileSlots - 1;
  for (std::size_t i = 1; i < kThreadTileSlots; ++i)
    if (lastTiles[i].is(id_, k)) slot = i;
  toFront(slot);
  lastTiles[0] = {id_, k, found};
  return found;
}

const HeightTile& HeightTileCache::threadTile(int tx, int ty) const {
  if (tx >= 0 && tx < tilesX_) {
    const std::uint64_t k = key(tx, ty);
    if (lastTiles[0].is(id_, k)) [[likely]]
      return *lastTiles[0].tile;
    for (std::size_t i = 1; i < kThreadTileSlots; ++i)
      if (lastTiles[i].is(id_, k)) {
        toFront(i);
        return *lastTiles[0].tile;
      }
  }
  tile(tx, ty);
  return *lastTiles[0].tile;
}

bool HeightTileCache::holds(int tx, int ty) const {
  const std::lock_guard lock(mutex_);
  return held_.count(key(tx, ty)) != 0;
}

void HeightTileCache::queueFirst(std::span<const std::pair<int, int>> tiles) const {
  std::vector<std::uint64_t> first;  // these tiles not held, in their order
  for (const auto& [tx, ty] : tiles) {
    if (tx < 0 || ty < 0 || tx >= tilesX_ || ty >= tilesY_) continue;
    const std::uint64_t k = key(tx, ty);
    if (auto it = held_.find(k); it != held_.end()) {
      // Held: it counts as used now, so the walk's own tiles are not the next to go.
      touch(it->second);
      continue;
    }
    if (inFlight_.count(k) || std::find(first.begin(), first.end(), k) != first.end()) continue;
    if (const auto queued = std::find(queue_.begin(), queue_.end(), k); queued != queue_.end()) queue_.erase(queued);
    first.push_back(k);
  }
  // Ahead of what earlier calls queued: the latest call knows where the walk goes now.
  queue_.insert(queue_.begin(), first.begin(), first.end());
}

void HeightTileCache::startThread() const {
  // Started on the first request, not with the cache: a scene loader forks to read models
  // (core/guarded_process.h) while no other thread runs.
  if (!prefetcher_.joinable()) {
    prefetcher_ = std::thread([this] { prefetchLoop(); });
    started_.store(true);
  }
}

void HeightTileCache::request(const TileRequest& request) const {
  if (request.tx0 > request.tx1 || request.ty0 > request.ty1) return;
  {
    const std::lock_guard lock(requestMutex_);
    requests_.push_back(request);
  }
  pending_.store(true);
  // The thread sets parked_ before it last looks at pending_ and waits (under mutex_): parked, it
  // may have missed this request and is woken (the lock makes sure it waits before the
  // notification); active, it finds the request within a poll period (see height_tiles.h).
  if (!started_.load() || parked_.load()) {
    {
      const std::lock_guard lock(mutex_);
      startThread();
    }
    changed_.notify_all();
  }
}

void HeightTileCache::prefetchLoop() const {
  using Clock = std::chrono::steady_clock;
  auto lastWork = Clock::now();
  std::vector<TileRequest> taken;  // swapped with the mailbox: each keeps its capacity
  std::unique_lock lock(mutex_);
  for (;;) {
    if (stopping_) return;
    // Read before it is written: a poll that finds nothing leaves the flag's cache line to the
    // walker's core.
    if (pending_.load(std::memory_order_relaxed) && pending_.exchange(false)) {
      taken.clear();
      {
        const std::lock_guard requestLock(requestMutex_);
        taken.swap(requests_);
      }
      ordering_ = true;
      lock.unlock();
      std::vector<std::vector<std::pair<int, int>>> ordered;  // no lock held: the sorts are ours
      for (const TileRequest& r : taken) ordered.push_back(tilesByReach(r));
      lock.lock();
      ordering_ = false;
      for (const auto& tiles : ordered) queueFirst(tiles);  // in the order made: the latest ends first
      lastWork = Clock::now();
      changed_.notify_all();  // waitForPrefetch() looks at pending_ too
      continue;
    }
    if (queue_.empty()) {
      if (Clock::now() - lastWork < std::chrono::milliseconds(kTileRequestActiveMs)) {
        changed_.wait_for(lock, std::chrono::milliseconds(kTileRequestPollMs));
      } else {
        parked_.store(true);
        changed_.wait(lock, [&] { return stopping_ || !queue_.empty() || pending_.load(); });
        parked_.store(false);
        lastWork = Clock::now();
      }
      continue;
    }
    const std::uint64_t k = queue_.front();
    queue_.pop_front();
    if (held_.count(k) || inFlight_.count(k)) {
      changed_.notify_all();
      continue;
    }
    inFlight_.insert(k);
    lock.unlock();
    std::shared_ptr<const HeightTile> tile;
    try {
      tile = read(int(k % std::uint64_t(tilesX_)), int(k / std::uint64_t(tilesX_)));
    } catch (...) {
      // Dropped: the query that needs this tile reads it and reports the error.
    }
    lock.lock();
    inFlight_.erase(k);
    if (tile) {
      insert(k, std::move(tile));
      ++stats_.prefetched;
    }
    lastWork = Clock::now();
    changed_.notify_all();
  }
}

void HeightTileCache::waitForPrefetch() const {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return queue_.empty() && inFlight_.empty() && !ordering_ && !pending_.load(); });
}

std::uint64_t HeightTileCache::threadWaits() { return waitsOfThisThread; }

HeightTileStats HeightTileCache::stats() const {
  const std::lock_guard lock(mutex_);
  return stats_;
}

}  // namespace nestwalk::terrain
