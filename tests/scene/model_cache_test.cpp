// The validated-model cache (scene/model_cache.h): an entry is used only for the file it was made
// from, as it was (a file rewritten, even to the same size, is read again), and only when intact
// (an entry cut short or with a flipped byte is never handed to OSG's reader: it is what would
// hang it); the cache being off or unwritable changes nothing but speed; a model read twice
// through readModelFile is served from its entry the second time, with the same geometry.
#include "nestwalk/scene/model_cache.h"

#include "nestwalk/scene/model_file.h"
#include "nestwalk/scene/node_geometry.h"
#include "tests/common/temp_folder.h"
#include "tests/common/test_data.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;

/// Sets NESTWALK_MODEL_CACHE for the scope, and restores it.
class CacheFolder {
 public:
  explicit CacheFolder(const std::string& value) {
    if (const char* old = std::getenv("NESTWALK_MODEL_CACHE")) saved_ = old;
    ::setenv("NESTWALK_MODEL_CACHE", value.c_str(), 1);
  }
  ~CacheFolder() {
    if (saved_) ::setenv("NESTWALK_MODEL_CACHE", saved_->c_str(), 1);
    else ::unsetenv("NESTWALK_MODEL_CACHE");
  }

 private:
  std::optional<std::string> saved_;
};

fs::path onlyEntry(const fs::path& folder) {
  fs::path found;
  for (const auto& e : fs::directory_iterator(folder)) {
    EXPECT_TRUE(found.empty()) << "more than one entry";
    found = e.path();
  }
  return found;
}

TEST(ModelCache, EntryServesOnlyTheFileAsItWas) {
  const test::TempFolder folder;
  const CacheFolder cache((folder / "cache").string());
  const fs::path model = folder / "m.osgt";
  test::writeText(model, "first version");
  EXPECT_FALSE(cachedModel(model.string()));
  storeCachedModel(model.string(), *modelFileIdentity(model.string()), "osgb bytes of the first version");
  EXPECT_EQ(cachedModel(model.string()).value_or(""), "osgb bytes of the first version");
  // Another path, even to the same content, has no entry.
  fs::copy_file(model, folder / "copy.osgt");
  EXPECT_FALSE(cachedModel((folder / "copy.osgt").string()));
  // Rewritten to the same size: its modification time changed, the entry no longer serves it.
  std::this_thread::sleep_for(std::chrono::milliseconds(5));
  test::writeText(model, "other version");
  EXPECT_FALSE(cachedModel(model.string()));
  // Storing again replaces the entry (one entry per path).
  storeCachedModel(model.string(), *modelFileIdentity(model.string()), "osgb bytes of the other version");
  EXPECT_EQ(cachedModel(model.string()).value_or(""), "osgb bytes of the other version");
  onlyEntry(folder / "cache");
}

TEST(ModelCache, AFileChangedDuringItsReadIsNotFiled) {
  const test::TempFolder folder;
  const CacheFolder cache((folder / "cache").string());
  const fs::path model = folder / "m.osgt";
  test::writeText(model, "version read");
  const ModelFileIdentity before = *modelFileIdentity(model.string());
  std::this_thread::sleep_for(std::chrono::milliseconds(5));
  test::writeText(model, "version written meanwhile");  // changed while the guard read it
  storeCachedModel(model.string(), before, "osgb bytes of the version read");
  EXPECT_FALSE(cachedModel(model.string()));
}

TEST(ModelCache, DamagedEntriesAreNeverUsed) {
  const test::TempFolder folder;
  const CacheFolder cache((folder / "cache").string());
  const fs::path model = folder / "m.osgt";
  test::writeText(model, "model");
  const std::string bytes(100000, 'b');
  storeCachedModel(model.string(), *modelFileIdentity(model.string()), bytes);
  const fs::path entry = onlyEntry(folder / "cache");
  std::ifstream in(entry, std::ios::binary);
  const std::string whole{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  in.close();
  auto rewrite = [&](const std::string& content) {
    std::ofstream out(entry, std::ios::binary | std::ios::trunc);
    out << content;
  };
  rewrite(whole.substr(0, whole.size() / 2));  // cut short
  EXPECT_FALSE(cachedModel(model.string()));
  std::string flipped = whole;
  flipped[whole.size() - 10] ^= 0x20;  // one byte of the body
  rewrite(flipped);
  EXPECT_FALSE(cachedModel(model.string()));
  rewrite(whole + "x");  // longer than its header says
  EXPECT_FALSE(cachedModel(model.string()));
  rewrite(whole);
  EXPECT_EQ(cachedModel(model.string()).value_or(""), bytes);
}

TEST(ModelCache, OffOrUnwritableChangesNothingButSpeed) {
  const test::TempFolder folder;
  const fs::path model = folder / "m.osgt";
  test::writeText(model, "model");
  {
    const CacheFolder off("off");
    EXPECT_EQ(modelCacheFolder(), "");
    storeCachedModel(model.string(), *modelFileIdentity(model.string()), "bytes");
    EXPECT_FALSE(cachedModel(model.string()));
  }
  // A cache "folder" that is a file: nothing can be stored, nothing fails.
  test::writeText(folder / "not_a_folder", "");
  const CacheFolder blocked((folder / "not_a_folder" / "cache").string());
  storeCachedModel(model.string(), *modelFileIdentity(model.string()), "bytes");
  EXPECT_FALSE(cachedModel(model.string()));
}

TEST(ModelCache, SecondReadComesFromTheEntryWithTheSameGeometry) {
  const fs::path source = test::bundledSceneFolder() / "models" / "pickup.osgt";
  if (!fs::exists(source)) GTEST_SKIP() << source << " is absent: build the bundled_scene target";
  const test::TempFolder folder;
  const CacheFolder cache((folder / "cache").string());
  const fs::path model = folder / "pickup.osgt";
  fs::copy_file(source, model);
  const ModelFile first = readModelFile(model.string());
  ASSERT_TRUE(first.node) << first.problem;
  ASSERT_TRUE(cachedModel(model.string()));
  // Served from the entry: it is read even with no time at all left for a guarded read.
  ProcessLimits none;
  none.seconds = 1e-9;
  const ModelFile second = readModelFile(model.string(), none);
  ASSERT_TRUE(second.node) << second.problem;
  const TriangleMesh a = collectModelGeometry(*first.node, "first"), b = collectModelGeometry(*second.node, "second");
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.triangles, b.triangles);
  const ModelFile direct = readModelFileUnguarded(model.string());
  EXPECT_EQ(collectModelGeometry(*direct.node, "direct").vertices, a.vertices);
}

TEST(ModelCache, EntriesStayBounded) {
  // 1100 models stored: past 1000 entries the older half goes, so the folder never holds more
  // than 1001, and the newest entry is always there.
  const test::TempFolder folder;
  const CacheFolder cache((folder / "cache").string());
  fs::create_directories(folder / "models");
  for (int i = 0; i < 1100; ++i) {
    const fs::path m = folder / "models" / ("m" + std::to_string(i) + ".osgt");
    test::writeText(m, "model " + std::to_string(i));
    storeCachedModel(m.string(), *modelFileIdentity(m.string()), "bytes " + std::to_string(i));
    ASSERT_EQ(cachedModel(m.string()).value_or(""), "bytes " + std::to_string(i));
  }
  std::size_t entries = 0;
  for (const auto& e : fs::directory_iterator(folder / "cache")) entries += e.path().extension() == ".osgbc";
  EXPECT_LE(entries, 1001u);
  EXPECT_GE(entries, 500u);
}

}  // namespace
}  // namespace nestwalk
