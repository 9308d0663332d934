#include "nestwalk/terrain/terrain_pyramid_format.h"

#include "nestwalk/core/input_error.h"

#include <zlib.h>

#include <bit>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace nestwalk::terrain {

static_assert(std::endian::native == std::endian::little, "the pyramid's CRC-32s are of little-endian floats");

std::string pyramidPageCrcKey(int page) { return "NESTWALK_PAGE_" + std::to_string(page) + "_CRC32"; }

std::string pyramidPathOf(const std::string& terrainPath) {
  const std::size_t slash = terrainPath.find_last_of('/');
  const std::size_t dot = terrainPath.find_last_of('.');
  const bool hasExtension = dot != std::string::npos && (slash == std::string::npos || dot > slash + 1);
  return (hasExtension ? terrainPath.substr(0, dot) : terrainPath) + ".pyramid.tif";
}

PyramidLayout::PyramidLayout(int cols_, int rows_) : cols(cols_), rows(rows_) {
  if (cols < 2 || rows < 2) throw std::invalid_argument("PyramidLayout: the grid needs 2 x 2 samples");
  const std::int64_t cells = std::max(cols - 1, rows - 1);
  int level = 0;
  while ((std::int64_t(kPyramidTopCells) << level) < cells) ++level;
  levels = level + 1;
}

std::uint32_t crc32Floats(std::uint32_t crc, const float* values, std::size_t count) {
  auto bytes = reinterpret_cast<const Bytef*>(values);
  std::size_t left = count * sizeof(float);
  uLong c = crc;
  while (left > 0) {  // zlib's length is a uInt
    const uInt n = uInt(std::min<std::size_t>(left, 1u << 30));
    c = ::crc32(c, bytes, n);
    bytes += n;
    left -= n;
  }
  return std::uint32_t(c);
}

TerrainFingerprint fingerprintOf(const std::string& terrainPath) {
  std::ifstream in(terrainPath, std::ios::binary);
  if (!in) throw InputError(terrainPath + ": cannot open the terrain file");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) throw InputError(terrainPath + ": cannot read the terrain file's size");
  TerrainFingerprint f;
  f.bytes = std::uint64_t(size);
  std::vector<char> buffer(std::size_t(std::min<std::uint64_t>(f.bytes, kFingerprintBytes)));
  auto crcAt = [&](std::uint64_t offset) {
    in.seekg(std::streamoff(offset));
    in.read(buffer.data(), std::streamsize(buffer.size()));
    if (!in) throw InputError(terrainPath + ": cannot read the terrain file");
    return std::uint32_t(::crc32(0, reinterpret_cast<const Bytef*>(buffer.data()), uInt(buffer.size())));
  };
  f.headCrc = crcAt(0);
  f.tailCrc = crcAt(f.bytes - buffer.size());
  return f;
}

}  // namespace nestwalk::terrain
