// The peers of the terrain benchmark (terrain_bench.h): other libraries answering the same rays on
// the same triangulated grid. Each factory builds the peer's structure from the grid once (the
// caller times it as the peer's build time) and returns a RayPeer that answers rays in the grid's
// local frame: Embree and OSG convert each ray to their own types in the loop (as an application
// would), Bullet converts a set once, on its first pass (the benchmark's facts pass, not timed).
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <functional>
#include <vector>

namespace nestwalk::bench {

/// n x n height samples `spacing` metres apart, row by row from the northern edge. Local frame:
/// sample (c, r) at x = c * spacing (east), y = -r * spacing (north up), z = its height.
struct HeightGrid {
  int n = 0;
  double spacing = 1;
  std::vector<float> heights;
  float minH = 0, maxH = 0;

  float at(int c, int r) const { return heights[std::size_t(r) * std::size_t(n) + std::size_t(c)]; }
  /// Sample i = r * n + c as a vertex of the local frame, in float (the peers' precision).
  Eigen::Vector3f vertex(std::size_t i) const {
    const std::size_t c = i % std::size_t(n), r = i / std::size_t(n);
    return {float(double(c) * spacing), float(-double(r) * spacing), heights[i]};
  }
  /// The grid's triangles as vertex index triples, counter-clockwise seen from above: per cell with
  /// corners a = (c, r), b = (c+1, r), cc = (c+1, r+1), d = (c, r+1), the upper (a, cc, b) and the
  /// lower (a, d, cc): the split of nestwalk's Heightfield.
  std::vector<unsigned> triangles() const {
    std::vector<unsigned> t;
    t.reserve(6 * std::size_t(n - 1) * std::size_t(n - 1));
    for (int r = 0; r + 1 < n; ++r)
      for (int c = 0; c + 1 < n; ++c) {
        const unsigned a = unsigned(r * n + c), b = a + 1, cc = unsigned((r + 1) * n + c + 1), d = cc - 1;
        for (unsigned i : {a, cc, b, a, d, cc}) t.push_back(i);
      }
    return t;
  }
};

/// Rays in the grid's local frame: origin + t * dir for t in [0, tMax], dir of unit length.
struct Rays {
  std::vector<Eigen::Vector3d> origin, dir;
  std::vector<double> tMax;
  Eigen::Vector3d end(std::size_t k) const { return origin[k] + tMax[k] * dir[k]; }
};

/// Answers the first n rays: z[k] = the height of ray k's nearest hit (local frame), NaN on a miss,
/// when z is not null. Returns the sum of the hit heights (answerAll, bench_runner.h).
using RayPeer = std::function<double(const Rays& rays, std::size_t n, double* z)>;

/// Embree: rtcIntersect1 on the grid's triangles in one scene (peers/embree_terrain.cpp).
RayPeer embreeTerrain(const HeightGrid& grid);
/// Bullet: btHeightfieldTerrainShape::performRaycast (peers/bullet_terrain.cpp).
RayPeer bulletTerrain(const HeightGrid& grid);
/// OpenSceneGraph: osgUtil::LineSegmentIntersector on a Geometry with a KdTree
/// (peers/osg_terrain.cpp).
RayPeer osgTerrain(const HeightGrid& grid);

}  // namespace nestwalk::bench
