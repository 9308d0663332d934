// The Khronos glTF Validator (npm gltf-validator, pinned in tools/web/package.json and installed by
// tools/setup-deps.sh) run on a file through tools/web/validate_gltf.mjs: its report as JSON
// ({"errors", "warnings", "messages", "info"}), or a test failure saying what is missing.
#pragma once

#include "tests/common/build_paths.h"
#include "tests/common/run_command.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace nestwalk::test {

inline nlohmann::json validateGltf(const std::filesystem::path& file) {
  const std::filesystem::path web = std::filesystem::path(build::sourceDir()) / "tools" / "web";
  if (!std::filesystem::exists(web / "node_modules" / "gltf-validator")) {
    ADD_FAILURE() << "the glTF validator is not installed in " << web << " (tools/setup-deps.sh runs npm ci there)";
    return {};
  }
  const CommandResult r = runCommand("node " + quoted(web / "validate_gltf.mjs") + " " + quoted(file));
  if (r.exitCode != 0 && r.exitCode != 1) {
    ADD_FAILURE() << "the glTF validator failed on " << file << ": " << r.err;
    return {};
  }
  return nlohmann::json::parse(r.out);
}

/// The JSON chunk of a .glb, parsed (the writer's structure, for the checks the reader does not show).
inline nlohmann::json glbJson(const std::string& bytes) {
  if (bytes.size() < 20) return {};
  std::uint32_t length = 0;
  for (int i = 3; i >= 0; --i)
    length = (length << 8) | static_cast<unsigned char>(bytes[12 + static_cast<std::size_t>(i)]);
  return nlohmann::json::parse(bytes.substr(20, length));
}

}  // namespace nestwalk::test
