// Options shared by the commands that walk a scene (`run`, `view`): the frame size and the
// contact-method overrides of the scene's own. Errors are InputError naming the option.
#pragma once

#include "nestwalk/render/view_graph.h"
#include "nestwalk/scene/method_spec.h"

#include <CLI/CLI.hpp>

#include <string>
#include <utility>

namespace nestwalk::tools {

// WIDTHxHEIGHT, each 16 to 8192 pixels.
std::pair<int, int> parseFrameSize(const std::string& text);

// --method, --hierarchy, --degree, --split-axis, --split-point as given (empty or 0: the scene's).
struct MethodOverrides {
  std::string volumes, hierarchy, splitAxis, splitPoint;
  int degree = 0;
};
MethodSpec applyMethodOverrides(const MethodOverrides& o, MethodSpec m);

// --terrain-loading and --terrain-budget: how the paged terrain loads its chunks and how much memory
// its cache may hold (render/paged_terrain.h).
struct TerrainArgs {
  std::string loading;      // background or complete (empty: the command's default)
  double budgetMiB = 0;     // 0: defaultTerrainBudgetBytes()
};
void addTerrainOptions(CLI::App& cmd, TerrainArgs& args, const char* defaultLoading);
// Into the render options; InputError naming the option for a bad value.
void applyTerrainArgs(const TerrainArgs& args, RenderOptions& options);

}  // namespace nestwalk::tools
