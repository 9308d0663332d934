// The one way the program and the benchmarks find the bundled mining-dump scene and a scene's
// flythroughs, for every subcommand that defaults to them (report, bench walker, bench render).
#pragma once

#include <string>
#include <vector>

namespace nestwalk::assets {

/// The bundled scene's file: where the build generates it (the bundled_scene target).
std::string bundledSceneFile();

/// The flythrough scripts beside a scene file: its scripts/*.txt, sorted by name (the bundled
/// scene's three, or a user's own); empty when there are none.
std::vector<std::string> scriptsBeside(const std::string& sceneFile);

/// Fills in the defaults of a subcommand's SCENE and --scripts: the bundled scene when `scene` is
/// empty, its scripts/*.txt when `scripts` is empty. Throws InputError when the bundled scene is
/// absent ("build the bundled_scene target or give ...") or no script is found.
void defaultSceneAndScripts(std::string& scene, std::vector<std::string>& scripts);

}  // namespace nestwalk::assets
