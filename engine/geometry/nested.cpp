#include "nestwalk/geometry/nested.h"

namespace nestwalk {

const char* stageName(OverlapStage s) {
  switch (s) {
    case OverlapStage::AabbAabb: return "aabb-aabb";
    case OverlapStage::AabbObb: return "aabb-obb";
    case OverlapStage::ObbObb: return "obb-obb";
  }
  return "";
}

namespace {

// An axis index of the test (B, A) renamed for the test (A, B): face axes swap owners and the
// edge axis B_i x A_j is the edge axis A_j x B_i (the sign of an axis does not matter).
int swapRoles(int axis) {
  if (axis < 0) return axis;
  if (axis < 3) return axis + 3;
  if (axis < 6) return axis - 3;
  const int i = (axis - 6) / 3, j = (axis - 6) % 3;
  return 6 + 3 * j + i;
}

}  // namespace

NestedResult testBoxPair(const Obb<double>& a, const Obb<double>& b) {
  Obb<double> la = a, lb = b;
  la.center.setZero();
  lb.center = b.center - a.center;
  const bool aAligned = la.isAxisAligned(), bAligned = lb.isAxisAligned();
  const NestedVolume<double> va = NestedVolume<double>::fromObb(la), vb = NestedVolume<double>::fromObb(lb);

  const SatResult s1 = satAabbAabb(va.outer, vb.outer);
  if (!s1.overlap || (aAligned && bAligned)) return {s1.overlap, OverlapStage::AabbAabb, s1.axis};

  if (bAligned) {
    const SatResult s2 = satAabbObb(vb.outer, la);
    return {s2.overlap, OverlapStage::AabbObb, std::int8_t(swapRoles(s2.axis))};
  }
  const SatResult s2 = satAabbObb(va.outer, lb);
  if (!s2.overlap || aAligned) return {s2.overlap, OverlapStage::AabbObb, s2.axis};

  const SatResult s3 = satObbObb(la, lb);
  return {s3.overlap, OverlapStage::ObbObb, s3.axis};
}

}  // namespace nestwalk
