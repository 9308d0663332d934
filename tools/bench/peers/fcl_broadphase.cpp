// FCL's dynamic AABB tree manager as a peer of the broad-phase benchmark (broadphase_peers.h).
// Conversion: each box becomes an fcl::CollisionObjectd of an fcl::Boxd of the box's side lengths,
// translated to its centre, its index the object's user data. For float coordinates the centre and
// the sides are exact in double, so FCL's AABB (centre -+ side / 2) is the box itself: counted in
// aabbMismatches, which should stay 0. Build time: creating the objects, registerObjects and setup.
// The query boxes become objects the same way, before the timed loop.
#include "tools/bench/peers/broadphase_peers.h"

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/narrowphase/collision_object.h>

#include <memory>

namespace nestwalk::bench {
namespace {

std::unique_ptr<fcl::CollisionObjectd> object(const Aabb<double>& b, std::size_t index) {
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.translation() = 0.5 * (b.min + b.max);
  auto obj = std::make_unique<fcl::CollisionObjectd>(std::make_shared<fcl::Boxd>(b.max - b.min), tf);
  obj->setUserData(reinterpret_cast<void*>(static_cast<std::uintptr_t>(index)));
  return obj;
}

/// The objects whose AABB is not their box.
std::size_t mismatches(const std::vector<std::unique_ptr<fcl::CollisionObjectd>>& objects,
                       const std::vector<Aabb<double>>& boxes) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < boxes.size(); ++i)
    n += objects[i]->getAABB().min_ != boxes[i].min || objects[i]->getAABB().max_ != boxes[i].max ? 1 : 0;
  return n;
}

/// Records the stored object of every pair; returns false: go on, all pairs, no narrow phase.
bool record(fcl::CollisionObjectd* stored, fcl::CollisionObjectd*, void* hits) {
  const auto index = reinterpret_cast<std::uintptr_t>(stored->getUserData());
  static_cast<Hits*>(hits)->push_back(static_cast<std::uint32_t>(index));
  return false;
}

struct FclData {
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects, queries;
  fcl::DynamicAABBTreeCollisionManagerd manager;
  Hits scratch;
};

}  // namespace

BroadPhasePeer fclBroadPhase(const std::vector<Aabb<double>>& boxes, const std::vector<Aabb<double>>& queries) {
  auto f = std::make_shared<FclData>();
  BroadPhasePeer peer;
  const double t0 = threadSeconds();
  std::vector<fcl::CollisionObjectd*> raw;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    f->objects.push_back(object(boxes[i], i));
    raw.push_back(f->objects.back().get());
  }
  f->manager.registerObjects(raw);
  f->manager.setup();
  peer.buildSeconds = threadSeconds() - t0;
  for (std::size_t k = 0; k < queries.size(); ++k) f->queries.push_back(object(queries[k], k));
  peer.aabbMismatches = mismatches(f->objects, boxes) + mismatches(f->queries, queries);
  peer.pass = [f](Hits* answers) {
    FclData& data = *f;
    return answerQueries(data.queries.size(), answers, data.scratch,
                         [&](std::size_t k, Hits& out) { data.manager.collide(data.queries[k].get(), &out, record); });
  };
  return peer;
}

}  // namespace nestwalk::bench
