// libccd's MPR as a peer of the bounding-volume benchmark (box_peers.h). No conversion: libccd
// takes the boxes as opaque objects through support and centre callbacks, here reading the
// nestwalk::Obb<double> itself (libccd is built with double ccd_real_t on Debian). The settings are
// FCL's for libccd.
#include "tools/bench/peers/box_peers.h"

#include <ccd/ccd.h>

#include <memory>

namespace nestwalk::bench {
namespace {

constexpr unsigned long kMaxIterations = 500;  // FCL's setting; MPR converges in far fewer on boxes
constexpr double kMprTolerance = 1e-6;         // m, FCL's setting: the portal's convergence distance

/// The support point of the box in direction `dir`: the corner furthest along it.
void boxSupport(const void* obj, const ccd_vec3_t* dir, ccd_vec3_t* out) {
  const Obb<double>& b = *static_cast<const Obb<double>*>(obj);
  const Vec3<double> d(dir->v[0], dir->v[1], dir->v[2]);
  Vec3<double> p = b.center;
  for (int k = 0; k < 3; ++k) p += (b.axes.col(k).dot(d) >= 0 ? b.halfExtents[k] : -b.halfExtents[k]) * b.axes.col(k);
  for (int k = 0; k < 3; ++k) out->v[k] = p[k];
}

void boxCenter(const void* obj, ccd_vec3_t* c) {
  const Obb<double>& b = *static_cast<const Obb<double>*>(obj);
  for (int k = 0; k < 3; ++k) c->v[k] = b.center[k];
}

}  // namespace

Pass<std::uint8_t> ccdBoxPairs(const std::vector<Obb<double>>& a, const std::vector<Obb<double>>& b) {
  auto ccd = std::make_shared<ccd_t>();
  CCD_INIT(ccd.get());
  ccd->support1 = ccd->support2 = boxSupport;
  ccd->center1 = ccd->center2 = boxCenter;
  ccd->max_iterations = kMaxIterations;
  ccd->mpr_tolerance = kMprTolerance;
  return [ccd, &a, &b](std::uint8_t* verdicts) {
    const ccd_t* settings = ccd.get();
    const std::vector<Obb<double>>&x = a, &y = b;
    return answerAll(x.size(), verdicts, [&](std::size_t k) { return ccdMPRIntersect(&x[k], &y[k], settings) != 0; });
  };
}

}  // namespace nestwalk::bench
