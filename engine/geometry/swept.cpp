#include "nestwalk/geometry/swept.h"

#include "nestwalk/geometry/slab_clip.h"

#include <Eigen/Geometry>

#include <cmath>

namespace nestwalk {
namespace {

/// The 15 slabs of the moving box A (frame: columns of Aax, half extents a) against B, given
/// t0 = A^T (cB - cA), dv = A^T d, R = A^T B. Mirrors satInFrameOfA (sat.h), with t replaced by
/// t0 - t dv on every axis. Fills the world axis of the entering slab through the callback data.
SweepResult sweepInFrame(const Vec3<double>& t0, const Vec3<double>& dv, const Mat3<double>& Rm, const Vec3<double>& a,
                         const Vec3<double>& b, const Mat3<double>& Aax, const Mat3<double>& Bax, double inputRounding) {
  double R[3][3], absR[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      R[i][j] = Rm(i, j);
      absR[i][j] = std::abs(R[i][j]) + kParallelEpsilon<double>;
    }
  // Slack as in sat.h's pairSlack, over the whole step: the largest |cB - cA(t)|_1 on [0, 1] is
  // at most |t0|_1 + |dv|_1.
  const double slack = kRoundingSlack<double> * (t0.cwiseAbs().sum() + dv.cwiseAbs().sum() + a.sum() + b.sum()) +
                       inputRounding;
  SlabClip c;
  bool alive = true;
  for (int i = 0; i < 3 && alive; ++i)
    alive = c.clip(t0[i], dv[i], a[i] + b[0] * absR[i][0] + b[1] * absR[i][1] + b[2] * absR[i][2] + slack,
                   std::int8_t(i), i);
  for (int j = 0; j < 3 && alive; ++j) {
    const double ra = a[0] * absR[0][j] + a[1] * absR[1][j] + a[2] * absR[2][j];
    const double p = t0[0] * R[0][j] + t0[1] * R[1][j] + t0[2] * R[2][j];
    const double v = dv[0] * R[0][j] + dv[1] * R[1][j] + dv[2] * R[2][j];
    alive = c.clip(p, v, ra + b[j] + slack, std::int8_t(3 + j), 3 + j);
  }
  for (int i = 0; i < 3 && alive; ++i) {
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3 && alive; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double ra = a[i1] * absR[i2][j] + a[i2] * absR[i1][j];
      const double rb = b[j1] * absR[i][j2] + b[j2] * absR[i][j1];
      const double p = t0[i2] * R[i1][j] - t0[i1] * R[i2][j];
      const double v = dv[i2] * R[i1][j] - dv[i1] * R[i2][j];
      alive = c.clip(p, v, ra + rb + slack, std::int8_t(6 + 3 * i + j), 6 + 3 * i + j);
    }
  }
  SweepResult out;
  out.enter = c.enter;
  out.exit = c.exit;
  out.axis = alive ? c.enterAxis : c.decidingAxis;
  if (alive && c.enterSlot >= 0) {
    Vec3<double> L;
    const int s = c.enterSlot;
    if (s < 3) {
      L = Aax.col(s);
    } else if (s < 6) {
      L = Bax.col(s - 3);
    } else {
      L = Aax.col((s - 6) / 3).cross(Bax.col((s - 6) % 3));
    }
    const double n = L.norm();
    if (n > 0) out.normal = (c.enterSign / n) * L;
  }
  return out;
}

/// Intersects two intervals; the later entry gives the axis and normal.
SweepResult intersect(const SweepResult& x, const SweepResult& y) {
  SweepResult out = x.enter >= y.enter ? x : y;
  out.exit = std::min(x.exit, y.exit);
  return out;
}

SweptNestedResult finish(const SweepResult& r, OverlapStage stage) {
  SweptNestedResult out;
  out.stage = stage;
  out.axis = r.axis;
  out.contact = r.contactInStep();
  if (out.contact) {
    out.t = std::max(r.enter, 0.0);
    out.normal = r.normal;
  }
  return out;
}

}  // namespace

SweepResult sweepAabbAabb(const Aabb<double>& a, const Vec3<double>& d, const Aabb<double>& b) {
  // Per axis: a.min + t d <= b.max and b.min <= a.max + t d. Written as a slab around the centres so
  // that the slack is the same as for the other tests; the centre and half extents are rounded
  // from min and max, covered by the input rounding term as in satAabbObb.
  const Vec3<double> t0 = b.center() - a.center();
  const Vec3<double> r = a.halfExtents() + b.halfExtents();
  const double inputRounding =
      8 * std::numeric_limits<double>::epsilon() *
      ((a.min.cwiseAbs() + a.max.cwiseAbs()).sum() + (b.min.cwiseAbs() + b.max.cwiseAbs()).sum());
  const double slack =
      kRoundingSlack<double> * (t0.cwiseAbs().sum() + d.cwiseAbs().sum() + r.sum()) + inputRounding;
  SlabClip c;
  bool alive = true;
  for (int k = 0; k < 3 && alive; ++k) alive = c.clip(t0[k], d[k], r[k] + slack, std::int8_t(k), k);
  SweepResult out;
  out.enter = c.enter;
  out.exit = c.exit;
  out.axis = alive ? c.enterAxis : c.decidingAxis;
  if (alive && c.enterSlot >= 0) out.normal[c.enterSlot] = c.enterSign;
  return out;
}

SweepResult sweepAabbObb(const Aabb<double>& a, const Vec3<double>& d, const Obb<double>& b) {
  const double inputRounding =
      8 * std::numeric_limits<double>::epsilon() * (a.min.cwiseAbs() + a.max.cwiseAbs()).sum();
  return sweepInFrame(b.center - a.center(), d, b.axes, a.halfExtents(), b.halfExtents, Mat3<double>::Identity(),
                      b.axes, inputRounding);
}

SweepResult sweepObbObb(const Obb<double>& a, const Vec3<double>& d, const Obb<double>& b) {
  const Mat3<double> At = a.axes.transpose();
  return sweepInFrame(At * (b.center - a.center), At * d, At * b.axes, a.halfExtents, b.halfExtents, a.axes, b.axes,
                      0.0);
}

SweptNestedResult sweepNested(const NestedVolume<double>& viewer, const Vec3<double>& d,
                              const NestedVolume<double>& object) {
  SweepResult r = sweepAabbAabb(viewer.outer, d, object.outer);
  if (!r.contactInStep()) return finish(r, OverlapStage::AabbAabb);
  const SweepResult r2 = sweepAabbObb(viewer.outer, d, object.inner);
  if (!r2.contactInStep()) return finish(r2, OverlapStage::AabbObb);
  r = intersect(r, r2);
  if (!r.contactInStep()) return finish(r, OverlapStage::AabbObb);
  const SweepResult r3 = sweepObbObb(viewer.inner, d, object.inner);
  if (!r3.contactInStep()) return finish(r3, OverlapStage::ObbObb);
  return finish(intersect(r, r3), OverlapStage::ObbObb);
}

SweptNestedResult sweepOuterOnly(const NestedVolume<double>& viewer, const Vec3<double>& d,
                                 const NestedVolume<double>& object) {
  return finish(sweepAabbAabb(viewer.outer, d, object.outer), OverlapStage::AabbAabb);
}

SweptNestedResult sweepInnerOnly(const NestedVolume<double>& viewer, const Vec3<double>& d,
                                 const NestedVolume<double>& object) {
  return finish(sweepObbObb(viewer.inner, d, object.inner), OverlapStage::ObbObb);
}

}  // namespace nestwalk
