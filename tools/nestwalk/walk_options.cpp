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

}  // namespace nestwalk::tools
