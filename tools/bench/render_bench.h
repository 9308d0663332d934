// The rendering benchmark (`nestwalk bench render`, issue 5): the bundled scene rendered offscreen
// (software OpenGL where there is no GPU) along its flythroughs, the walker's view at the poses
// the walker takes. Per configuration: median and p95 ms per frame, split into cull, draw and
// readback, triangles drawn and the terrain's vertical error on screen. Configurations: the
// default (terrain LOD at 1 px of error, nested culling), the same with OSG's bounding-sphere
// culling, the terrain at full resolution (no LOD: error 0) and LOD at 0.5, 2 and 4 px (speed
// against error). The view culling itself is compared on the same frames: instances kept and µs
// per frame for the nested volumes and for OSG's spheres. Target: 30 frames per second.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace nestwalk::bench {

struct RenderBenchOptions {
  bool json = false;
  bool quick = false;                // 320 x 180, a few frames per flythrough, two configurations
  int width = 1280, height = 720;
  int framesPerScript = 120;         // poses sampled evenly along each flythrough
  std::string scene;                 // scene file
  std::vector<std::string> scripts;  // its flythroughs
};

int runRenderBench(const RenderBenchOptions& opts, std::ostream& out);

}  // namespace nestwalk::bench
