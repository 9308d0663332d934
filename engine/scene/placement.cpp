#include "nestwalk/scene/placement.h"

#include "nestwalk/geometry/convex_hull.h"

namespace nestwalk {

std::vector<Eigen::Vector2d> footprintOutline(const Eigen::Vector3d& origin, const Similarity<double>& toLocal,
                                              const std::vector<Vec3<double>>& hull) {
  std::vector<Eigen::Vector2d> xy;
  xy.reserve(hull.size());
  for (const Vec3<double>& p : hull) xy.push_back((toLocal.apply(p) + origin).head<2>());
  std::vector<Eigen::Vector2d> outline;
  for (int k : convexHull2d(xy)) outline.push_back(xy[std::size_t(k)]);
  if (outline.empty()) outline.push_back((toLocal.translation + origin).head<2>());
  return outline;
}

terrain::GroundSpan groundUnderFootprint(const terrain::Heightfield& hf, const Eigen::Vector3d& origin,
                                         const Similarity<double>& toLocal, const std::vector<Vec3<double>>& hull) {
  return terrain::groundUnderPolygon(hf, footprintOutline(origin, toLocal, hull));
}

}  // namespace nestwalk
