// The validated-model cache (model_cache.h).
#include "nestwalk/scene/model_cache.h"

#include "nestwalk/core/output_file.h"
#include "nestwalk/scene/cache_folder.h"

#include <sys/stat.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;

/// The first bytes of an entry; the version changes when the layout does.
constexpr char kMagic[8] = {'N', 'W', 'M', 'C', 'A', 'C', 'H', '1'};

/// Entries kept at most; past it, storing an entry first removes the oldest half (by the time
/// they were written). Models in temporary folders (tests, scratch scenes) leave entries that are
/// never used again; this bounds them (at a few MB per hundred models).
constexpr std::size_t kMaxEntries = 1000;

/// Removes the older half of the entries when there are more than kMaxEntries.
void prune(const fs::path& folder) {
  std::error_code ec;
  std::vector<std::pair<fs::file_time_type, fs::path>> entries;
  for (const auto& e : fs::directory_iterator(folder, ec))
    if (e.path().extension() == ".osgbc") entries.emplace_back(e.last_write_time(ec), e.path());
  if (entries.size() <= kMaxEntries) return;
  std::sort(entries.begin(), entries.end());
  for (std::size_t i = 0; i < entries.size() / 2; ++i) fs::remove(entries[i].second, ec);
}

using Identity = ModelFileIdentity;

struct Header {
  char magic[8];
  Identity source;
  std::uint64_t length;    // bytes of .osgb after the header
  std::uint64_t checksum;  // of those bytes
};

}  // namespace

std::optional<ModelFileIdentity> modelFileIdentity(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return std::nullopt;
  return Identity{std::uint64_t(st.st_size), std::uint64_t(st.st_mtim.tv_sec) * 1'000'000'000ull + std::uint64_t(st.st_mtim.tv_nsec),
                  std::uint64_t(st.st_ino), std::uint64_t(st.st_dev)};
}

namespace {

std::uint64_t checksumOf(std::string_view bytes) { return std::hash<std::string_view>{}(bytes); }

/// The entry's file for `path`: a hash of its canonical path.
std::optional<fs::path> entryOf(const std::string& path) {
  const std::string folder = modelCacheFolder();
  if (folder.empty()) return std::nullopt;
  std::error_code ec;
  const fs::path canonical = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec) return std::nullopt;
  char name[32];
  std::snprintf(name, sizeof name, "%016llx.osgbc",
                static_cast<unsigned long long>(std::hash<std::string>{}(canonical.string())));
  return fs::path(folder) / name;
}

}  // namespace

std::string modelCacheFolder() { return cacheFolder("NESTWALK_MODEL_CACHE", "models"); }

std::optional<std::string> cachedModel(const std::string& path) {
  const std::optional<fs::path> entry = entryOf(path);
  const std::optional<Identity> source = modelFileIdentity(path);
  if (!entry || !source) return std::nullopt;
  std::ifstream in(*entry, std::ios::binary);
  Header h{};
  if (!in.read(reinterpret_cast<char*>(&h), sizeof h)) return std::nullopt;
  if (std::memcmp(h.magic, kMagic, sizeof kMagic) != 0 || !(h.source == *source)) return std::nullopt;
  std::error_code ec;
  if (fs::file_size(*entry, ec) != sizeof h + h.length || ec) return std::nullopt;  // cut short on disk
  std::string bytes(h.length, '\0');
  if (!in.read(bytes.data(), std::streamsize(h.length)) || checksumOf(bytes) != h.checksum) return std::nullopt;
  return bytes;
}

void storeCachedModel(const std::string& path, const ModelFileIdentity& before, const std::string& osgbBytes) {
  const std::optional<fs::path> entry = entryOf(path);
  const std::optional<Identity> source = modelFileIdentity(path);
  if (!entry || !source || !(*source == before)) return;  // changed while it was read
  std::error_code ec;
  fs::create_directories(entry->parent_path(), ec);
  if (ec) return;
  prune(entry->parent_path());
  Header h{};
  std::memcpy(h.magic, kMagic, sizeof kMagic);
  h.source = *source;
  h.length = osgbBytes.size();
  h.checksum = checksumOf(osgbBytes);
  try {
    std::string content(reinterpret_cast<const char*>(&h), sizeof h);
    content += osgbBytes;
    writeFileAtomically(entry->string(), content);
  } catch (const std::exception&) {
    // best effort: the model was read; the next load reads it under the guard again
  }
}

}  // namespace nestwalk
