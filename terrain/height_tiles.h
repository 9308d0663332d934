// Fine heights in tiles, read on demand through a cache with a byte budget: the storage of a paged
// Heightfield (heightfield.h), for a DEM too large to hold (a survey of 0.4-2 G samples).
//
// Tiles: tile (tx, ty) holds the samples of the cells [tx T, (tx + 1) T) x [ty T, (ty + 1) T) with
// T = kHeightTileCells, i.e. the samples tx T .. min((tx + 1) T, cols - 1) (and rows likewise): one
// column and row more than its cells, shared with the next tile, so that every cell's four corners
// lie in the one tile that holds the cell. A tile keeps the heights with every hole as NaN (as the
// resident heightfield's clean copy) and the {min, max} of each ray block's samples
// (kHeightTileBlockCells cells a side: the ray pyramid's base level, heightfield.cpp), computed from
// the tile's own samples, so the ray cast reads exactly what it reads from a resident grid; and
// whether each block holds a hole (Heightfield::groundCeiling).
// Each tile also has a coarse {min, max} given at construction (from the terrain pyramid), so a ray
// passing above a tile never reads it.
//
// Cache: tiles read (the loader's call) when first asked for, kept until the bytes held exceed the
// budget, then the least recently used go first (at least one tile is always kept). Tiles handed out
// are shared: one evicted while a query still holds it lives until that query lets go, and each
// thread keeps the last kThreadTileSlots tiles it used (so its hits take no lock and no atomic
// operation: a walker's footprint astride a tile edge, or its ground ceiling's blocks on the next
// tile, would otherwise take the lock at every switch), so the bytes alive can exceed the budget
// by a few tiles per thread. A tile counts as used (it moves to the front of the cache's use
// order, in constant time under its lock) when a thread takes it into its slots, when tile() asks
// for it while it is not the thread's most recent, and when a request() names it (a walker names
// its own tiles as they change), not on every hit; eviction takes the back, also in constant time.
//
// Background reads: request() names a walk's rectangle of tiles and its path for a background
// thread (started by the first call), so that a walker's next tiles are read before it needs them;
// a tile asked for that is not held yet is a wait (stats().waits), whether read there or in flight
// on the background thread. The thread orders the tiles (tilesByReach), counts the held ones as
// used and queues the others ahead of those queued before (the latest request names where the walk
// goes now). The caller only stores the request (a lock of its own, no look-up, no sort): on a
// 3.2 cm DEM the look-ups and the ordering on a walker's own thread were most of its step's p99.
// The thread takes every request in the order made, so the latest's tiles end first, each
// request's in its order. While it has had work within kTileRequestActiveMs it looks for requests
// every kTileRequestPollMs; then it parks, and the next request wakes it. A wake-up per request
// cost the walker's step up to 4.5 ms now and then: the woken reader often took the walker's core
// (notify_all returned after it), so that bench render's 1 G walk at 10x pace had a step p99 of
// 23-93 us, against 14-18 us polling (alternated runs, 2026-11-30; 6.1-7.2 at 1 M, resident).
// Neither waited for a tile (5 runs each). The waits once seen there (5 of 28 runs) were the bench's
// pacing, not the requests' path: its clock started before the placement's reads, and the flight
// ran its first steps back to back to catch up, over the ground held around the start, before a
// tile ahead could be read (a fresh tile takes 5-10 ms here; render_terrain_sweep.cpp).
//
// Errors: what the loader throws (an InputError naming the file) reaches the query that asked for
// the tile; a prefetch that fails is dropped (the query that needs the tile reads it again and gets
// the error). Thread safety: every member may be called from several threads at once; the loader
// is called from the querying threads and from the prefetch thread, one call at a time.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <list>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <thread>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

