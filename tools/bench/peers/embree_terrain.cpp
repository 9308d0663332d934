// Embree as a peer of the terrain benchmark (terrain_peers.h): the grid's triangles as one
// RTC_GEOMETRY_TYPE_TRIANGLE geometry of float vertices in a committed scene; each ray converted to
// float and answered by rtcIntersect1 (nearest hit), its height computed from the hit distance.
#include "tools/bench/peers/terrain_peers.h"

#include "tools/bench/bench_runner.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <limits>
#include <memory>

namespace nestwalk::bench {
namespace {

struct EmbreeScene {
  RTCDevice device = rtcNewDevice(nullptr);
  RTCScene scene = rtcNewScene(device);
  ~EmbreeScene() {
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
  }
};

}  // namespace

RayPeer embreeTerrain(const HeightGrid& grid) {
  auto e = std::make_shared<EmbreeScene>();
  RTCGeometry geom = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  const std::size_t vertices = grid.heights.size();
  auto* v = static_cast<float*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertices));
  for (std::size_t i = 0; i < vertices; ++i) Eigen::Map<Eigen::Vector3f>(v + 3 * i) = grid.vertex(i);
  const std::vector<unsigned> t = grid.triangles();
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(unsigned), t.size() / 3));
  std::copy(t.begin(), t.end(), idx);
  rtcCommitGeometry(geom);
  rtcAttachGeometry(e->scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(e->scene);
  return [e](const Rays& rays, std::size_t n, double* z) {
    RTCScene scene = e->scene;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    return answerAll(n, z, [&](std::size_t k) {
      RTCRayHit rh;
      rh.ray.org_x = float(rays.origin[k].x());
      rh.ray.org_y = float(rays.origin[k].y());
      rh.ray.org_z = float(rays.origin[k].z());
      rh.ray.dir_x = float(rays.dir[k].x());
      rh.ray.dir_y = float(rays.dir[k].y());
      rh.ray.dir_z = float(rays.dir[k].z());
      rh.ray.tnear = 0.0f;
      rh.ray.tfar = float(rays.tMax[k]);
      rh.ray.mask = 0xFFFFFFFFu;
      rh.ray.time = 0.0f;
      rh.ray.flags = 0;
      rh.hit.geomID = rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene, &ctx, &rh);
      if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::numeric_limits<double>::quiet_NaN();
      return double(rh.ray.org_z) + double(rh.ray.tfar) * double(rh.ray.dir_z);
    });
  };
}

}  // namespace nestwalk::bench
