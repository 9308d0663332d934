#include "assets/generators/bundled_scene.h"

#include "nestwalk/core/input_error.h"

#include <algorithm>
#include <filesystem>

namespace nestwalk::assets {

namespace fs = std::filesystem;

std::string bundledSceneFile() { return (fs::path(NESTWALK_BUNDLED_SCENE_DIR) / "scene.json").string(); }

std::vector<std::string> scriptsBeside(const std::string& sceneFile) {
  std::vector<std::string> found;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(fs::path(sceneFile).parent_path() / "scripts", ec))
    if (entry.is_regular_file() && entry.path().extension() == ".txt") found.push_back(entry.path().string());
  std::sort(found.begin(), found.end());
  return found;
}

void defaultSceneAndScripts(std::string& scene, std::vector<std::string>& scripts) {
  if (scene.empty()) {
    scene = bundledSceneFile();
    if (!fs::exists(scene))
      throw InputError(scene + ": the bundled scene is absent; build the bundled_scene target or give a scene");
  }
  if (scripts.empty()) scripts = scriptsBeside(scene);
  if (scripts.empty()) throw InputError(scene + ": no flythrough scripts in its scripts/ folder; give them with --scripts");
}

}  // namespace nestwalk::assets