namespace nestwalk::terrain {

/// Cells a side of a tile: 32 ray blocks, 264 KB of heights; a tile's read decodes at most four of
/// the terrain file's own 512 x 512 tiles (GDAL's block cache, 256 MiB by default, keeps them too).
inline constexpr int kHeightTileCells = 256;
/// Cells a side of a ray block (the base level of heightfield.cpp's ray pyramid, 2^3).
inline constexpr int kHeightTileBlockCells = 8;
/// Tiles each thread keeps for lock-free hits (see above): the up to 4 tiles a footprint astride a
/// tile corner reads.
inline constexpr std::size_t kThreadTileSlots = 4;
/// The default budget: some 480 tiles, 32 M samples (32 km^2 at 1 m cells, 3.3 ha at 3.2 cm). With
/// the chunk cache's 1 GiB (paged_terrain.h) a survey's run stays within 1.5 GB (1,430 MiB): bench
/// render's 1 G-sample run peaked at 1,452-1,575 MiB with 256 MiB of tiles, 1,334-1,359 MiB with
/// 128 MiB, the walker waiting for no read and the views as fast.
inline constexpr std::size_t kDefaultHeightTileBudgetBytes = std::size_t(128) << 20;
/// tilesByReach(): tiles off the walk's path are ordered by the path's points taken this many cells
/// apart (an eighth of a tile), at most kTileReachPathPoints of them (a walker's path is at most a
/// few tiles; a far `to` from another caller costs no more).
inline constexpr double kTileReachPathStepCells = kHeightTileCells / 8.0;
inline constexpr int kTileReachPathPoints = 64;
/// The background thread, while active (it had work within kTileRequestActiveMs), looks for
/// request()s every kTileRequestPollMs; then it parks until one wakes it (see above). A walker at
/// 400 m/s covers 0.4 m in a poll period, within the 4 m held around it (walker.h).
inline constexpr int kTileRequestPollMs = 1;
inline constexpr int kTileRequestActiveMs = 2000;

/// Where a walk goes, in the grid's cell units (column, row: fractional, row down): the tiles
/// [tx0, tx1] x [ty0, ty1] it wants (inclusive; clipped to the grid) and its path from `from` to
/// `to` (the feet and where the motion takes them).
struct TileRequest {
  int tx0 = 0, ty0 = 0, tx1 = -1, ty1 = -1;
  double fromCol = 0.0, fromRow = 0.0, toCol = 0.0, toRow = 0.0;
};

/// The request's tiles, the soonest reached first by a walk along its path: the tiles the path
/// crosses in the order it enters their cells (Liang-Barsky), then the others by the least of
/// (cells along the path to a point) + (cells from that point to the tile), over at most
/// kTileReachPathPoints points; ties in row-major order. A path with no finite length is its
/// start point.
std::vector<std::pair<int, int>> tilesByReach(const TileRequest& request);

struct HeightTile {
  int c0 = 0, r0 = 0;      // the fine sample held at (0, 0)
  int cols = 0, rows = 0;  // samples held (the row stride)
  std::vector<float> clean;  // cols * rows heights, holes NaN
  int blocksX = 0, blocksY = 0;
  std::vector<float> blockRange;  // {min, max} of the valid samples of each ray block (+inf, -inf if none)
  std::vector<std::uint8_t> blockHoles;  // 1 where a ray block's corner samples hold a hole, row-major

  const float* at(int c, int r) const {
    return clean.data() + std::size_t(r - r0) * std::size_t(cols) + std::size_t(c - c0);
  }
  /// Block (i, j) of the whole grid (it lies in this tile).
  const float* range(int i, int j) const {
    return blockRange.data() +
           2 * (std::size_t(j - r0 / kHeightTileBlockCells) * std::size_t(blocksX) + std::size_t(i - c0 / kHeightTileBlockCells));
  }
  /// Whether block (i, j) of the whole grid (it lies in this tile) holds a hole.
  bool holes(int i, int j) const {
    return blockHoles[std::size_t(j - r0 / kHeightTileBlockCells) * std::size_t(blocksX) +
                      std::size_t(i - c0 / kHeightTileBlockCells)] != 0;
  }
  std::size_t bytes() const {
    return sizeof(HeightTile) + (clean.size() + blockRange.size()) * sizeof(float) + blockHoles.size();
  }
};

struct HeightTileStats {
  std::uint64_t reads = 0;       // tiles read (by queries and by the prefetch thread)
  std::uint64_t waits = 0;       // tiles a query needed that were not held yet
  std::uint64_t prefetched = 0;  // tiles the prefetch thread read
  std::uint64_t evicted = 0;
  std::size_t bytesHeld = 0, peakBytesHeld = 0;
};

class HeightTileCache {
 public:
  /// Reads the stored samples of the window [c0, c0 + w) x [r0, r0 + h), row-major.
  using Loader = std::function<std::vector<float>(int c0, int r0, int w, int h)>;

  /// cols x rows samples (at least 2 x 2); noData: the stored sentinel (NaN and infinities are
  /// holes too); tileRanges: {min, max} per tile, row-major, each bounding every valid sample the
  /// tile holds (empty: none known, every tile is read when a ray passes). Throws
  /// std::invalid_argument on inconsistent sizes.
  HeightTileCache(int cols, int rows, std::optional<float> noData, Loader loader, std::vector<float> tileRanges,
                  std::size_t budgetBytes = kDefaultHeightTileBudgetBytes);
  ~HeightTileCache();
  HeightTileCache(const HeightTileCache&) = delete;
  HeightTileCache& operator=(const HeightTileCache&) = delete;

