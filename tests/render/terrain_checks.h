// Independent checks shared by the terrain rendering tests: the brute-force projected error of a
// chunk over a fine sample range, and the sky pixels of an ID frame below the terrain's silhouette;
// and the views the cull tests look from.
#pragma once

#include "nestwalk/render/paged_terrain.h"
#include "nestwalk/render/view_graph.h"
#include "nestwalk/render/view_renderer.h"
#include "nestwalk/terrain/heightfield.h"
#include "nestwalk/terrain/terrain_chunk.h"

#include <osg/Image>
#include <osg/Matrixd>
#include <osg/Vec3d>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>

namespace nestwalk::test {

/// A camera for a cull traversal: view and projection matrices (60 degrees, 16:9) and the eye.
struct View {
  osg::Matrixd view, projection;
  osg::Vec3d eye;
};

inline View viewFrom(const osg::Vec3d& eye, const osg::Vec3d& at) {
  return {osg::Matrixd::lookAt(eye, at, osg::Vec3d(0, 0, 1)), osg::Matrixd::perspective(60.0, 16.0 / 9.0, 0.5, 5000.0),
          eye};
}

/// The largest projected error of a chunk's grid surface over fine columns [c0, c1] and rows
/// [r0, r1], by brute force: at every fine sample, |fine - coarse| * pixelsPerRadian / distance from
/// the eye to the coarse surface point there (the surfaces' difference is largest at fine samples on
/// square cells: terrain_chunk.h).
inline double projectedPixels(const terrain::Heightfield& hf, const terrain::ChunkLayout& l,
                              const terrain::ChunkKey& k, int c0, int c1, int r0, int r1, const osg::Vec3d& eye,
                              double pixelsPerRadian) {
  double worst = 0;
  for (int r = r0; r <= r1; ++r)
    for (int c = c0; c <= c1; ++c) {
      if (!hf.valid(c, r)) continue;
      const double x = c * hf.dx(), y = -r * hf.dy();
      const std::optional<double> coarse = terrain::chunkHeightAt(hf, l, k, x, y);
      if (!coarse) continue;
      const double d = std::max((osg::Vec3d(x, y, *coarse) - eye).length(), kMinEyeDistanceM);
      worst = std::max(worst, std::abs(double(hf.sample(c, r)) - *coarse) * pixelsPerRadian / d);
    }
  return worst;
}

/// Sky pixels below the first terrain pixel of their column (rows from the top) in an ID frame.
/// Equipment does not count as a silhouette: sky under a lamp's arm is no crack.
inline std::size_t skyBelowSilhouette(const osg::Image& image) {
  std::size_t n = 0;
  for (int x = 0; x < image.s(); ++x) {
    bool seen = false;
    for (int y = 0; y < image.t(); ++y) {
      const std::uint32_t id = ViewRenderer::idAt(image, x, y);
      if (id == 1) seen = true;
      else if (id == 0 && seen) ++n;
    }
  }
  return n;
}

}  // namespace nestwalk::test
