// The renderer's depth range and haze (view_depth.h).
#include "nestwalk/render/view_depth.h"

#include "nestwalk/terrain/heightfield.h"

#include <algorithm>
#include <cmath>

namespace nestwalk {

ViewDepth viewDepth(const Scene& scene) {
  ViewDepth d;
  const Eigen::Vector3d& body = scene.spec.viewer.bodyHalfExtents;
  d.nearM = std::clamp(0.5 * std::min(body.x(), body.y()), 0.05, 0.5);
  const terrain::Heightfield& hf = *scene.terrain;
  d.farM = 1.5 * std::hypot(hf.cols() * hf.dx(), hf.rows() * hf.dy()) + 1000.0;
  d.hazeStartM = std::min(1500.0, 0.3 * d.farM);
  d.hazeEndM = d.farM;
  return d;
}

}  // namespace nestwalk
