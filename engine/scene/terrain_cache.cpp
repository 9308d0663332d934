// The terrain cache (terrain_cache.h).
#include "nestwalk/scene/terrain_cache.h"

#include "nestwalk/core/output_file.h"
#include "nestwalk/scene/cache_folder.h"
#include "nestwalk/scene/model_cache.h"
#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/terrain/heightfield.h"
#include "nestwalk/terrain/imagery_import.h"
#include "nestwalk/terrain/terrain_import.h"
#include "nestwalk/terrain/terrain_pyramid.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>
#include <vector>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;

/// What an entry's `source` file says: the DEM's canonical path and identity, and the grid as the
/// scene read it (size, holes, height range: what changes with files beside the DEM, such as a
/// VRT's sources or a nodata value in an .aux.xml, which the identity does not see).
std::string sourceText(const std::string& canonical, const ModelFileIdentity& id, const terrain::Heightfield* hf,
                       std::pair<int, int> size, const std::string& header) {
  std::ostringstream s;
  s.precision(17);
  s << id.size << ' ' << id.mtimeNs << ' ' << id.inode << ' ' << id.device << '\n' << canonical << '\n';
  if (!hf) {
    s << size.first << ' ' << size.second << " unread " << header << '\n';  // paged: the raster's header only
    return s.str();
  }
  s << hf->cols() << ' ' << hf->rows() << ' ' << hf->noDataFraction();
  if (const auto range = hf->heightRange()) s << ' ' << range->first << ' ' << range->second;
  s << '\n';
  return s.str();
}

/// Temporary folders of imports that never finished (a process killed meanwhile) go after this.
constexpr auto kStaleTemporaryAge = std::chrono::hours(24);

/// Removes the least recently used entries (folders) beyond kMaxTerrainCacheEntries - 1, making room
/// for one more.
void prune(const fs::path& folder) {
  std::error_code ec;
  std::vector<std::pair<fs::file_time_type, fs::path>> entries;
  const auto now = fs::file_time_type::clock::now();
  for (const auto& e : fs::directory_iterator(folder, ec)) {
    if (!e.is_directory(ec)) continue;
    const fs::file_time_type written = fs::last_write_time(e.path(), ec);
    if (e.path().filename().string().front() == '.') {
      if (now - written > kStaleTemporaryAge) fs::remove_all(e.path(), ec);
      continue;
    }
    entries.emplace_back(written, e.path());
  }
  if (entries.size() < std::size_t(kMaxTerrainCacheEntries)) return;
  std::sort(entries.begin(), entries.end());
  for (std::size_t i = 0; i + std::size_t(kMaxTerrainCacheEntries) <= entries.size(); ++i)
    fs::remove_all(entries[i].second, ec);
}

/// The entry's pyramid when its source matches and it opens, else null.
std::shared_ptr<const terrain::TerrainPyramid> openEntry(const fs::path& entry, const std::string& source) {
  std::ifstream in(entry / "source");
  std::ostringstream s;
  s << in.rdbuf();
  if (!in || s.str() != source) return nullptr;
  try {
    return std::make_shared<const terrain::TerrainPyramid>((entry / "terrain.tif").string());
  } catch (const std::exception&) {
    return nullptr;
  }
}

}  // namespace

std::string terrainCacheFolder() { return cacheFolder("NESTWALK_TERRAIN_CACHE", "terrain"); }

