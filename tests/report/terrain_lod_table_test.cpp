// The methods report's terrain table (engine/report/terrain_lod_table.h) of a terrain with its
// pyramid, read whole or paged from the pyramid: the levels' chunks and errors from the pyramid's
// blocks are those of every chunk built from the samples (chunkLevelTable over the heightfield),
// and the heights measured at the random points are the same whichever way the samples are held;
// every level's measured error stays within its table's. At UTM magnitudes, 70 N.
#include "nestwalk/report/terrain_lod_table.h"

#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/terrain/paged_heightfield.h"
#include "nestwalk/terrain/terrain_chunk.h"
#include "nestwalk/terrain/terrain_import.h"
#include "nestwalk/terrain/terrain_pyramid.h"
#include "tests/common/temp_folder.h"
#include "tests/terrain/rough_heights.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

namespace nestwalk {
namespace {

TEST(TerrainLodTable, APagedTerrainsTableFromItsPyramidIsTheResidentOnesFromItsChunks) {
  constexpr int cols = 901, rows = 655;
  test::TempFolder dir;
  const std::string file = (dir / "rough.tif").string();
  terrain::writeTerrainCog(file, cols, rows, test::roughHeights(cols, rows, 5), 612000.5, 7769000.5, 0.5, 0.5,
                           "EPSG:32633", false);
  const terrain::Heightfield resident = terrain::readDem(file);
  const auto pyramid = std::make_shared<const terrain::TerrainPyramid>(file);
  const terrain::Heightfield paged = terrain::openPagedHeightfield(pyramid);
  ASSERT_TRUE(paged.paged());

  constexpr std::size_t kPoints = 4000;
  const std::vector<TerrainLodRow> a = measureTerrainLod(resident, nullptr, kPoints, 1);
  const std::vector<TerrainLodRow> b = measureTerrainLod(paged, pyramid.get(), kPoints, 1);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GE(a.size(), 5u);  // full and levels 0 to 3 at least
  for (std::size_t k = 0; k < a.size(); ++k) {
    SCOPED_TRACE(a[k].name);
    EXPECT_EQ(a[k].name, b[k].name);
    EXPECT_EQ(a[k].chunks, b[k].chunks);
    EXPECT_EQ(a[k].points, b[k].points);
    EXPECT_EQ(a[k].maxError, b[k].maxError);  // bit-identical heights at the same points
    EXPECT_EQ(a[k].meanError, b[k].meanError);
    float rounded = float(a[k].tableMaxError);
    if (double(rounded) < a[k].tableMaxError) rounded = std::nextafter(rounded, INFINITY);
    EXPECT_EQ(b[k].tableMaxError, double(rounded));
    if (k > 0) {
      EXPECT_GT(a[k].points, kPoints / 2);
      // Level 0 is the grid itself: the two interpolations differ only by rounding (1e-6 m).
      EXPECT_LE(a[k].maxError, a[k].tableMaxError + 1e-6) << "a measured error past the level's exact one";
    }
  }
}

}  // namespace
}  // namespace nestwalk
