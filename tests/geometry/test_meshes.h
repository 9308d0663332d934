// Meshes that stress the mesh trees and the swept triangle tests (an icosphere, a thin tilted
// pole, coplanar and degenerate triangles, one triangle, an empty mesh, exponentially spaced
// parts, a sphere at UTM magnitudes) and the random query boxes around them.
#pragma once

#include "nestwalk/geometry/triangle_mesh.h"
#include "nestwalk/geometry/volumes.h"
#include "tests/geometry/test_shapes.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

namespace nestwalk::testmeshes {

using V3 = Vec3<double>;

inline TriangleMesh icosphere(int subdivisions, double radius) {
  const double g = (1 + std::sqrt(5.0)) / 2;
  TriangleMesh m;
  m.vertices = {V3(-1, g, 0), V3(1, g, 0),  V3(-1, -g, 0), V3(1, -g, 0), V3(0, -1, g), V3(0, 1, g),
                V3(0, -1, -g), V3(0, 1, -g), V3(g, 0, -1),  V3(g, 0, 1),  V3(-g, 0, -1), V3(-g, 0, 1)};
  m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},   {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (V3& v : m.vertices) v = v.normalized() * radius;
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoints;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      auto [it, added] = midpoints.try_emplace(key, std::uint32_t(m.vertices.size()));
      if (added) m.vertices.push_back((m.vertices[a] + m.vertices[b]).normalized() * radius);
      return it->second;
    };
    std::vector<std::array<std::uint32_t, 3>> finer;
    for (const auto& t : m.triangles) {
      const std::uint32_t ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
      finer.insert(finer.end(), {{t[0], ab, ca}, {t[1], bc, ab}, {t[2], ca, bc}, {ab, bc, ca}});
    }
    m.triangles = std::move(finer);
  }
  return m;
}

// A 5 cm pole, 3 m tall: a 16-sided prism with capped ends, tilted off the axes.
inline TriangleMesh pole() {
  const int sides = 16;
  const double radius = 0.025, length = 3.0;
  const Mat3<double> tilt = Eigen::AngleAxisd(0.3, V3(1, 2, 0).normalized()).toRotationMatrix();
  TriangleMesh m;
  for (int end = 0; end < 2; ++end)
    for (int i = 0; i < sides; ++i) {
      const double a = 2 * std::numbers::pi * i / sides;
      m.vertices.push_back(tilt * V3(radius * std::cos(a), radius * std::sin(a), end * length));
    }
  for (std::uint32_t i = 0; i < sides; ++i) {
    const std::uint32_t j = (i + 1) % sides;
    m.triangles.push_back({i, j, sides + j});
    m.triangles.push_back({i, sides + j, sides + i});
  }
  for (std::uint32_t i = 1; i + 1 < sides; ++i) {
    m.triangles.push_back({0, i + 1, i});
    m.triangles.push_back({sides, sides + i, sides + i + 1});
  }
  return m;
}

// A 1 m floor of 200 coplanar triangles, a vertical coplanar wall, and degenerate triangles:
// collinear (on and off the floor), a repeated vertex, a point, duplicates.
inline TriangleMesh coplanarAndDegenerate() {
  TriangleMesh m;
  const int n = 10;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) m.vertices.push_back(V3(x * 0.1, y * 0.1, 0));
  for (std::uint32_t y = 0; y < n; ++y)
    for (std::uint32_t x = 0; x < n; ++x) {
      const std::uint32_t a = y * (n + 1) + x, b = a + 1, c = a + n + 1, d = c + 1;
      m.triangles.push_back({a, b, d});
      m.triangles.push_back({a, d, c});
    }
  auto add = [&](const V3& p, const V3& q, const V3& r) {
    const auto base = std::uint32_t(m.vertices.size());
    m.vertices.insert(m.vertices.end(), {p, q, r});
    m.triangles.push_back({base, base + 1, base + 2});
  };
  for (int i = 0; i < 20; ++i) add(V3(0.5, i * 0.05, 0.2), V3(0.5, i * 0.05, 0.6), V3(0.5, i * 0.05 + 0.05, 0.4));  // wall
  add(V3(0, 0, 0.3), V3(1, 1, 0.3), V3(0.5, 0.5, 0.3));          // collinear, above the floor
  add(V3(0.2, 0.9, 0), V3(0.8, 0.9, 0), V3(0.4, 0.9, 0));        // collinear, on the floor
  add(V3(1.2, 0.2, 0.1), V3(1.2, 0.2, 0.1), V3(1.4, 0.3, 0.1));  // a repeated vertex
  add(V3(1.3, 0.8, 0.5), V3(1.3, 0.8, 0.5), V3(1.3, 0.8, 0.5));  // a point
  m.triangles.push_back(m.triangles[7]);                          // duplicates
  m.triangles.push_back(m.triangles[7]);
  return m;
}

