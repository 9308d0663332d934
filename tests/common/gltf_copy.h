// glTF copies of model files made by a second, independent glTF writer (assimp's exporter, Debian's
// assimp-utils), for checking nestwalk's glTF reader against the original file read by OSG's
// plugins: the same triangles and volumes. Formats assimp reads (OBJ, 3DS) are exported directly;
// OSG's own formats (.osgt, .osgb) go through OSG's OBJ writer (osgconv) first, without materials.
// Images beside the model are copied beside the copy, which refers to them by name as the original
// does. Each reader keeps its own axis convention (assimp turns a 3DS file y-up, OSG's OBJ reader
// turns an OBJ z-up): a copy holds the original's points under a signed permutation of the axes.
#pragma once

#include "tests/common/run_command.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace nestwalk::test {

/// The .glb copy of `model` written into `folder`; empty (with a test failure saying why) when a
/// tool is missing or fails.
inline std::filesystem::path gltfCopy(const std::filesystem::path& model, const std::filesystem::path& folder) {
  namespace fs = std::filesystem;
  if (runCommand("command -v assimp").exitCode != 0) {
    ADD_FAILURE() << "assimp is not installed (Debian's assimp-utils; tools/setup-deps.sh installs it)";
    return {};
  }
  for (const auto& e : fs::directory_iterator(model.parent_path())) {
    const std::string ext = e.path().extension().string();
    if (ext == ".jpg" || ext == ".png" || ext == ".JPG" || ext == ".PNG")
      fs::copy_file(e.path(), folder / e.path().filename(), fs::copy_options::overwrite_existing);
  }
  fs::path source = model;
  const std::string ext = model.extension().string();
  if (ext == ".osgt" || ext == ".osgb" || ext == ".ive") {
    source = folder / (model.stem().string() + ".obj");
    const CommandResult c = runCommand("osgconv " + quoted(model) + " " + quoted(source));
    if (c.exitCode != 0) {
      ADD_FAILURE() << "osgconv " << model << " failed: " << c.err;
      return {};
    }
    // Without its materials: an image embedded in OSG's format (the street lamp's DDS) is one no
    // glTF reader decodes, and the check is of geometry.
    fs::remove(folder / (model.stem().string() + ".mtl"));
  }
  const fs::path copy = folder / (model.stem().string() + ".glb");
  const CommandResult c = runCommand("assimp export " + quoted(source) + " " + quoted(copy) + " -fglb2");
  if (c.exitCode != 0 || !fs::exists(copy)) {
    ADD_FAILURE() << "assimp export " << source << " failed: " << c.out << c.err;
    return {};
  }
  return copy;
}

}  // namespace nestwalk::test