  int tilesX() const { return tilesX_; }
  int tilesY() const { return tilesY_; }
  std::size_t budgetBytes() const { return budget_; }
  /// The coarse {min, max} of tile (tx, ty): -inf, +inf when none was given.
  std::pair<float, float> tileRange(int tx, int ty) const;
  /// The tile, read if not held (the caller's thread waits: a wait).
  std::shared_ptr<const HeightTile> tile(int tx, int ty) const;
  /// The tile as tile() gives it, without touching its count of owners: it stays alive (in the
  /// calling thread's slots) at least until this thread next asks any cache for a tile. For the
  /// hot single-sample queries (a ground height), which read it at once.
  const HeightTile& threadTile(int tx, int ty) const;
  /// Adds the request to those the thread has not taken yet: it queues each one's tiles not held
  /// yet in tilesByReach order, ahead of the tiles queued before (a tile queued already moves up),
  /// in the order made (see above). Costs the caller a lock
  /// of its own and two atomic operations (and a wake-up when the thread is parked): a median of
  /// 1.2 us, p99 2.3-2.9, on bench render's 1 G walk, mostly the cache lines the thread wrote when
  /// it took the last request (3.3-3.9 us, p99 23-83, while its polls wrote pending_ each time).
  void request(const TileRequest& request) const;
  /// Whether the tile is held now (no read).
  bool holds(int tx, int ty) const;
  HeightTileStats stats() const;
  /// Waits (see stats()) of the calling thread, on every cache, since it started: a walker's count
  /// of ground reads that waited, apart from the renderer's.
  static std::uint64_t threadWaits();
  /// Waits until the prefetch queue is empty and no request is pending (tests, benchmarks).
  void waitForPrefetch() const;

 private:
  /// The tiles held, each with its place in useOrder_ (most recently used first): a use moves it to
  /// the front and eviction takes the back, in constant time under mutex_ (a scan for the oldest of
  /// some 970 tiles, each a cache miss, held the lock for up to 300 us and stalled a walker's step).
  struct Held {
    std::shared_ptr<const HeightTile> tile;
    std::list<std::uint64_t>::iterator use;
  };
  std::shared_ptr<const HeightTile> read(int tx, int ty) const;
  void insert(std::uint64_t key, std::shared_ptr<const HeightTile> tile) const;  // mutex_ held
  void touch(Held& held) const;                                                   // mutex_ held: used now
  void prefetchLoop() const;
  void startThread() const;                                        // mutex_ held
  void queueFirst(std::span<const std::pair<int, int>> tiles) const;  // mutex_ held: a request's queueing
  std::uint64_t key(int tx, int ty) const { return std::uint64_t(ty) * std::uint64_t(tilesX_) + std::uint64_t(tx); }

  int cols_, rows_, tilesX_, tilesY_;
  float noDataCompare_;
  Loader loader_;
  std::vector<float> tileRanges_;
  std::size_t budget_;
  std::uint64_t id_;  // this cache among every one of the process (the threads' last-tile slots)

  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  mutable std::unordered_map<std::uint64_t, Held> held_;
  mutable std::list<std::uint64_t> useOrder_;
  mutable std::unordered_set<std::uint64_t> inFlight_;
  mutable std::deque<std::uint64_t> queue_;
  mutable HeightTileStats stats_;
  mutable std::mutex readMutex_;  // the loader, one call at a time
  bool stopping_ = false;
  mutable std::thread prefetcher_;  // started by the first request()

  // request()'s mailbox: the requests not taken yet, in the order made. The caller sets pending_,
  // then reads parked_; the thread sets parked_, then reads pending_ under mutex_ before it waits:
  // one of them sees the other's store, so a request is never left to a parked thread.
  mutable std::mutex requestMutex_;
  mutable std::vector<TileRequest> requests_;
  mutable std::atomic<bool> pending_{false};
  mutable bool ordering_ = false;                 // mutex_: the thread is ordering a request it took
  mutable std::atomic<bool> started_{false};      // the thread runs (prefetcher_ is not atomic)
  mutable std::atomic<bool> parked_{false};       // the thread waits for a wake-up, not polling
};

}  // namespace nestwalk::terrain
