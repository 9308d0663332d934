// Bullet's box-box detector as a peer of the bounding-volume benchmark (box_peers.h). Conversion:
// each box becomes a btTransform (the axes as the basis' columns, the centre as its origin) and
// half extents, in btScalar (float in Debian's Bullet: rounded). Two reusable btBoxShapes with
// margin 0 get each pair's half extents, the only thing the detector reads from them.
#include "tools/bench/peers/box_peers.h"

#include <BulletCollision/CollisionDispatch/btBoxBoxDetector.h>
#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <LinearMath/btTransform.h>

#include <memory>

namespace nestwalk::bench {
namespace {

btVector3 toBullet(const Vec3<double>& v) { return btVector3(btScalar(v.x()), btScalar(v.y()), btScalar(v.z())); }

btTransform toBullet(const Obb<double>& b) {
  const Mat3<double>& r = b.axes;  // btMatrix3x3 is row-major; its columns are the box axes
  const btMatrix3x3 basis(btScalar(r(0, 0)), btScalar(r(0, 1)), btScalar(r(0, 2)),  //
                          btScalar(r(1, 0)), btScalar(r(1, 1)), btScalar(r(1, 2)),  //
                          btScalar(r(2, 0)), btScalar(r(2, 1)), btScalar(r(2, 2)));
  return btTransform(basis, toBullet(b.center));
}

/// btBoxBoxDetector reports contact points only for penetrating boxes (it returns at the first
/// separating axis); this result records whether any point was added.
struct OverlapOnly : btDiscreteCollisionDetectorInterface::Result {
  bool hit = false;
  void setShapeIdentifiersA(int, int) override {}
  void setShapeIdentifiersB(int, int) override {}
  void addContactPoint(const btVector3&, const btVector3&, btScalar) override { hit = true; }
};

struct BulletPairs {
  std::vector<btTransform> ta, tb;
  std::vector<btVector3> ha, hb;
  btBoxShape sa{btVector3(1, 1, 1)}, sb{btVector3(1, 1, 1)};
  btBoxBoxDetector detector{&sa, &sb};
  btDiscreteCollisionDetectorInterface::ClosestPointInput input;
  OverlapOnly result;

  bool overlap(std::size_t k) {
    sa.setImplicitShapeDimensions(ha[k]);
    sb.setImplicitShapeDimensions(hb[k]);
    input.m_transformA = ta[k];
    input.m_transformB = tb[k];
    result.hit = false;
    detector.getClosestPoints(input, result, nullptr);
    return result.hit;
  }
};

}  // namespace

Pass<std::uint8_t> bulletBoxPairs(const std::vector<Obb<double>>& a, const std::vector<Obb<double>>& b) {
  auto p = std::make_shared<BulletPairs>();
  p->sa.setMargin(0);
  p->sb.setMargin(0);
  p->input.m_maximumDistanceSquared = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    p->ta.push_back(toBullet(a[k]));
    p->tb.push_back(toBullet(b[k]));
    p->ha.push_back(toBullet(a[k].halfExtents));
    p->hb.push_back(toBullet(b[k].halfExtents));
  }
  return [p](std::uint8_t* verdicts) {
    BulletPairs& pairs = *p;
    return answerAll(pairs.ta.size(), verdicts, [&](std::size_t k) { return pairs.overlap(k); });
  };
}

}  // namespace nestwalk::bench
