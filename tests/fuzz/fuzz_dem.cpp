// Fuzz target: a DEM as GDAL reads it and our checks after it (terrain/dem_reader.h: readDem), from
// GDAL's in-memory file system (/vsimem/), then a ground query at the raster's centre. The limit on
// samples is lowered to 4M so that a header claiming a huge raster is refused, not allocated.
#include "nestwalk/terrain/dem_reader.h"
#include "tests/fuzz/fuzz_input.h"

#include <cpl_vsi.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  nestwalk::terrain::initGdal();
  const char* path = "/vsimem/fuzz.tif";
  VSILFILE* f = VSIFileFromMemBuffer(path, const_cast<GByte*>(data), vsi_l_offset(size), FALSE);
  if (!f) return 0;
  VSIFCloseL(f);
  nestwalk::fuzz::expectInputErrorOnly([&] {
    nestwalk::terrain::DemReadOptions options;
    options.maxSamples = 1u << 22;
    const nestwalk::terrain::Heightfield hf = nestwalk::terrain::readDem(path, options);
    const Eigen::Vector2d centre = hf.samplePosition(hf.cols() / 2, hf.rows() / 2);
    hf.groundHeight(centre.x(), centre.y());
  });
  VSIUnlink(path);
  return 0;
}
