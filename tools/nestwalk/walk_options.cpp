// Options shared by the commands that walk a scene (walk_options.h).
#include "tools/nestwalk/walk_options.h"

#include "nestwalk/core/input_error.h"

#include <cstdio>

namespace nestwalk::tools {

std::pair<int, int> parseFrameSize(const std::string& text) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w < 16 ||
      h < 16 || w > 8192 || h > 8192)
    throw InputError("--size: expected WIDTHxHEIGHT between 16 and 8192 pixels, e.g. 1280x720, got '" + text + "'");
  return {w, h};
}

MethodSpec applyMethodOverrides(const MethodOverrides& a, MethodSpec m) {
  if (!a.volumes.empty()) {
    if (!parseVolumeMethod(a.volumes, m.volumes))
      throw InputError("--method: expected nested, aabb, obb, nested+mesh, kdop18 or auto, got '" + a.volumes + "'");
  }
  if (!a.hierarchy.empty()) {
    if (a.hierarchy == "template") m.templateHierarchy = true;
    else if (a.hierarchy == "auto") m.templateHierarchy = false;
    else throw InputError("--hierarchy: expected auto or template, got '" + a.hierarchy + "'");
  }
  if (a.degree != 0) m.autoTree.degree = a.degree;
  if (!a.splitAxis.empty()) {
    if (a.splitAxis == "longest") m.autoTree.axis = SplitAxis::LongestSide;
    else if (a.splitAxis == "splatter") m.autoTree.axis = SplitAxis::Splatter;
    else throw InputError("--split-axis: expected longest or splatter, got '" + a.splitAxis + "'");
  }
  if (!a.splitPoint.empty()) {
    if (a.splitPoint == "mean") m.autoTree.point = SplitPoint::Mean;
    else if (a.splitPoint == "median") m.autoTree.point = SplitPoint::Median;
    else throw InputError("--split-point: expected mean or median, got '" + a.splitPoint + "'");
  }
  return m;
}

void addTerrainOptions(CLI::App& cmd, TerrainArgs& args, const char* defaultLoading) {
  cmd.add_option("--terrain-loading", args.loading,
                 std::string("Terrain chunks: background (frames never wait; coarser until loaded) or complete (each "
                             "frame waits for its chunks); default ") + defaultLoading);
  cmd.add_option("--terrain-budget", args.budgetMiB,
                 "Terrain cache budget in MiB (default: a sixteenth of the memory, 256 to 1024)")
      ->check(CLI::Range(1.0, 1048576.0));
}

void applyTerrainArgs(const TerrainArgs& args, RenderOptions& options) {
  if (args.loading == "background") options.terrainLoading = TerrainLoading::Background;
  else if (args.loading == "complete") options.terrainLoading = TerrainLoading::Complete;
  else if (!args.loading.empty())
    throw InputError("--terrain-loading: expected background or complete, got '" + args.loading + "'");
  if (args.budgetMiB > 0) options.terrainBudgetBytes = std::size_t(args.budgetMiB * 1024 * 1024);
}

}  // namespace nestwalk::tools
