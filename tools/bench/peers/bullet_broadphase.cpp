// Bullet's dynamic AABB tree as a peer of the broad-phase benchmark (broadphase_peers.h). Conversion:
// each box becomes a btDbvtVolume from its corners in btScalar (float in Debian's Bullet; the
// benchmark's coordinates are floats already, so nothing is rounded), its index the leaf's data.
// Build time: the inserts. The queries are converted before the timed loop.
#include "tools/bench/peers/broadphase_peers.h"

#include <BulletCollision/BroadphaseCollision/btDbvt.h>

#include <memory>

namespace nestwalk::bench {
namespace {

btDbvtVolume volume(const Aabb<double>& b) {
  auto bt = [](const Eigen::Vector3d& v) { return btVector3(btScalar(v.x()), btScalar(v.y()), btScalar(v.z())); };
  return btDbvtVolume::FromMM(bt(b.min), bt(b.max));
}

/// Appends the index of every leaf the query meets.
struct CollectLeaves : btDbvt::ICollide {
  Hits* out = nullptr;
  void Process(const btDbvtNode* leaf) override {
    out->push_back(static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(leaf->data)));
  }
};

struct DbvtData {
  btDbvt tree;
  std::vector<btDbvtVolume> queries;
  Hits scratch;
};

}  // namespace

BroadPhasePeer bulletBroadPhase(const std::vector<Aabb<double>>& boxes, const std::vector<Aabb<double>>& queries) {
  auto d = std::make_shared<DbvtData>();
  const double t0 = threadSeconds();
  for (std::size_t i = 0; i < boxes.size(); ++i)
    d->tree.insert(volume(boxes[i]), reinterpret_cast<void*>(static_cast<std::uintptr_t>(i)));
  BroadPhasePeer peer;
  peer.buildSeconds = threadSeconds() - t0;
  for (const Aabb<double>& q : queries) d->queries.push_back(volume(q));
  peer.pass = [d](Hits* answers) {
    DbvtData& data = *d;
    CollectLeaves collect;
    return answerQueries(data.queries.size(), answers, data.scratch, [&](std::size_t k, Hits& out) {
      collect.out = &out;
      data.tree.collideTV(data.tree.m_root, data.queries[k], collect);
    });
  };
  return peer;
}

}  // namespace nestwalk::bench