inline TriangleMesh singleTriangle() { return {{V3(0, 0, 0), V3(1, 0.2, 0.1), V3(0.3, 0.8, -0.2)}, {{0, 1, 2}}}; }

// Small triangles at x = 1.2^i: mean splits peel a few triangles off the far end at every level.
inline TriangleMesh exponentiallySpaced() {
  TriangleMesh m;
  for (std::uint32_t i = 0; i < 150; ++i) {
    const double x = std::pow(1.2, i), s = 0.1 * x;
    m.vertices.insert(m.vertices.end(), {V3(x, 0, 0), V3(x + s, s, 0), V3(x, s, s)});
    m.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  return m;
}

inline TriangleMesh translated(TriangleMesh m, const V3& offset) {
  for (V3& v : m.vertices) v += offset;
  return m;
}

inline Aabb<double> boundsOf(const TriangleMesh& m) {
  Aabb<double> b;
  for (const auto& t : m.triangles)
    for (std::uint32_t v : t) b.extend(m.vertices[v]);
  return b;
}

// ---- Query boxes. ----

struct BoxMaker {
  std::mt19937 rng;
  Aabb<double> region;  // the mesh's bounds, grown
  double size;          // largest half extent

  double logUniform(double lo, double hi) {
    return std::exp(std::uniform_real_distribution<double>(std::log(lo), std::log(hi))(rng));
  }
  Obb<double> random() {
    Obb<double> b;
    std::uniform_real_distribution<double> u(0, 1);
    for (int k = 0; k < 3; ++k) {
      b.center[k] = region.min[k] + u(rng) * (region.max[k] - region.min[k]);
      b.halfExtents[k] = rng() % 10 == 0 ? 0.0 : logUniform(1e-3, size);
    }
    if (rng() % 4 != 0) b.axes = testshapes::randomRotation(rng);
    return b;
  }
  // An axis-aligned box with a corner on vertex v, extending away from it on random sides.
  Obb<double> touching(const V3& v) {
    Obb<double> b;
    for (int k = 0; k < 3; ++k) {
      b.halfExtents[k] = std::ldexp(1.0, -int(rng() % 8));  // 1 .. 1/128, exact
      b.center[k] = v[k] + (rng() % 2 ? b.halfExtents[k] : -b.halfExtents[k]);
    }
    return b;
  }
};

inline BoxMaker boxesAround(const TriangleMesh& m, unsigned seed) {
  Aabb<double> region = boundsOf(m);
  if (region.isEmpty()) region = {V3::Constant(-1), V3::Constant(1)};
  const V3 grow = 0.3 * region.size() + V3::Constant(0.1);
  const double size = std::max(0.5 * region.size().maxCoeff(), 0.01);
  return {std::mt19937(seed), {region.min - grow, region.max + grow}, size};
}

struct NamedMesh {
  const char* name;
  TriangleMesh mesh;
};

inline std::vector<NamedMesh> testMeshes() {
  return {{"icosphere", icosphere(3, 1.0)},
          {"icosphere@utm", translated(icosphere(2, 1.0), V3(512345.0, 4476543.0, 1210.0))},
          {"pole", pole()},
          {"coplanar+degenerate", coplanarAndDegenerate()},
          {"single", singleTriangle()},
          {"empty", TriangleMesh{}},
          {"exponential", exponentiallySpaced()}};
}

}  // namespace nestwalk::testmeshes
