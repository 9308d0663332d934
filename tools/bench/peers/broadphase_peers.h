// The peers of the broad-phase benchmark (broadphase_bench.h): other libraries' trees answering the
// same queries on the same boxes: which stored boxes does query box k meet (closed boxes, touching
// counts)? Each factory builds the peer's structure from the boxes, timing that build alone, and
// converts the queries to the peer's types, both outside any timing.
#pragma once

#include "tools/bench/bench_runner.h"

#include "nestwalk/geometry/volumes.h"

#include <cstdint>
#include <vector>

namespace nestwalk::bench {

/// The indices of the stored boxes one query meets, in any order.
using Hits = std::vector<std::uint32_t>;

struct BroadPhasePeer {
  Pass<Hits> pass;                 // answers every query: answers[k] = the hits of query k
  double buildSeconds = 0;         // CPU time (threadSeconds) of building the structure
  std::size_t aabbMismatches = 0;  // boxes and queries whose AABB in the peer differs from the box
};

/// The loop of a broad-phase pass: query(k, out) appends query k's hits to out, which is
/// answers[k] when `answers` is not null and `scratch` otherwise. Returns the total of hits.
template <class Query>
double answerQueries(std::size_t queries, Hits* answers, Hits& scratch, const Query& query) {
  std::size_t total = 0;
  for (std::size_t k = 0; k < queries; ++k) {
    Hits& out = answers ? answers[k] : scratch;
    out.clear();
    query(k, out);
    total += out.size();
  }
  return double(total);
}

/// Bullet: btDbvt, one insert per box, btDbvt::collideTV per query with a callback collecting the
/// leaves (peers/bullet_broadphase.cpp).
BroadPhasePeer bulletBroadPhase(const std::vector<Aabb<double>>& boxes, const std::vector<Aabb<double>>& queries);

/// FCL: DynamicAABBTreeCollisionManager over fcl::Box objects whose AABBs are the boxes
/// (registerObjects + setup), manager->collide(query object, data, callback) with a callback that
/// only records the pair: FCL runs no narrow phase unless the callback does
/// (peers/fcl_broadphase.cpp).
BroadPhasePeer fclBroadPhase(const std::vector<Aabb<double>>& boxes, const std::vector<Aabb<double>>& queries);

}  // namespace nestwalk::bench
