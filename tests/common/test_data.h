// Where the tests find data they do not make themselves: the shared real data (../shared/data
// beside the checkout: DEMs and models, some not redistributable, never copied into the project)
// and the bundled scene the build generates. A test whose data is absent skips and says so.
#pragma once

#include "tests/common/build_paths.h"
#include <cstdlib>
#include <filesystem>
#include <string>

namespace nestwalk::test {

/// The shared real data folder: the environment variable NESTWALK_SHARED_DATA, else the
/// default beside the checkout (build_paths.h); empty when it is absent.
inline std::filesystem::path sharedData() {
  const char* env = std::getenv("NESTWALK_SHARED_DATA");
  const std::filesystem::path p = env && *env ? env : nestwalk::test::build::sharedDataDir();
  return std::filesystem::is_directory(p) ? p : std::filesystem::path();
}

/// The bundled mining-dump scene's folder (scene.json, models/, scripts/): the environment
/// variable NESTWALK_BUNDLED_SCENE, else where the build generates it (build_paths.h).
/// It may be absent: callers check and skip ("build the bundled_scene target").
inline std::filesystem::path bundledSceneFolder() {
  const char* env = std::getenv("NESTWALK_BUNDLED_SCENE");
  return env && *env ? std::filesystem::path(env) : std::filesystem::path(nestwalk::test::build::bundledSceneDir());
}
inline std::filesystem::path bundledSceneFile() { return bundledSceneFolder() / "scene.json"; }
/// A bundled flythrough, by file name ("bench_patrol.txt").
inline std::filesystem::path bundledScript(const std::string& name) { return bundledSceneFolder() / "scripts" / name; }

/// The bundled weather station model (OBJ, metres, foot at the origin), from the source tree.
inline std::string weatherStation() { return std::string(nestwalk::test::build::sourceDir()) + "/assets/models/weather_station.obj"; }

}  // namespace nestwalk::test
