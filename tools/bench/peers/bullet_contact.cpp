// Bullet's convex sweep as a peer of the contact benchmark (contact_peers.h). Conversion: the
// mesh's triangles into a btTriangleMesh (btScalar: float in Debian's Bullet, so rounded) under a
// btBvhTriangleMeshShape with margin 0, in a btCollisionObject at the identity; the box as a
// btBoxShape of its half extents with margin 0 (Bullet's boxes keep their margin inside the
// extents; 0 makes the shape the box itself), cast from its pose to the pose moved by d.
#include "tools/bench/peers/contact_peers.h"

#include <BulletCollision/BroadphaseCollision/btBroadphaseProxy.h>
#include <BulletCollision/CollisionDispatch/btCollisionObject.h>
#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>
#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btBvhTriangleMeshShape.h>
#include <BulletCollision/CollisionShapes/btTriangleMesh.h>

#include <limits>
#include <memory>

namespace nestwalk::bench {
namespace {

btVector3 toBullet(const Vec3<double>& v) { return btVector3(btScalar(v.x()), btScalar(v.y()), btScalar(v.z())); }

class BulletContact : public ContactPeer {
 public:
  explicit BulletContact(const TriangleMesh& mesh) : triangles_(std::make_unique<btTriangleMesh>()) {
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      const Triangle t = mesh.triangle(i);
      triangles_->addTriangle(toBullet(t[0]), toBullet(t[1]), toBullet(t[2]));
    }
    shape_ = std::make_unique<btBvhTriangleMeshShape>(triangles_.get(), true);
    shape_->setMargin(0);
    object_.setCollisionShape(shape_.get());
  }
  double timeOfContact(const Obb<double>& box, const Vec3<double>& d) const override {
    btBoxShape cast(toBullet(box.halfExtents));
    cast.setMargin(0);
    const Mat3<double>& r = box.axes;  // btMatrix3x3 is row-major; its columns are the box axes
    const btMatrix3x3 basis(btScalar(r(0, 0)), btScalar(r(0, 1)), btScalar(r(0, 2)),  //
                            btScalar(r(1, 0)), btScalar(r(1, 1)), btScalar(r(1, 2)),  //
                            btScalar(r(2, 0)), btScalar(r(2, 1)), btScalar(r(2, 2)));
    const btTransform from(basis, toBullet(box.center)), to(basis, toBullet(box.center + d));
    btCollisionWorld::ClosestConvexResultCallback hit(from.getOrigin(), to.getOrigin());
    btCollisionWorld::objectQuerySingle(&cast, from, to, const_cast<btCollisionObject*>(&object_), shape_.get(),
                                        object_.getWorldTransform(), hit, 0);
    return hit.hasHit() ? double(hit.m_closestHitFraction) : std::numeric_limits<double>::infinity();
  }

 private:
  std::unique_ptr<btTriangleMesh> triangles_;
  std::unique_ptr<btBvhTriangleMeshShape> shape_;
  btCollisionObject object_;
};

}  // namespace

std::unique_ptr<ContactPeer> bulletContactPeer(const TriangleMesh& mesh) {
  return std::make_unique<BulletContact>(mesh);
}

}  // namespace nestwalk::bench