std::shared_ptr<const terrain::TerrainPyramid> cachedTerrainPyramid(const std::string& demPath,
                                                                    const terrain::Heightfield* hf,
                                                                    const std::function<void(const std::string&)>& note) {
  const std::string folder = terrainCacheFolder();
  if (folder.empty()) return nullptr;
  // A valid sample at the terrain files' nodata value would become a hole in the import.
  if (const auto range = hf ? hf->heightRange() : std::nullopt;
      range && range->first <= terrain::kTerrainNoData && terrain::kTerrainNoData <= range->second)
    return nullptr;
  std::pair<int, int> size;
  std::string header;
  try {
    size = hf ? std::make_pair(hf->cols(), hf->rows()) : terrain::rasterSize(demPath);
    if (!hf) header = terrain::rasterHeaderText(demPath);
  } catch (const std::exception&) {
    return nullptr;
  }
  std::error_code ec;
  const std::string canonical = fs::weakly_canonical(fs::absolute(demPath, ec), ec).string();
  const std::optional<ModelFileIdentity> before = modelFileIdentity(demPath);
  if (ec || !before) return nullptr;
  char name[32];
  std::snprintf(name, sizeof name, "%016llx", static_cast<unsigned long long>(std::hash<std::string>{}(canonical)));
  const fs::path entry = fs::path(folder) / name;
  const std::string source = sourceText(canonical, *before, hf, size, header);
  std::shared_ptr<const terrain::TerrainPyramid> pyramid = openEntry(entry, source);
  if (!pyramid) {
    try {
      fs::create_directories(folder, ec);
      if (ec) return nullptr;
      prune(folder);
      if (note) note(demPath + ": importing it once into the terrain cache (" + entry.string() + ")");
      OutputFolder out(entry.string());
      terrain::ImportOptions importing;
      importing.progress = !hf;  // a survey-size DEM takes minutes: GDAL's progress line on stderr
      terrain::importTerrain(demPath, (fs::path(out.tempPath()) / "terrain.tif").string(), importing);
      if (!(modelFileIdentity(demPath) == before)) return nullptr;  // changed while it was imported
      writeFileAtomically((fs::path(out.tempPath()) / "source").string(), source);
      out.commit();
      pyramid = openEntry(entry, source);
    } catch (const std::exception&) {
      return nullptr;  // best effort: the scene loads without a pyramid
    }
  }
  if (!pyramid || pyramid->layout().cols != size.first || pyramid->layout().rows != size.second) return nullptr;
  fs::last_write_time(entry, fs::file_time_type::clock::now(), ec);  // used: the last to go
  return pyramid;
}

std::string cachedImagery(const std::string& imageryPath, const std::string& terrainCrsWkt,
                          const std::function<void(const std::string&)>& note) {
  if (terrain::imageryReadyToDrape(imageryPath, terrainCrsWkt)) return imageryPath;
  const std::string folder = terrainCacheFolder();
  if (folder.empty()) return imageryPath;
  std::error_code ec;
  const std::string canonical = fs::weakly_canonical(fs::absolute(imageryPath, ec), ec).string();
  const std::optional<ModelFileIdentity> before = modelFileIdentity(imageryPath);
  if (ec || !before) return imageryPath;
  char name[40];
  std::snprintf(name, sizeof name, "imagery-%016llx",
                static_cast<unsigned long long>(std::hash<std::string>{}(canonical)));
  const fs::path entry = fs::path(folder) / name;
  std::ostringstream sourceStream;
  sourceStream << before->size << ' ' << before->mtimeNs << ' ' << before->inode << ' ' << before->device << '\n'
               << canonical << '\n'
               << terrainCrsWkt << '\n';
  const std::string source = sourceStream.str();
  const fs::path imported = entry / "imagery.tif";
  {
    std::ifstream in(entry / "source");
    std::ostringstream s;
    s << in.rdbuf();
    if (in && s.str() == source && fs::is_regular_file(imported, ec)) {
      fs::last_write_time(entry, fs::file_time_type::clock::now(), ec);  // used: the last to go
      return imported.string();
    }
  }
  try {
    fs::create_directories(folder, ec);
    if (ec) return imageryPath;
    prune(folder);
    if (note) note(imageryPath + ": importing it once into the terrain cache to drape it (" + entry.string() + ")");
    OutputFolder out(entry.string());
    terrain::importImagery(imageryPath, (fs::path(out.tempPath()) / "imagery.tif").string(), terrainCrsWkt, false, true);
    if (!(modelFileIdentity(imageryPath) == before)) return imageryPath;  // changed while it was imported
    writeFileAtomically((fs::path(out.tempPath()) / "source").string(), source);
    out.commit();
    return imported.string();
  } catch (const std::exception&) {
    return imageryPath;  // best effort: drawn from the file itself
  }
}

}  // namespace nestwalk
