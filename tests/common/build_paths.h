// Where this build keeps what the tests read or run: the shared real data folder, the source tree,
// the `nestwalk` program and the scenes the build generates. Absolute paths of one checkout and
// one build folder.
//
// Defined in one file the build generates (tests/common/build_paths.cpp.in), not as compile
// definitions of every test source: a path on a compiler's command line makes that command differ
// from one checkout to the next, so the compiler cache (ccache, tools/build.sh) could not serve a
// clean clone in another folder. Here only build_paths.cpp differs.
#pragma once

namespace nestwalk::test::build {

/// ../shared/data beside the checkout (it may be absent; test_data.h checks).
const char* sharedDataDir();
/// The checkout's root (assets/models/... are read from it).
const char* sourceDir();
/// This build's `nestwalk` program.
const char* nestwalkProgram();
/// The bundled mining-dump scene the build generates (scene.json, models/, scripts/).
const char* bundledSceneDir();
/// The GIS sample scene build-scene makes, and the inputs it is made from.
const char* gisSceneDir();
const char* gisInputsDir();

}  // namespace nestwalk::test::build
