// Fuzz target: a terrain pyramid (terrain/terrain_pyramid.h) as its reader opens, checks and reads
// it. The terrain file is fixed (a 150 x 100 grid with holes, written once per process in a
// temporary folder); each input is that terrain's sidecar, so inputs that keep the header's
// fingerprint reach the pages: every page is checked (verify) and a window of each level read.
#include "nestwalk/terrain/terrain_import.h"
#include "nestwalk/terrain/terrain_pyramid.h"
#include "tests/fuzz/fuzz_input.h"

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <vector>

namespace {

/// The fixed terrain's path, written on first use.
const std::string& terrainPath() {
  static const std::string path = [] {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("nestwalk-fuzz-pyramid-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    static const fs::path removeAtExit = dir;
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(removeAtExit, ignored);
    });
    const int cols = 150, rows = 100;
    std::vector<float> h(std::size_t(cols) * rows);
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c)
        h[std::size_t(r) * cols + std::size_t(c)] =
            (c * 7 + r * 13) % 97 == 0 ? NAN : float(100 + 10 * std::sin(0.1 * c) * std::cos(0.13 * r));
    const std::string p = (dir / "t.tif").string();
    nestwalk::terrain::writeTerrainCog(p, cols, rows, h, 500000.5, 7000000.5, 1.0, 1.0, "EPSG:32633", true);
    return p;
  }();
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& terrain = terrainPath();
  {
    std::ofstream out(nestwalk::terrain::pyramidPathOf(terrain), std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  nestwalk::fuzz::expectInputErrorOnly([&] {
    const nestwalk::terrain::TerrainPyramid pyramid(terrain);
    pyramid.verify();
    const nestwalk::terrain::PyramidLayout& layout = pyramid.layout();
    for (int level = 0; level < layout.levels; ++level) {
      pyramid.readHeights(level, 0, 0, layout.levelCols(level), layout.levelRows(level));
      pyramid.readBlocks(level, 0, 0, layout.blocksX(level), layout.blocksY(level));
    }
  });
  return 0;
}
