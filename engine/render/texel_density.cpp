#include "nestwalk/render/texel_density.h"

#include "nestwalk/render/imagery_tiles.h"
#include "nestwalk/render/paged_terrain.h"
#include "nestwalk/render/view_graph.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

namespace nestwalk {

void sampleTexelsPerPixel(const ViewRenderer& renderer, const terrain::Heightfield& terrain, int pixelStep,
                          TexelsPerPixel& into) {
  if (pixelStep < 1) throw std::invalid_argument("sampleTexelsPerPixel: pixelStep must be at least 1");
  const PagedTerrain& paged = renderer.graph().pagedTerrain();
  const ImageryTiles* tiles = paged.imageryTiles();
  if (!tiles) return;
  const int w = renderer.image().s(), h = renderer.image().t();
  const Eigen::Vector3d origin0(terrain.origin().x(), terrain.origin().y(), 0.0);
  auto ground = [&](int x, int y) -> std::optional<Eigen::Vector3d> {  // mesh frame
    if (x < 0 || y < 0 || x >= w || y >= h) return std::nullopt;
    const auto [origin, dir] = renderer.pixelRay(x + 0.5, y + 0.5);
    if (const auto hit = terrain.intersectRay(origin, dir)) return origin + hit->t * dir - origin0;
    return std::nullopt;
  };
  // The drawn parts' areas (mesh frame) and their tiles' texels.
  struct Area {
    double x0, x1, y0, y1, texelX, texelY;
  };
  std::vector<Area> areas;
  const double cells = paged.layout().chunkCells();
  for (const DrawnPart& part : paged.drawnParts()) {
    const double sx = cells * std::ldexp(terrain.dx(), part.key.level - 1);
    const double sy = cells * std::ldexp(terrain.dy(), part.key.level - 1);
    const double ax = (2 * part.key.x + (part.quadrant & 1)) * sx, ay = (2 * part.key.y + (part.quadrant >> 1)) * sy;
    const double texelX = tiles->texelSize(part.imageryDrawn.texelLevel);
    areas.push_back({ax, ax + sx, ay, ay + sy, texelX, texelX * terrain.dy() / terrain.dx()});
  }
  const auto [eyeMap, unused] = renderer.pixelRay(0.5 * w, 0.5 * h);
  const Eigen::Vector3d eye = eyeMap - origin0;
  for (int y = pixelStep / 2; y < h; y += pixelStep)
    for (int x = pixelStep / 2; x < w; x += pixelStep) {
      const std::optional<Eigen::Vector3d> p = ground(x, y);
      if (!p) continue;
      const auto area = std::find_if(areas.begin(), areas.end(), [&](const Area& a) {
        return p->x() >= a.x0 && p->x() <= a.x1 && -p->y() >= a.y0 && -p->y() <= a.y1;
      });
      if (area == areas.end()) continue;
      // The texture coordinates are the map's x and y (chunk_node.h), so a step counts the texels
      // it crosses horizontally.
      auto texels = [&](const Eigen::Vector3d& q) { return std::hypot((q.x() - p->x()) / area->texelX, (q.y() - p->y()) / area->texelY); };
      double perPixel = 0;
      for (int axis = 0; axis < 2 && std::isfinite(perPixel); ++axis) {
        double step = std::numeric_limits<double>::infinity();
        for (int s : {-1, 1})
          if (const auto q = axis == 0 ? ground(x + s, y) : ground(x, y + s)) step = std::min(step, texels(*q));
        perPixel = std::max(perPixel, step);
      }
      if (!std::isfinite(perPixel)) continue;
      const double distance = (*p - eye).norm();
      (distance < kTexelNearM ? into.near : distance < kTexelFarM ? into.middle : into.far).push_back(perPixel);
    }
}

}  // namespace nestwalk
