// Bullet as a peer of the terrain benchmark (terrain_peers.h): btHeightfieldTerrainShape over a
// copy of the float heights with the rows reversed (Bullet's row j is the grid's row n-1-j) and
// Bullet's own frame, centred on the grid (local + offset); the rays converted to that frame in
// btScalar on the first pass over a set (the benchmark's facts pass, outside the timed loop) and
// kept, each answered by performRaycast with a callback that keeps the nearest hit.
//
// Bullet's default split of its cell (x, j) is the diagonal (x, j+1)-(x+1, j); with the rows
// reversed that is the grid's (c, r)-(c+1, r+1): the same triangles. No buildAccelerator(): with
// Bullet 3.24's accelerator (vertical-bounds chunks) about a third of the oblique rays here missed
// the surface or hit it metres away from the other peers; without it performRaycast walks the
// cells under the ray (a 2D DDA) and agrees with everyone.
#include "tools/bench/peers/terrain_peers.h"

#include "tools/bench/bench_runner.h"

#include <BulletCollision/CollisionShapes/btHeightfieldTerrainShape.h>
#include <BulletCollision/NarrowPhaseCollision/btRaycastCallback.h>

#include <limits>
#include <memory>

namespace nestwalk::bench {
namespace {

constexpr int kUpAxis = 2;  // z up

struct BulletTerrain {
  std::vector<float> heights;  // rows reversed
  std::unique_ptr<btHeightfieldTerrainShape> shape;
  btVector3 offset;  // Bullet's frame = the grid's local frame + offset
  const Rays* converted = nullptr;  // the set whose first `from.size()` rays are in from, to
  std::vector<btVector3> from, to;
};

/// Keeps the nearest hit (btTriangleRaycastCallback only reports hits nearer than m_hitFraction).
struct NearestHit : btTriangleRaycastCallback {
  NearestHit(const btVector3& from, const btVector3& to) : btTriangleRaycastCallback(from, to, 0) {}
  btScalar reportHit(const btVector3&, btScalar hitFraction, int, int) override { return hitFraction; }
};

btVector3 toBullet(const Eigen::Vector3d& v) { return btVector3(btScalar(v.x()), btScalar(v.y()), btScalar(v.z())); }

}  // namespace

RayPeer bulletTerrain(const HeightGrid& grid) {
  auto b = std::make_shared<BulletTerrain>();
  const int n = grid.n;
  b->heights.resize(grid.heights.size());
  for (int r = 0; r < n; ++r)
    std::copy_n(grid.heights.begin() + std::ptrdiff_t(r) * n, n, b->heights.begin() + std::ptrdiff_t(n - 1 - r) * n);
  b->shape = std::make_unique<btHeightfieldTerrainShape>(n, n, b->heights.data(), btScalar(grid.minH),
                                                         btScalar(grid.maxH), kUpAxis, false);
  b->shape->setLocalScaling(btVector3(btScalar(grid.spacing), btScalar(grid.spacing), 1));
  b->offset = btVector3(btScalar(-0.5 * (n - 1) * grid.spacing), btScalar(0.5 * (n - 1) * grid.spacing),
                        btScalar(-0.5 * (double(grid.minH) + double(grid.maxH))));
  return [b](const Rays& rays, std::size_t n, double* z) {
    if (b->converted != &rays || b->from.size() != n) {
      b->converted = &rays;
      b->from.clear();
      b->to.clear();
      for (std::size_t k = 0; k < n; ++k) {
        b->from.push_back(toBullet(rays.origin[k]) + b->offset);
        b->to.push_back(toBullet(rays.end(k)) + b->offset);
      }
    }
    const BulletTerrain& t = *b;
    return answerAll(n, z, [&](std::size_t k) {
      const btVector3 &from = t.from[k], &to = t.to[k];
      NearestHit hit(from, to);
      t.shape->performRaycast(&hit, from, to);
      if (!(hit.m_hitFraction < 1)) return std::numeric_limits<double>::quiet_NaN();
      const double f = hit.m_hitFraction;
      return double(from.z()) + f * (double(to.z()) - double(from.z())) - double(t.offset.z());
    });
  };
}

}  // namespace nestwalk::bench
