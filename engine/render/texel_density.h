// Texels per pixel in a rendered frame: how finely the imagery tiles (imagery_tiles.h) are drawn
// against the screen, measured from the frame itself, not from the texel rule's boxes.
//
// At a pixel (x, y) of the last frame the ground point is the exact ray cast through the pixel's
// centre (Heightfield::intersectRay). Texels per pixel there is, as a GPU's derivatives measure a
// pixel's footprint, the larger over the screen's two axes of the step to the neighbouring pixel's
// ground point (on each axis the smaller of the two sides' steps, so that a step over a silhouette
// does not count), counted in texels of the tile the drawn part holding the ground point was drawn
// with (DrawnPart::imageryDrawn). Steps are horizontal: the texture coordinates are the map's x and
// y (chunk_node.h), so on a steep face a pixel crosses fewer texels than its ground distance.
// 1 is one of the tile's texels per pixel; below 1 the tile is magnified (the imagery holds no
// finer detail, or the tile is coarser than the view can show); above 1 several of its texels fall
// in a pixel: without mip levels they alias, with them (the default, imagery_tiles.h) the GL
// samples the level of the footprint instead (OpenGL 4.6, 8.14), so the value then says how much
// finer the tile is than the view needs there.
//
// Pixels are sampled every `pixelStep` pixels across and down and binned by the ground point's
// distance from the eye: near (< kTexelNearM), middle (< kTexelFarM), far.
//
// Cost: five ray casts a sampled pixel; for benchmarks and tests, not per frame.
#pragma once

#include "nestwalk/render/view_renderer.h"
#include "nestwalk/terrain/heightfield.h"

#include <vector>

namespace nestwalk {

/// Metres from the eye: the near band (a walker's surroundings, where the finest imagery shows) ends
/// here, the middle band (the next benches) at kTexelFarM.
inline constexpr double kTexelNearM = 20.0;
inline constexpr double kTexelFarM = 100.0;

/// Texels per pixel of the sampled pixels, by band (see above); appended to over frames.
struct TexelsPerPixel {
  std::vector<double> near, middle, far;
};

/// Samples the last frame of `renderer`, which draws `terrain` through its paged terrain with
/// imagery tiles, into `into`. Does nothing without imagery tiles. Throws std::invalid_argument
/// for pixelStep < 1.
void sampleTexelsPerPixel(const ViewRenderer& renderer, const terrain::Heightfield& terrain, int pixelStep,
                          TexelsPerPixel& into);

}  // namespace nestwalk
