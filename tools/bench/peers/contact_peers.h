// The peers of the contact benchmark (contact_bench.h): other libraries answering the walker's
// exact-stage question on the same sweeps: a box translating by d (t from 0 to 1) against a
// triangle mesh at rest, both in the model's frame: the first t at which they touch.
// Each factory converts the mesh to the peer's own structure once, outside any timing.
#pragma once

#include "nestwalk/geometry/triangle_mesh.h"
#include "nestwalk/geometry/volumes.h"

#include <memory>

namespace nestwalk::bench {

class ContactPeer {
 public:
  virtual ~ContactPeer() = default;
  /// The time of first contact in [0, 1]; +infinity when the box does not touch the mesh in the
  /// step.
  virtual double timeOfContact(const Obb<double>& box, const Vec3<double>& d) const = 0;
};

/// FCL: fcl::continuousCollide of a BVHModel<OBBRSS> of the mesh and an fcl::Box, translation only,
/// CCDC_NAIVE sampled every 0.05 mm along the step (the one solver FCL 0.7 answers it with; see
/// peers/fcl_contact.cpp).
std::unique_ptr<ContactPeer> fclContactPeer(const TriangleMesh& mesh);

/// Bullet: btCollisionWorld::objectQuerySingle of a btBoxShape (margin 0) cast against a
/// btBvhTriangleMeshShape of the mesh (margin 0), in btScalar (float in Debian's Bullet)
/// (peers/bullet_contact.cpp).
std::unique_ptr<ContactPeer> bulletContactPeer(const TriangleMesh& mesh);

}  // namespace nestwalk::bench
