// terrain/paged_heightfield and height_tiles: a heightfield paged through a budget of a few tiles
// answers exactly as the resident one read from the same file (readDem): ground heights at random
// points, at samples and on grid lines (holes around), rays of every kind, samples, the height
// range, also with the scene loader's map shift; the tile cache keeps to its budget (least recently
// used out first), counts the reads a query waited for, and prefetched tiles cost no wait; terrain
// chunks built from it (the finest levels copy their fine window) are the resident ones. Real
// DEMs of ../shared/data are imported and compared the same way.
#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/terrain/height_tiles.h"
#include "nestwalk/terrain/paged_heightfield.h"
#include "nestwalk/terrain/terrain_chunk.h"
#include "nestwalk/terrain/terrain_import.h"
#include "nestwalk/terrain/terrain_pyramid.h"
#include "tests/common/temp_folder.h"
#include "tests/common/test_data.h"
#include "tests/terrain/rough_heights.h"

#include <cpl_conv.h>
#include <gdal.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <cstring>
#include <random>

namespace nestwalk::test {
namespace {

using terrain::Heightfield;

bool sameDouble(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Whether two optional answers are the same to the bit.
::testing::AssertionResult sameGround(const std::optional<double>& a, const std::optional<double>& b) {
  if (a.has_value() != b.has_value() || (a && !sameDouble(*a, *b)))
    return ::testing::AssertionFailure() << (a ? std::to_string(*a) : "none") << " vs "
                                         << (b ? std::to_string(*b) : "none");
  return ::testing::AssertionSuccess();
}

::testing::AssertionResult sameHit(const std::optional<terrain::RayHit>& a, const std::optional<terrain::RayHit>& b) {
  if (a.has_value() != b.has_value()) return ::testing::AssertionFailure() << (a ? "hit" : "miss") << " vs " << (b ? "hit" : "miss");
  if (!a) return ::testing::AssertionSuccess();
  if (!sameDouble(a->t, b->t) || a->col != b->col || a->row != b->row || a->half != b->half ||
      !sameDouble(a->point.z(), b->point.z()))
    return ::testing::AssertionFailure() << "t " << a->t << " vs " << b->t << ", cell " << a->col << "," << a->row
                                         << "/" << int(a->half) << " vs " << b->col << "," << b->row << "/" << int(b->half);
  return ::testing::AssertionSuccess();
}

/// Every kind of query on both heightfields, over the whole grid.
void expectSameAnswers(const Heightfield& resident, const Heightfield& paged, unsigned seed, int points, int rays) {
  ASSERT_EQ(resident.cols(), paged.cols());
  ASSERT_EQ(resident.rows(), paged.rows());
  ASSERT_EQ(resident.heightRange(), paged.heightRange());
  ASSERT_EQ(resident.origin(), paged.origin());
  std::mt19937 rng(seed);
  const Eigen::Vector2d a = resident.samplePosition(0, 0), b = resident.samplePosition(resident.cols() - 1, resident.rows() - 1);
  std::uniform_real_distribution<double> ux(a.x() - 2 * resident.dx(), b.x() + 2 * resident.dx());
  std::uniform_real_distribution<double> uy(b.y() - 2 * resident.dy(), a.y() + 2 * resident.dy());
  std::uniform_int_distribution<int> col(0, resident.cols() - 1), row(0, resident.rows() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < points; ++k) {
    const double x = ux(rng), y = uy(rng);
    ASSERT_TRUE(sameGround(resident.groundHeight(x, y), paged.groundHeight(x, y))) << "at " << x << ", " << y;
    // Exactly on a sample, on a grid line, on a cell diagonal (holes decide there).
    const int c = col(rng), r = row(rng);
    const Eigen::Vector2d s = resident.samplePosition(c, r);
    ASSERT_TRUE(sameGround(resident.groundHeight(s.x(), s.y()), paged.groundHeight(s.x(), s.y()))) << "sample " << c << "," << r;
    ASSERT_TRUE(sameGround(resident.groundHeight(s.x(), y), paged.groundHeight(s.x(), y)));
    ASSERT_TRUE(sameGround(resident.groundHeight(x, s.y()), paged.groundHeight(x, s.y())));
    const double f = unit(rng);
    const double dxg = s.x() + f * resident.dx(), dyg = s.y() - f * resident.dy();
    ASSERT_TRUE(sameGround(resident.groundHeight(dxg, dyg), paged.groundHeight(dxg, dyg)));
    const float hr = resident.sample(c, r), hp = paged.sample(c, r);
    ASSERT_TRUE(std::memcmp(&hr, &hp, sizeof hr) == 0) << "sample " << c << "," << r;
    ASSERT_EQ(resident.valid(c, r), paged.valid(c, r));
    // The ground's ceiling over a rectangle of up to 40 cells (across tiles too).
    const double w = 40 * unit(rng) * resident.dx(), hgt = 40 * unit(rng) * resident.dy();
    ASSERT_TRUE(sameGround(resident.groundCeiling(x, y, x + w, y + hgt), paged.groundCeiling(x, y, x + w, y + hgt)))
        << "ceiling at " << x << ", " << y;
  }
  const auto range = *resident.heightRange();
  std::uniform_real_distribution<double> uz(range.first - 5, range.second + 30), dir(-1.0, 1.0);
  for (int k = 0; k < rays; ++k) {
    const Eigen::Vector3d o(ux(rng), uy(rng), uz(rng));
    Eigen::Vector3d d;
    switch (k % 4) {
      case 0:  // steep, down
        d = {dir(rng), dir(rng), -1.0 - unit(rng)};
        break;
      case 1:  // grazing, across many tiles
        d = {dir(rng), dir(rng), 0.02 * dir(rng)};
        break;
      case 2:  // vertical, through a sample or along a grid line
        d = {0.0, 0.0, -1.0};
        break;
      default:  // any
        d = {dir(rng), dir(rng), dir(rng)};
    }
    Eigen::Vector3d origin = o;
    if (k % 4 == 2) {
      const Eigen::Vector2d s = resident.samplePosition(col(rng), row(rng));
      origin.x() = s.x();
      if (k % 8 == 2) origin.y() = s.y();
    }
    ASSERT_TRUE(sameHit(resident.intersectRay(origin, d), paged.intersectRay(origin, d))) << "ray " << k;
    ASSERT_TRUE(sameHit(resident.intersectRay(origin, d, 0.5, 900.0), paged.intersectRay(origin, d, 0.5, 900.0))) << "ray " << k;
  }
}

struct PagedCase {
  TempFolder dir;
  std::string path;
  PagedCase(int cols, int rows, unsigned seed, double holes) : path((dir / "survey.tif").string()) {
    terrain::writeTerrainCog(path, cols, rows, roughHeights(cols, rows, seed, holes), 512345.5, 7765432.5, 0.25, 0.25,
                             "EPSG:32633", false);
  }
};

/// Four whole tiles: heights, block ranges, block hole flags and the tile itself (under 1 KB).
constexpr std::size_t kFourTiles =
    4 * (std::size_t(terrain::kHeightTileCells + 1) * (terrain::kHeightTileCells + 1) * 4 + 8192 + 1024 + 1024);

TEST(PagedHeightfield, AnswersBitForBitAsTheResidentHeightfieldThroughABudgetOfFourTiles) {
  // 3001 x 2501 at UTM magnitudes, 70 degrees north, holes: 12 x 10 tiles, the last narrow.
  PagedCase c(3001, 2501, 5, 0.02);
  const Heightfield resident = terrain::readDem(c.path);
  const Heightfield paged = terrain::openPagedHeightfield(std::make_shared<const terrain::TerrainPyramid>(c.path),
                                                          {.budgetBytes = kFourTiles});
  ASSERT_TRUE(paged.paged());
  EXPECT_TRUE(std::isnan(paged.noDataFraction()));
  expectSameAnswers(resident, paged, 17, 20000, 4000);
  const terrain::HeightTileStats s = paged.tiles()->stats();
  EXPECT_LE(s.peakBytesHeld, kFourTiles);
  EXPECT_GT(s.evicted, 100u);
  EXPECT_LE(s.reads - s.evicted, 4u) << "tiles held: those read less those evicted, four at most";
  EXPECT_GE(s.waits, s.reads - s.prefetched) << "every tile a query read itself was a wait";
}

TEST(PagedHeightfield, OpeningLowersGdalsBlockCacheButNeverRaisesIt) {
  if (CPLGetConfigOption("GDAL_CACHEMAX", nullptr)) GTEST_SKIP() << "GDAL_CACHEMAX is set: the user's value stands";
  PagedCase c(600, 500, 5, 0.0);
  const GIntBig before = GDALGetCacheMax64();
  GDALSetCacheMax64(GIntBig(256) << 20);
  { const Heightfield paged = terrain::openPagedHeightfield(std::make_shared<const terrain::TerrainPyramid>(c.path)); }
  EXPECT_EQ(GDALGetCacheMax64(), GIntBig(terrain::kPagedGdalBlockCacheBytes));
  GDALSetCacheMax64(GIntBig(16) << 20);
  { const Heightfield paged = terrain::openPagedHeightfield(std::make_shared<const terrain::TerrainPyramid>(c.path)); }
  EXPECT_EQ(GDALGetCacheMax64(), GIntBig(16) << 20);
  GDALSetCacheMax64(before);
}

TEST(PagedHeightfield, ChunksBuiltFromItAreTheResidentOnesBitForBit) {
  // Levels 0 to 3 of 64-cell chunks read every fine sample under them (a paged chunk copies its
  // window, tile by tile, through a budget of four tiles); simplified, shaded, with holes.
  PagedCase c(1301, 1093, 9, 0.02);
  const Heightfield resident = terrain::readDem(c.path);
  const Heightfield paged = terrain::openPagedHeightfield(std::make_shared<const terrain::TerrainPyramid>(c.path),
                                                          {.budgetBytes = kFourTiles});
  const terrain::ChunkLayout layout(resident.cols(), resident.rows(), 64);
  terrain::ChunkShading shading;
  const auto range = *resident.heightRange();
  shading.heightLo = range.first;
  shading.heightHi = range.second;
  int chunks = 0;
  for (int level = 0; level <= 3; ++level)
    for (int y = 0; y < layout.chunksY(level); ++y)
      for (int x = 0; x < layout.chunksX(level); ++x) {
        const terrain::ChunkKey key{level, x, y};
        if (!layout.exists(key)) continue;
        const terrain::ChunkMesh a = terrain::buildChunk(resident, layout, key, shading, 1.5);
        const terrain::ChunkMesh b = terrain::buildChunk(paged, layout, key, shading, 1.5);
        SCOPED_TRACE("chunk " + std::to_string(level) + "/" + std::to_string(x) + "/" + std::to_string(y));
        ASSERT_EQ(a.positions, b.positions);
        ASSERT_EQ(a.indices, b.indices);
        ASSERT_EQ(a.colours, b.colours);
        ASSERT_TRUE(sameDouble(a.maxError, b.maxError));
        for (std::size_t q = 0; q < 4; ++q) {
          ASSERT_TRUE(sameDouble(a.quadrants[q].maxError, b.quadrants[q].maxError));
          ASSERT_EQ(a.quadrants[q].blocks.size(), b.quadrants[q].blocks.size());
          for (std::size_t k = 0; k < a.quadrants[q].blocks.size(); ++k)
            ASSERT_TRUE(sameDouble(a.quadrants[q].blocks[k].error, b.quadrants[q].blocks[k].error));
          ASSERT_EQ(a.quadrants[q].refinements.size(), b.quadrants[q].refinements.size());
          for (std::size_t k = 0; k < a.quadrants[q].refinements.size(); ++k)
            ASSERT_TRUE(sameDouble(a.quadrants[q].refinements[k].maxError, b.quadrants[q].refinements[k].maxError));
        }
        ++chunks;
      }
  EXPECT_GT(chunks, 400);
  EXPECT_LE(paged.tiles()->stats().peakBytesHeld, kFourTiles);
}

TEST(PagedHeightfield, TheMapShiftMovesThePagedGroundAsTheLoaderMovesTheResidentOne) {
  PagedCase c(801, 613, 9, 0.05);
  const Heightfield plain = terrain::readDem(c.path);
  const Eigen::Vector3d shift(-512000.0, -7765000.0, 123.25);
  // The resident grid moved as scene_loader.cpp's shifted() does.
  std::vector<float> h;
  for (int r = 0; r < plain.rows(); ++r)
    for (int col = 0; col < plain.cols(); ++col) h.push_back(float(plain.sample(col, r) + shift.z()));
  const Heightfield resident(plain.cols(), plain.rows(), std::move(h), plain.origin().x() + shift.x(),
                             plain.origin().y() + shift.y(), plain.dx(), plain.dy(), plain.noData(), plain.crsWkt());
  const Heightfield paged = terrain::openPagedHeightfield(std::make_shared<const terrain::TerrainPyramid>(c.path),
                                                          {.budgetBytes = kFourTiles, .shift = shift});
  expectSameAnswers(resident, paged, 23, 5000, 2000);
}

TEST(HeightTileCache, KeepsToItsBudgetLeastRecentlyUsedOutFirstAndCountsWaits) {
  PagedCase c(1400, 900, 3, 0.0);  // 6 x 4 tiles
  const Heightfield paged = terrain::openPagedHeightfield(std::make_shared<const terrain::TerrainPyramid>(c.path),
                                                          {.budgetBytes = kFourTiles});
  const terrain::HeightTileCache& tiles = *paged.tiles();
  ASSERT_EQ(tiles.tilesX(), 6);
  ASSERT_EQ(tiles.tilesY(), 4);
  for (int t = 0; t < 4; ++t) tiles.tile(t, 0);
  EXPECT_EQ(tiles.stats().waits, 4u);
  tiles.tile(0, 0);  // used again: tile (1, 0) is now the least recently used
  EXPECT_EQ(tiles.stats().waits, 4u);
  tiles.tile(4, 0);
  EXPECT_EQ(tiles.stats().waits, 5u);
  EXPECT_TRUE(tiles.holds(0, 0));
  EXPECT_FALSE(tiles.holds(1, 0));
  EXPECT_TRUE(tiles.holds(2, 0) && tiles.holds(3, 0) && tiles.holds(4, 0));
  EXPECT_EQ(tiles.stats().evicted, 1u);

  // Prefetched tiles are held before they are asked for: no wait.
  paged.prefetch(paged.samplePosition(1100, 500).x(), paged.samplePosition(1100, 500).y(),
                 paged.samplePosition(1390, 890).x(), paged.samplePosition(1390, 890).y(),
                 paged.samplePosition(1100, 500), paged.samplePosition(1100, 500));
  tiles.waitForPrefetch();
  const std::uint64_t before = tiles.stats().waits;
  EXPECT_TRUE(tiles.holds(4, 1) && tiles.holds(5, 1) && tiles.holds(4, 3) && tiles.holds(5, 3));
  for (int r = 500; r < 890; r += 7)
    for (int col = 1100; col < 1390; col += 7) {
      const Eigen::Vector2d p = paged.samplePosition(col, r);
      paged.groundHeight(p.x() + 0.1, p.y() - 0.05);
    }
  EXPECT_EQ(tiles.stats().waits, before);
  EXPECT_GT(tiles.stats().prefetched, 0u);
}

TEST(HeightTileCache, EachThreadKeepsItsLastFourTilesAliveAndReadsThemNoMore) {
  // A budget of one tile: the cache keeps one, but a thread's slots keep its last four alive, so a
  // query alternating among the four tiles at a tile corner never reads one again; a fifth pushes
  // the least recent out. The samples read through the slots are the file's (readDem).
  PagedCase c(1400, 900, 7, 0.0);
  const Heightfield resident = terrain::readDem(c.path);
  const Heightfield paged = terrain::openPagedHeightfield(std::make_shared<const terrain::TerrainPyramid>(c.path),
                                                          {.budgetBytes = kFourTiles / 4});
  const terrain::HeightTileCache& tiles = *paged.tiles();
  const int T = terrain::kHeightTileCells;
  const std::pair<int, int> corner[4] = {{1, 1}, {2, 1}, {1, 2}, {2, 2}};
  for (const auto& [tx, ty] : corner) tiles.threadTile(tx, ty);
  const std::uint64_t reads = tiles.stats().reads;
  EXPECT_EQ(reads, 4u);
  EXPECT_GE(tiles.stats().evicted, 3u);
  for (int k = 0; k < 100; ++k)
    for (const auto& [tx, ty] : corner) {
      const terrain::HeightTile& t = tiles.threadTile(tx, ty);
      const int col = tx * T + (k * 37) % T, row = ty * T + (k * 53) % T;
      ASSERT_EQ(*t.at(col, row), resident.sample(col, row)) << "tile " << tx << "," << ty;
    }
  EXPECT_EQ(tiles.stats().reads, reads) << "the four tiles came from the thread's slots";
  tiles.threadTile(3, 1);  // a fifth: (1, 1), the least recent, leaves the slots
  tiles.threadTile(2, 2);
  EXPECT_EQ(tiles.stats().reads, reads + 1);
  tiles.threadTile(1, 1);
  EXPECT_EQ(tiles.stats().reads, reads + 2);
}

/// A tile cache of 8 x 8 tiles of flat ground whose loader records the order of its reads and holds
/// the first until released, so that requested tiles queue up behind it: the order they are then
/// read in is the queue's.
struct RecordedReads {
  static constexpr int kTiles = 8;
  std::mutex m;
  std::condition_variable cv;
  bool released = false;
  std::vector<std::pair<int, int>> order;
  std::shared_ptr<const terrain::HeightTileCache> tiles = std::make_shared<const terrain::HeightTileCache>(
      kTiles * terrain::kHeightTileCells + 1, kTiles * terrain::kHeightTileCells + 1, std::nullopt,
      [this](int c0, int r0, int w, int h) {
        std::unique_lock lock(m);
        order.emplace_back(c0 / terrain::kHeightTileCells, r0 / terrain::kHeightTileCells);
        cv.notify_all();
        if (order.size() == 1) cv.wait(lock, [this] { return released; });
        return std::vector<float>(std::size_t(w) * std::size_t(h), 1.0f);
      },
      std::vector<float>{});
  /// Releases a read still held (a test that failed before release()), so the cache can stop.
  ~RecordedReads() {
    {
      const std::lock_guard lock(m);
      released = true;
    }
    cv.notify_all();
  }
  /// Requests tile (7, 7) and waits until its read holds the background thread.
  void block() {
    const double at = (kTiles - 1) * terrain::kHeightTileCells + 9.0;
    tiles->request({.tx0 = kTiles - 1, .ty0 = kTiles - 1, .tx1 = kTiles - 1, .ty1 = kTiles - 1,
                    .fromCol = at, .fromRow = at, .toCol = at, .toRow = at});
    std::unique_lock lock(m);
    cv.wait(lock, [this] { return !order.empty(); });
  }
  /// Lets the reads go on, waits for them, and returns their order after the blocking one.
  std::vector<std::pair<int, int>> release() {
    {
      const std::lock_guard lock(m);
      released = true;
    }
    cv.notify_all();
    tiles->waitForPrefetch();
    return {order.begin() + 1, order.end()};
  }
};

TEST(HeightTileCache, ALaterRequestsTilesAreReadFirstAndATileQueuedTwiceOnce) {
  // Standing in tile (0, 0), then in tile (3, 0): reach order (0, 0), (1, 0), (2, 0), then
  // (3, 0), (2, 0), (1, 0). The later request's tiles come first, (1, 0) and (2, 0) moved up from
  // the earlier one's, each read once.
  RecordedReads reads;
  reads.block();
  const int T = terrain::kHeightTileCells;
  reads.tiles->request({.tx0 = 0, .ty0 = 0, .tx1 = 2, .ty1 = 0, .fromCol = 10.0, .fromRow = 10.0, .toCol = 10.0, .toRow = 10.0});
  reads.tiles->request({.tx0 = 1, .ty0 = 0, .tx1 = 3, .ty1 = 0, .fromCol = 3 * T + 10.0, .fromRow = 10.0,
                        .toCol = 3 * T + 10.0, .toRow = 10.0});
  const std::vector<std::pair<int, int>> expected = {{3, 0}, {2, 0}, {1, 0}, {0, 0}};
  EXPECT_EQ(reads.release(), expected);
}

TEST(HeightTileCache, ARequestReachesThePollingOrParkedThreadAndTheLatestIsReadFirst) {
  // Requests only store themselves; the background thread takes them. Two requests made while the
  // thread is busy are queued in the order made: the later's tiles first, each in its reach order.
  // One made while the thread polls (it had work just now) is found; one made after it parked (no
  // work for kTileRequestActiveMs) wakes it.
  RecordedReads reads;
  reads.block();
  reads.tiles->request({.tx0 = 0, .ty0 = 0, .tx1 = 1, .ty1 = 0, .fromCol = 10.0, .fromRow = 10.0, .toCol = 10.0, .toRow = 10.0});
  reads.tiles->request({.tx0 = 4, .ty0 = 5, .tx1 = 4, .ty1 = 6, .fromCol = 4 * terrain::kHeightTileCells + 9.0,
                        .fromRow = 6 * terrain::kHeightTileCells + 9.0, .toCol = 4 * terrain::kHeightTileCells + 9.0,
                        .toRow = 6 * terrain::kHeightTileCells + 9.0});
  const std::vector<std::pair<int, int>> order = {{4, 6}, {4, 5}, {0, 0}, {1, 0}};  // the feet's tile first
  EXPECT_EQ(reads.release(), order);

  auto readSoon = [&](int tx, int ty) {
    for (int k = 0; k < 500; ++k) {  // up to 5 s: a request never taken fails here, not in a hang
      if (reads.tiles->holds(tx, ty)) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  };
  reads.tiles->tile(2, 2);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // idle, polling
  reads.tiles->request({.tx0 = 2, .ty0 = 2, .tx1 = 3, .ty1 = 2, .fromCol = 600.0, .fromRow = 600.0, .toCol = 900.0, .toRow = 600.0});
  EXPECT_TRUE(readSoon(3, 2));
  std::this_thread::sleep_for(std::chrono::milliseconds(terrain::kTileRequestActiveMs + 500));  // parked
  reads.tiles->request({.tx0 = 5, .ty0 = 5, .tx1 = 5, .ty1 = 5, .fromCol = 1300.0, .fromRow = 1300.0, .toCol = 1300.0, .toRow = 1300.0});
  EXPECT_TRUE(readSoon(5, 5));
  EXPECT_EQ(reads.tiles->stats().waits, 1u) << "tile (2, 2) only, read by this thread";
}

TEST(PagedHeightfield, PrefetchAsksForTheTilesTheWalkReachesFirstFirst) {
  // 1 m cells. Standing (the path is a point): each tile of the rectangle by the distance from the
  // point to the nearest of its cells' corners (a brute-force walk over its border), ties in
  // row-major order.
  const int T = terrain::kHeightTileCells;
  RecordedReads reads;
  const Heightfield paged(RecordedReads::kTiles * T + 1, RecordedReads::kTiles * T + 1, reads.tiles,
                          std::pair<float, float>{1.0f, 1.0f}, 500000.0, 7000000.0, 1.0, 1.0);
  reads.block();
  const double col = 3 * T + 200.0, row = 2 * T + 10.0;  // in tile (3, 2), 10 cells below its top
  paged.prefetch(paged.samplePosition(T + 5, T + 5).x(), paged.samplePosition(T + 5, T + 5).y(),
                 paged.samplePosition(5 * T - 5, 4 * T - 5).x(), paged.samplePosition(5 * T - 5, 4 * T - 5).y(),
                 Eigen::Vector2d(500000.0 + col, 7000000.0 - row), Eigen::Vector2d(500000.0 + col, 7000000.0 - row));
  std::vector<std::pair<double, std::pair<int, int>>> byDistance;
  for (int ty = 1; ty <= 3; ++ty)
    for (int tx = 1; tx <= 4; ++tx) {
      double nearest = std::numeric_limits<double>::infinity();
      for (int k = 0; k <= T; ++k)
        for (const auto& [c, r] : {std::pair{tx * T + k, ty * T}, std::pair{tx * T + k, (ty + 1) * T},
                                   std::pair{tx * T, ty * T + k}, std::pair{(tx + 1) * T, ty * T + k}})
          nearest = std::min(nearest, std::hypot(c - col, r - row));
      const bool inside = col >= tx * T && col <= (tx + 1) * T && row >= ty * T && row <= (ty + 1) * T;
      byDistance.push_back({inside ? 0.0 : nearest, {tx, ty}});
    }
  std::stable_sort(byDistance.begin(), byDistance.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::pair<int, int>> expected;
  for (const auto& entry : byDistance) expected.push_back(entry.second);
  EXPECT_EQ(reads.release(), expected);
  EXPECT_EQ(expected[0], (std::pair<int, int>{3, 2}));
  EXPECT_EQ(expected[1], (std::pair<int, int>{3, 1}));  // 10 cells up, against 56 to the right

  // Walking: the tiles the path crosses are read first, in the order it enters them (brute force:
  // the path every tenth of a cell), the feet's tile first. The path runs from tile (4, 1)
  // south-west into (1, 3).
  RecordedReads walk;
  const Heightfield walked(RecordedReads::kTiles * T + 1, RecordedReads::kTiles * T + 1, walk.tiles,
                           std::pair<float, float>{1.0f, 1.0f}, 500000.0, 7000000.0, 1.0, 1.0);
  walk.block();
  const Eigen::Vector2d from(4 * T + 100.0, T + 30.0), to(T + 60.0, 3 * T + 200.0);  // (col, row)
  auto map = [](const Eigen::Vector2d& cr) { return Eigen::Vector2d(500000.0 + cr.x(), 7000000.0 - cr.y()); };
  walked.prefetch(map({T + 5.0, T + 5.0}).x(), map({T + 5.0, T + 5.0}).y(), map({5 * T - 5.0, 4 * T - 5.0}).x(),
                  map({5 * T - 5.0, 4 * T - 5.0}).y(), map(from), map(to));
  std::vector<std::pair<int, int>> crossed;
  for (int k = 0; k <= 10 * 1000; ++k) {
    const Eigen::Vector2d p = from + (to - from) * (k / 10000.0);
    const std::pair<int, int> t{int(p.x()) / T, int(p.y()) / T};
    if (std::find(crossed.begin(), crossed.end(), t) == crossed.end()) crossed.push_back(t);
  }
  ASSERT_GE(crossed.size(), 5u);
  const std::vector<std::pair<int, int>> order = walk.release();
  ASSERT_EQ(order.size(), 12u);
  const std::vector<std::pair<int, int>> first(order.begin(), order.begin() + std::ptrdiff_t(crossed.size()));
  EXPECT_EQ(first, crossed);

  // A path that clips tile (1, 1) for under 6 cells, 4 cells from its corner: entered, so read
  // between the two tiles it joins, before (2, 2), which it misses.
  RecordedReads clip;
  const Heightfield clipped(RecordedReads::kTiles * T + 1, RecordedReads::kTiles * T + 1, clip.tiles,
                            std::pair<float, float>{1.0f, 1.0f}, 500000.0, 7000000.0, 1.0, 1.0);
  clip.block();
  clipped.prefetch(map({T + 5.0, T + 5.0}).x(), map({T + 5.0, T + 5.0}).y(), map({3 * T - 5.0, 3 * T - 5.0}).x(),
                   map({3 * T - 5.0, 3 * T - 5.0}).y(), map({2 * T - 200.0, 2 * T + 196.0}),
                   map({2 * T + 196.0, 2 * T - 200.0}));
  const std::vector<std::pair<int, int>> clipOrder = {{1, 2}, {1, 1}, {2, 1}, {2, 2}};
  EXPECT_EQ(clip.release(), clipOrder);
}

TEST(PagedHeightfield, RealDemsAnswerAsTheirResidentHeightfields) {
  const auto data = sharedData();
  if (data.empty()) GTEST_SKIP() << "../shared/data is absent (NESTWALK_SHARED_DATA): no real DEM to compare";
  for (const char* name : {"storml_elev_orig.tif", "mt_rainier_90m.tif", "pre_runout_DEM.asc"}) {
    SCOPED_TRACE(name);
    const auto source = data / "terrain" / name;
    if (!std::filesystem::exists(source)) {
      std::printf("%s absent: skipped\n", source.c_str());
      continue;
    }
    TempFolder dir;
    const std::string out = (dir / "imported.tif").string();
    terrain::importTerrain(source.string(), out, {});
    const Heightfield resident = terrain::readDem(out);
    const Heightfield paged =
        terrain::openPagedHeightfield(std::make_shared<const terrain::TerrainPyramid>(out), {.budgetBytes = kFourTiles});
    expectSameAnswers(resident, paged, 31, 5000, 1500);
  }
}

}  // namespace
}  // namespace nestwalk::test
