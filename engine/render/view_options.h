// What a view of the scene is asked to draw: the renderer's options (size, field of view, the
// terrain's error bound, loading and cache, shading, culling, overlays, the ID pass) and the
// walker's pose. The public vocabulary of rendering (view_renderer.h, view_graph.h), free of the
// drawing internals.
// Units: pixels, degrees, metres; the pose in the map frame.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <string>

namespace nestwalk {

// How the own quadtree loads chunks: on its loader thread while frames go on (Background), or every
// chunk a frame wants before it is drawn (Complete: for measurements and tests; paged_terrain.h).
enum class TerrainLoading { Background, Complete };
const char* terrainLoadingName(TerrainLoading l);  // "background", "complete"

struct RenderOptions {
  int width = 1280, height = 720;
  double fovYDegrees = 60.0;
  double lodMaxPixels = 1.0;     // terrain LOD: the largest vertical error allowed on screen, pixels
  int terrainChunkCells = 64;    // cells per terrain chunk side (power of two, paged_terrain.h)
  std::size_t terrainBudgetBytes = 0;  // the terrain cache's budget (0: defaultTerrainBudgetBytes())
  TerrainLoading terrainLoading = TerrainLoading::Background;  // paged_terrain.h
  bool terrainShading = true;    // Horn's hillshade in the terrain's colours where the scene asks for it (SceneSpec::hillshadeOn)
  /// Draped imagery: no texel finer than this, metres (0: the imagery's own pixel; the DEM's spacing
  /// gives a drape at the DEM's resolution, for comparisons: imagery_tiles.h).
  double imageryFinestTexelM = 0;
  /// Draped imagery: tiles carry mip levels built on the loader thread, so each pixel samples the
  /// level of its own footprint (imagery_tiles.h); false samples each tile's own texels alone.
  bool imageryMipmaps = true;
  bool nestedCulling = true;     // false: OSG's bounding-sphere culling decides alone
  bool volumes = false;          // outer AABBs (yellow) and inner OBBs (cyan) as wireframes
  bool blockedOverlay = true;    // a red frame and the blocker's name while blocked
  bool idPass = false;           // render IDs instead of colours (view_graph.h)
};

// Where the walker is and what it sees (map frame).
struct ViewPose {
  Eigen::Vector3d eye = Eigen::Vector3d::Zero();
  double headingDeg = 0, pitchDeg = 0;
  bool blocked = false;
  std::string blockedBy;
};

}  // namespace nestwalk
