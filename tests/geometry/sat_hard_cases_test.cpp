// Hard cases of the overlap tests (sat.h, nested.h), each its own named test. Every expected answer
// comes from the construction (exactly representable contacts) and from the long double reference
// of sat_reference.h evaluated on the very doubles given to the engine, never from the code under test.
//
// Each case is run five ways (runCase):
//   1. at the origin: satObbObb(A, B), satObbObb(B, A), testBoxPair(A, B), testNested(fromObb(A), fromObb(B));
//   2. at UTM magnitudes (A and B moved by (550000, 4650000, 1000)): testBoxPair on the map coordinates;
//   3. the same UTM pair shifted back by hand (exact subtraction of nearby doubles) through satObbObb;
//   4. float, after that local shift: only "no missed contact" is required, beyond the float band
//      wF = 32 * 2^-24 * (|T|_1 + sum of half extents + max |centre|) (rounding of the boxes to float
//      and of the float SAT; the float |R| + 1e-6 inflation covers the axes);
//   5. the float and double reference margins are printed for the record.
// Expected answers:
//   - touching and penetrating pairs: overlap, always (boxes are closed; no band);
//   - separated pairs: separated, except where the engine's documented false-overlap band applies.
//     sat.h separates on an axis iff its unnormalised gap exceeds kParallelEpsilon * (the half
//     extents the inflated |R| multiplies) + kRoundingSlack * M (M = |cB - cA|_1 + all half
//     extents); on an edge axis A_i x B_j at angle theta between the edges this is a band of
//     (kParallelEpsilon * S + kRoundingSlack * M) / sin(theta) (S = the four half extents involved).
//     Those cases are declared (bandFalseOverlap, with the band in words), the model of
//     sat_reference.h must agree that the pair is inside the band, and satObbObb must answer overlap;
//     the cascades (whose AABB stages are sharper) may answer either there.
// Test names: "1em6rad" is 1e-6 rad (gtest names cannot hold '-').
//
// Tests named ExactContact_* are the engine revision's former failures (missed contacts of exactly
// touching boxes, see the comment at each): regression tests.
#include "tests/geometry/sat_reference.h"

#include "nestwalk/geometry/nested.h"
#include "nestwalk/geometry/sat.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>

namespace nestwalk {
namespace {

using namespace nestwalk::testref;
using Vec3d = Vec3<double>;
using Mat3d = Mat3<double>;

constexpr ld kU = 1.1102230246251565e-16L;  // 2^-53
constexpr ld kUf = 5.9604644775390625e-8L;  // 2^-24
// The documented tolerances of sat.h (see SatModel in sat_reference.h).
const SatModel kEngine{kParallelEpsilon<double>, kRoundingSlack<double>, 0};
const SatModel kExact{};
const Vec3d kUtm(550000.0, 4650000.0, 1000.0);

enum class Truth { Overlap, Touching, Separated };

struct Case {
  Obb<double> a, b;
  Truth truth = Truth::Overlap;
  std::optional<double> margin;   // the signed distance the construction intends (checked against the reference)
  bool bandFalseOverlap = false;  // separated, but inside the engine's documented false-overlap band
  std::string band;               // that band, in words
  int satAxis = -2;               // expected separating axis of satObbObb(A, B) (-2: not checked)
  std::optional<OverlapStage> pairStage;  // expected stage of testBoxPair(A, B) when separated
  int pairAxis = -2;                      // expected axis of testBoxPair(A, B) when separated
  double bandWidth = 0;                   // the documented band on the deciding edge axis, when computed
};

Obb<double> box(const Vec3d& c, const Mat3d& axes, const Vec3d& h) { return {c, axes, h}; }
Obb<double> moved(const Obb<double>& b, const Vec3d& d) { return {b.center + d, b.axes, b.halfExtents}; }

Mat3d rotAbout(int axis, i64 c, i64 s, i64 h) { return IntRotation::aboutAxis(axis, c, s, h).toDouble(); }

/// Rotation by theta about a unit axis, evaluated in long double and rounded once.
Mat3d rodrigues(Vec3<ld> u, ld theta) {
  u.normalize();
  Mat3<ld> k;
  k << 0, -u.z(), u.y(), u.z(), 0, -u.x(), -u.y(), u.x(), 0;
  const Mat3<ld> r = Mat3<ld>::Identity() + std::sin(theta) * k + (1 - std::cos(theta)) * k * k;
  return r.cast<double>();
}

const char* verdict(bool overlap) { return overlap ? "overlap" : "separated"; }

ld windowOf(const SatRef& r, ld u) { return 32 * u * (r.extent + r.absCoord); }

// What the engine must answer for a pair whose exact status is `truth` and reference is `r`:
//   sat: satObbObb, by the documented model (touching/overlapping pairs: overlap, no band; separated
//        pairs: separated unless inside the band eps * infl + slack);
//   pair: testBoxPair, whose last word is stage 1 (both boxes aligned: exact AABB-AABB), stage 2 (one
//        aligned: satAabbObb in A's frame, slack + 8 epsilon sum |min| + |max|) or stage 3;
//   nested: testNested, whose last word is stage 3.
//   The cascades must answer overlap for touching/overlapping pairs and separated where their last
//   stage surely separates; in between (a separation inside a band) either answer.
struct Required {
  Expect sat, pair, nested;
};

// The model of testBoxPair's deciding stage for the pair (a, b) (in any frame: only cB - cA matters).
SatModel boxPairModel(const Obb<double>& a, const Obb<double>& b) {
  const bool aAligned = a.isAxisAligned(), bAligned = b.isAxisAligned();
  if (aAligned && bAligned) return kExact;
  if (!aAligned && !bAligned) return kEngine;
  ld mm = 0;  // sum |min| + |max| of the aligned box's AABB in A's frame
  for (int k = 0; k < 3; ++k) {
    if (aAligned) {
      mm += 2 * ld(a.halfExtents[k]);
    } else {
      const ld t = ld(b.center[k]) - ld(a.center[k]), h = b.halfExtents[k];
      mm += std::fabs(t - h) + std::fabs(t + h);
    }
  }
  return {kParallelEpsilon<double>, kRoundingSlack<double>, 8 * ld(std::numeric_limits<double>::epsilon()) * mm};
}

Required required(const Case& c, Truth truth, const SatRef& r, const Obb<double>& a, const Obb<double>& b,
                  const std::string& where, bool checkDeclaredBand) {
  if (truth != Truth::Separated) return {Expect::Overlap, Expect::Overlap, Expect::Overlap};
  const ld w = windowOf(r, kU);
  const Expect e = expectInflated(r, kEngine, w, false);
  if (checkDeclaredBand && c.bandFalseOverlap) {
    EXPECT_EQ(e, Expect::Overlap) << where << ": declared inside the false-overlap band (" << c.band
                                  << ") but the model says " << expectName(e) << " (margin " << double(r.margin) << ")";
  } else if (checkDeclaredBand) {
    EXPECT_EQ(e, Expect::Separated) << where << ": a separated case must be outside every band; the model says "
                                    << expectName(e) << " (margin " << double(r.margin) << ")";
  }
  const Expect ep = expectInflated(r, boxPairModel(a, b), w, false);
  return {e, ep == Expect::Separated ? Expect::Separated : Expect::Either,
          e == Expect::Separated ? Expect::Separated : Expect::Either};
}

void checkVerdict(const std::string& what, bool got, Expect req, const SatRef& r) {
  if (req == Expect::Either) return;
  EXPECT_EQ(got, req == Expect::Overlap) << what << ": got " << verdict(got) << ", required " << expectName(req)
                                         << " (reference margin " << double(r.margin) << " m on axis "
                                         << axisName(r.marginAxis) << ")";
}

void checkCascade(const std::string& what, const NestedResult& n, Expect req, const SatRef& r) {
  checkVerdict(what, n.overlap, req, r);
  if (!n.overlap) {
    EXPECT_GT(r.margin, 0) << what << " separated a pair that is not separated";
  }
}

// The contact survives the move to UTM when both centres moved exactly; otherwise (a touching
// construction whose centre needs more bits than UTM coordinates have) the rounded contact is
// decided by the model: the engine's face/edge inflation bands apply to the ~1e-13 m displacement.
bool movedExactly(const Case& c, const Obb<double>& aU, const Obb<double>& bU) {
  return (aU.center - kUtm) == c.a.center && (bU.center - kUtm) == c.b.center;
}

void runCase(const Case& c) {
  // ---- 1. origin
  bool consistent = false;
  const SatRef r = ldSatBothWays(c.a, c.b, consistent);
  EXPECT_TRUE(consistent) << "reference (A, B) and (B, A) disagree";
  const ld tolM = 1e-15L * (1 + r.extent);
  switch (c.truth) {
    case Truth::Touching: EXPECT_LE(std::fabs(r.margin), tolM) << "construction is not touching"; break;
    case Truth::Separated: EXPECT_GT(r.margin, tolM) << "construction is not separated"; break;
    case Truth::Overlap: EXPECT_LT(r.margin, -tolM) << "construction does not overlap"; break;
  }
  if (c.margin) {
    EXPECT_NEAR(double(r.margin), *c.margin, 1e-12 + 1e-9 * std::fabs(*c.margin)) << "construction margin";
  }
  const Required rq = required(c, c.truth, r, c.a, c.b, "origin", true);
  const Expect req = rq.sat;

  const SatResult s = satObbObb(c.a, c.b);
  checkVerdict("satObbObb(A, B)", s.overlap, req, r);
  if (!s.overlap) {
    const std::string why = checkReportedAxis(r, s.axis, kEngine, windowOf(r, kU), false);
    EXPECT_TRUE(why.empty()) << "satObbObb(A, B): " << why;
    if (c.satAxis != -2) {
      EXPECT_EQ(int(s.axis), c.satAxis) << "satObbObb(A, B) axis " << satAxisName(s.axis);
    }
  }
  const SatResult sb = satObbObb(c.b, c.a);
  checkVerdict("satObbObb(B, A)", sb.overlap, req, r);
  const NestedResult p = testBoxPair(c.a, c.b);
  checkCascade("testBoxPair(A, B)", p, rq.pair, r);
  if (!p.overlap && c.pairStage) {
    EXPECT_EQ(p.stage, *c.pairStage) << "testBoxPair stage " << stageName(p.stage);
    if (c.pairAxis != -2) {
      EXPECT_EQ(int(p.axis), c.pairAxis) << "testBoxPair axis";
    }
  }
  const NestedResult n = testNested(NestedVolume<double>::fromObb(c.a), NestedVolume<double>::fromObb(c.b));
  checkCascade("testNested(A, B)", n, rq.nested, r);

  // ---- 2./3. UTM
  const Obb<double> aU = moved(c.a, kUtm), bU = moved(c.b, kUtm);
  const Obb<double> aL = moved(aU, -kUtm), bL = moved(bU, -kUtm);  // exact: nearby doubles
  EXPECT_EQ(aL.center + kUtm, aU.center);
  EXPECT_EQ(bL.center + kUtm, bU.center);
  // The reference of the UTM pair, evaluated on the (identical) shifted geometry so that the rounding
  // window is that of local coordinates, as the engine works after its own exact shift.
  const SatRef rU = ldSat(aL, bL);
  EXPECT_NEAR(double(ldSat(aU, bU).margin), double(rU.margin), 1e-12);
  const bool roundedContact = c.truth == Truth::Touching && !movedExactly(c, aU, bU) && rU.margin != 0;
  const Truth tU = roundedContact ? (rU.margin > 0 ? Truth::Separated : Truth::Touching) : c.truth;
  const Required rqU = required(c, tU, rU, aL, bL, "UTM", !roundedContact);
  const Expect reqU = rqU.sat;
  if (roundedContact) {
    std::printf("  UTM: rounding moved the contact by %.2Le m; SAT must answer %s\n", rU.margin, expectName(reqU));
    EXPECT_NE(reqU, Expect::Separated) << "a rounded contact must stay inside the engine's band";
  }
  const NestedResult pU = testBoxPair(aU, bU);
  checkCascade("testBoxPair at UTM", pU, rqU.pair, rU);
  if (!pU.overlap && c.pairStage && tU == Truth::Separated) {
    EXPECT_EQ(pU.stage, *c.pairStage) << "testBoxPair at UTM: stage " << stageName(pU.stage);
    if (c.pairAxis != -2) {
      EXPECT_EQ(int(pU.axis), c.pairAxis) << "testBoxPair at UTM: axis";
    }
  }
  const SatResult sL = satObbObb(aL, bL);
  checkVerdict("satObbObb after the local shift", sL.overlap, reqU, rU);

  // ---- 4. float after the local shift
  const Obb<float> aF = aL.cast<float>(), bF = bL.cast<float>();
  const SatResult sF = satObbObb(aF, bF);
  const ld wF = windowOf(rU, kUf);
  if (!sF.overlap) {
    // No missed contact beyond the float band.
    EXPECT_GT(rU.margin, -wF) << "float missed a contact: margin " << double(rU.margin) << " < -" << double(wF);
  }
  const ld wD = windowOf(r, kU);
  std::printf("  margin %+.6Le m (axis %s) | double: sat %s%s, pair %s/%s, nested %s/%s | UTM: pair %s, local sat %s | "
              "float %s (band %.1Le m)%s\n",
              r.margin, axisName(r.marginAxis).c_str(), verdict(s.overlap),
              s.overlap ? "" : (std::string(" ") + satAxisName(s.axis)).c_str(), verdict(p.overlap), stageName(p.stage),
              verdict(n.overlap), stageName(n.stage), verdict(pU.overlap), verdict(sL.overlap), verdict(sF.overlap), wF,
              c.bandFalseOverlap ? (" | inside the false-overlap band: " + c.band).c_str() : "");
  (void)wD;
  if (::testing::Test::HasFailure()) {
    std::printf("  reference per axis (gap, normalised gap, engine threshold eps * infl + slack):\n");
    for (int k = 0; k < kAxes; ++k)
      std::printf("    %-6s %+.6Le %+.6Le %.3Le\n", axisName(k).c_str(), r.gap[k],
                  r.len[k] > 0 ? r.gap[k] / r.len[k] : ld(0), thresholdOf(r, kEngine, k));
  }
}

// ------------------------------------------------------------------------------------------------
// Near-parallel edges.
//
// B: half extents (1.25, 0.5, 0.5), rotated by theta about u = (0, 1, 1)/sqrt 2, so that its x edge is
//    tilted by theta in the plane normal to u and B_1 + B_2 stays (0, 1, 1).
// Edge config: A aligned, half extents (1.25, 0.5, 0.5), centre 0; its edge E_A along x at
//    (y, z) = (0.5, 0.5). B's edge E_B = c_B - 0.5 (B_1 + B_2) crosses E_A above x = 0, offset by d
//    along u; the edge axis A0 x B0 (parallel to u) has gap d, the faces of A and B gap
//    (d - 1.25 sin theta) / sqrt 2: the edge axis decides while d < 1.25 sin theta.
// Face config: A aligned, half extents (3, 0.5, 3); B above A's +y face, its lowest vertex d above
//    it (and above the face): the face axis A1 decides.
// The engine's band on A0 x B0: eps * S / sin theta with S = a1 + a2 + b1 + b2 = 2.

enum class Config { Edge, Face };

Case nearParallel(double theta, Config cfg, double d) {
  Case c;
  c.a = box(Vec3d::Zero(), Mat3d::Identity(), cfg == Config::Edge ? Vec3d(1.25, 0.5, 0.5) : Vec3d(3, 0.5, 3));
  const Mat3d R = rodrigues(Vec3<ld>(0, 1, 1), theta);
  const Vec3d hb(1.25, 0.5, 0.5);
  Vec3<ld> cb;
  if (cfg == Config::Edge) {
    const Vec3<ld> u = Vec3<ld>(0, 1, 1).normalized();
    cb = Vec3<ld>(0, 0.5, 0.5) + (R.col(1).cast<ld>() + R.col(2).cast<ld>()) * ld(0.5) + ld(d) * u;
  } else {
    ld ry = 0;  // B's extent along y with the double axes
    for (int k = 0; k < 3; ++k) ry += ld(hb[k]) * std::fabs(ld(R(1, k)));
    cb = Vec3<ld>(0, 0.5 + ry + ld(d), 0);
  }
  c.b = box(cb.cast<double>(), R, hb);
  c.truth = d > 0 ? Truth::Separated : Truth::Overlap;
  // Separated: the edges (or B's lowest point) are the closest features, so the SAT margin is d.
  // Penetrating: the margin is minus the smallest overlap over the axes, not necessarily d.
  if (d > 0) c.margin = d;
  const bool edgeDecides = cfg == Config::Edge && d < 1.25 * std::sin(theta);
  if (d > 0) {
    if (edgeDecides) {
      c.satAxis = 6;  // A0 x B0
      c.pairStage = OverlapStage::AabbObb;  // A is aligned: stage 2 is exact for the pair
      c.pairAxis = 6;
      // The documented band on A0 x B0: (kParallelEpsilon * S + kRoundingSlack * M) / sin(theta),
      // S = a1 + a2 + b1 + b2 = 2, M = |cB - cA|_1 + all half extents.
      const double M = c.b.center.cwiseAbs().sum() + c.a.halfExtents.sum() + c.b.halfExtents.sum();
      const double band = (kParallelEpsilon<double> * 2 + kRoundingSlack<double> * M) / std::sin(theta);
      c.bandWidth = band;
      if (d < band) {
        c.bandFalseOverlap = true;
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "edge axis A0xB0, (kParallelEpsilon * S + kRoundingSlack * M) / sin(theta) = "
                      "(1e-12 * 2 + 1e-12 * %.2f) / %.0e = %.1e m > gap %.0e m",
                      M, theta, band, d);
        c.band = buf;
      }
    } else {
      c.satAxis = 1;  // A's +y face
      c.pairStage = OverlapStage::AabbAabb;
      c.pairAxis = 1;
    }
  }
  return c;
}

#define NEAR_PARALLEL(EXP, CFG, NAME, D)                                                \
  TEST(HardCase, NearParallelEdges_1em##EXP##rad_##CFG##NAME) {                          \
    runCase(nearParallel(std::pow(10.0, -EXP), Config::CFG, D));                          \
  }
#define NEAR_PARALLEL_ALL(EXP)                      \
  NEAR_PARALLEL(EXP, Edge, Gap1mm, 1e-3)            \
  NEAR_PARALLEL(EXP, Edge, Gap1um, 1e-6)            \
  NEAR_PARALLEL(EXP, Edge, Penetration1mm, -1e-3)   \
  NEAR_PARALLEL(EXP, Edge, Penetration1um, -1e-6)   \
  NEAR_PARALLEL(EXP, Face, Gap1mm, 1e-3)            \
  NEAR_PARALLEL(EXP, Face, Gap1um, 1e-6)            \
  NEAR_PARALLEL(EXP, Face, Penetration1mm, -1e-3)   \
  NEAR_PARALLEL(EXP, Face, Penetration1um, -1e-6)

NEAR_PARALLEL_ALL(3)
NEAR_PARALLEL_ALL(4)
NEAR_PARALLEL_ALL(5)
NEAR_PARALLEL_ALL(6)
NEAR_PARALLEL_ALL(7)
NEAR_PARALLEL_ALL(8)
NEAR_PARALLEL_ALL(9)
NEAR_PARALLEL_ALL(10)

TEST(HardCase, NearParallelEdges_BandIsWhereDocumented) {
  // In the table above the only edge-decided separation inside the band is theta = 1e-6, gap 1 um
  // (band ~8.5 um); theta = 1e-5, gap 1 um (band ~0.85 um) separates on A0 x B0.
  const Case in = nearParallel(1e-6, Config::Edge, 1e-6), out = nearParallel(1e-5, Config::Edge, 1e-6);
  EXPECT_TRUE(in.bandFalseOverlap);
  EXPECT_FALSE(out.bandFalseOverlap);
  EXPECT_TRUE(satObbObb(in.a, in.b).overlap);
  const SatResult s = satObbObb(out.a, out.b);
  EXPECT_FALSE(s.overlap);
  EXPECT_EQ(s.axis, 6);
  // Both sides of the band at theta = 1e-5, edge-decided: half the band overlaps, twice separates.
  const double band = out.bandWidth;
  std::printf("  band at theta = 1e-5: %.3e m\n", band);
  const Case in2 = nearParallel(1e-5, Config::Edge, band / 2), out2 = nearParallel(1e-5, Config::Edge, band * 2);
  EXPECT_TRUE(in2.bandFalseOverlap);
  EXPECT_FALSE(out2.bandFalseOverlap);
  runCase(in2);
  runCase(out2);
  const SatResult s2 = satObbObb(out2.a, out2.b);
  EXPECT_FALSE(s2.overlap);
  EXPECT_EQ(s2.axis, 6);
  EXPECT_TRUE(satObbObb(in2.a, in2.b).overlap);
}

// ------------------------------------------------------------------------------------------------
// Exactly representable contacts.

const Mat3d I3 = Mat3d::Identity();

TEST(HardCase, FaceFaceTouching_Aligned) {
  Case c;
  c.a = box(Vec3d::Zero(), I3, Vec3d(0.5, 0.5, 0.5));
  c.b = box(Vec3d(1, 0.25, -0.125), I3, Vec3d(0.5, 0.5, 0.5));
  c.truth = Truth::Touching;
  runCase(c);
}

TEST(HardCase, FaceFaceGap1um_Aligned_StageAndAxis) {
  // Face-separated AABB pair: testBoxPair decides at stage aabb-aabb on z; satAabbAabb and satObbObb
  // report z too.
  Case c;
  c.a = box(Vec3d(0.5, 0.5, 0.5), I3, Vec3d(0.5, 0.5, 0.5));
  c.b = box(Vec3d(0.75, 0.25, 1.5 + 1e-6), I3, Vec3d(0.5, 0.5, 0.5));
  c.truth = Truth::Separated;
  c.margin = (1.5 + 1e-6) - 1.5;  // B's bottom (1.5 + 1e-6) - 0.5 minus A's top 1.0, exactly
  c.satAxis = 2;
  c.pairStage = OverlapStage::AabbAabb;
  c.pairAxis = 2;
  runCase(c);
  const SatResult s = satAabbAabb(aabbOf(c.a), aabbOf(c.b));
  EXPECT_FALSE(s.overlap);
  EXPECT_EQ(s.axis, 2);
  EXPECT_STREQ(aabbAxisName(s.axis), "z");
  const NestedResult n = testNested(NestedVolume<double>::fromObb(c.a), NestedVolume<double>::fromObb(c.b));
  EXPECT_EQ(n.stage, OverlapStage::AabbAabb);
  EXPECT_EQ(n.axis, 2);
}

TEST(HardCase, FaceFaceGap2pow43_Aligned_InsideTheSlackBand) {
  // Two aligned unit cubes 2^-43 m (~1.1e-13 m) apart in z (exact at the origin and at UTM z ~ 1000).
  // satObbObb answers overlap: the gap is inside its documented rounding slack kRoundingSlack * M
  // (M = |cB - cA|_1 + all half extents ~ 4 m, i.e. ~4e-12 m). testBoxPair decides two aligned boxes
  // at its exact AABB-AABB stage and separates them (correctly). So nested.h's "the verdict is always
  // the OBB-OBB answer" holds for the OBB pair, not literally for satObbObb's verdict inside its band.
  Case c;
  const double gap = std::ldexp(1.0, -43);
  c.a = box(Vec3d::Zero(), I3, Vec3d(0.5, 0.5, 0.5));
  c.b = box(Vec3d(0.25, -0.125, 1 + gap), I3, Vec3d(0.5, 0.5, 0.5));
  c.truth = Truth::Separated;
  c.margin = gap;
  c.bandFalseOverlap = true;
  c.band = "face axis A2, kParallelEpsilon * sum b + kRoundingSlack * M = 1.5e-12 + 4.4e-12 m > gap 1.1e-13 m";
  c.pairStage = OverlapStage::AabbAabb;
  c.pairAxis = 2;
  runCase(c);
  EXPECT_TRUE(satObbObb(c.a, c.b).overlap);
  const NestedResult p = testBoxPair(c.a, c.b);
  EXPECT_FALSE(p.overlap);
  EXPECT_EQ(p.stage, OverlapStage::AabbAabb);
}

TEST(HardCase, FaceFaceTouching_RotatedAboutTheNormal) {
  // B rotated about x by atan(4/3): its axes have zero x components exactly, so its x extent is
  // exactly b0 and its -x face lies on A's +x face.
  Case c;
  c.a = box(Vec3d::Zero(), I3, Vec3d(0.5, 0.5, 0.5));
  c.b = box(Vec3d(0.5 + 0.25, 0.125, 0), rotAbout(0, 3, 4, 5), Vec3d(0.25, 0.5, 0.5));
  c.truth = Truth::Touching;
  runCase(c);
}

TEST(HardCase, FaceFaceGap1um_RotatedAboutTheNormal) {
  Case c;
  c.a = box(Vec3d::Zero(), I3, Vec3d(0.5, 0.5, 0.5));
  c.b = box(Vec3d(0.75 + 1e-6, 0.125, 0), rotAbout(0, 3, 4, 5), Vec3d(0.25, 0.5, 0.5));
  c.truth = Truth::Separated;
  c.margin = (0.75 + 1e-6) - 0.75;
  c.satAxis = 0;
  c.pairStage = OverlapStage::AabbAabb;
  c.pairAxis = 0;
  runCase(c);
}

// Skew edges: A rotated about x, B about y (both atan(4/3)); A's top edge runs along x, B's bottom
// edge along y, they cross at (-0.25, -0.25). With a = (1, 1/4, 1/2), b = (1/4, 1, 1/2) the top of A is
// 0.25 fl(0.8) + 0.5 fl(0.6) and the bottom of B is 1 - (0.25 fl(0.8) + 0.5 fl(0.6)), since
// 0.5 fl(0.8) + fl(0.6) == 1 exactly in binary: the edges touch exactly. Separating axis: A0 x B1 = z.
Case skewEdges(double dz) {
  Case c;
  c.a = box(Vec3d::Zero(), rotAbout(0, 3, 4, 5), Vec3d(1, 0.25, 0.5));
  c.b = box(Vec3d(0, 0, 1 + dz), rotAbout(1, 3, 4, 5), Vec3d(0.25, 1, 0.5));
  c.truth = dz == 0 ? Truth::Touching : dz > 0 ? Truth::Separated : Truth::Overlap;
  if (dz != 0) c.margin = (1 + dz) - 1.0;
  c.satAxis = 7;  // A0 x B1
  return c;
}

TEST(HardCase, EdgeEdgeTouching_SkewEdges) {
  EXPECT_EQ(0.5 * 0.8 + 0.6, 1.0);  // the identity the construction rests on (each product exact)
  const Case c = skewEdges(0);
  const SatRef r = ldSat(c.a, c.b);
  EXPECT_EQ(r.gap[7], 0) << "the edge axis A0xB1 is the touching one";
  for (int k = 0; k < 6; ++k) EXPECT_LT(r.gap[k], 0) << "face axis " << axisName(k) << " must not touch";
  runCase(c);
}

TEST(HardCase, EdgeEdgeGap1um_SkewEdges_AxisIsA0xB1) {
  // A0 x B1 is the world z axis: satObbObb reports the edge axis, testBoxPair's AABB stage already
  // separates on z.
  Case c = skewEdges(1e-6);
  c.pairStage = OverlapStage::AabbAabb;
  c.pairAxis = 2;
  runCase(c);
}

TEST(HardCase, EdgeEdgePenetration1um_SkewEdges) { runCase(skewEdges(-1e-6)); }

// Vertex-face: B in a generic rational orientation, its lowest vertex exactly on A's top face z = 0.
// Half extents are picked (deterministically) so that the vertex depth sum_k b_k |B_kz| is a double.
Case vertexFace(double dz) {
  const int quats[][4] = {{1, 2, 3, 4}, {2, 1, 3, 1}, {3, 1, 2, 2}, {4, 1, 2, 3}};
  const double hs[] = {0.25, 0.5, 0.75, 1, 1.25, 1.5};
  for (const auto& q : quats) {
    const Mat3d R = IntRotation::fromQuaternion(q[0], q[1], q[2], q[3]).toDouble();
    for (double h0 : hs)
      for (double h1 : hs)
        for (double h2 : hs) {
          const Vec3d hb(h0, h1, h2);
          ld depth = 0;  // exact in long double: three products by dyadic half extents
          Vec3<ld> v = Vec3<ld>::Zero();
          for (int k = 0; k < 3; ++k) {
            const ld sgn = R(2, k) > 0 ? -1 : 1;  // the lowest vertex
            depth += ld(hb[k]) * std::fabs(ld(R(2, k)));
            v += sgn * ld(hb[k]) * R.col(k).cast<ld>();
          }
          if (ld(double(depth)) != depth) continue;
          Case c;
          c.a = box(Vec3d(0, 0, -1), I3, Vec3d(2, 2, 1));  // top face z = 0
          // Vertex at (x, y) ~ (0, 0) (rounding there is harmless), exactly at height dz.
          c.b = box(Vec3d(double(-v.x()), double(-v.y()), double(depth) + dz), R, hb);
          c.truth = dz == 0 ? Truth::Touching : dz > 0 ? Truth::Separated : Truth::Overlap;
          if (dz != 0) c.margin = (double(depth) + dz) - double(depth);
          if (dz > 0) {
            c.satAxis = 2;
            c.pairStage = OverlapStage::AabbAabb;
            c.pairAxis = 2;
          }
          return c;
        }
  }
  ADD_FAILURE() << "no representable vertex-face configuration found";
  return {};
}

TEST(HardCase, VertexFaceTouching_GenericRotation) { runCase(vertexFace(0)); }
TEST(HardCase, VertexFaceGap1um_GenericRotation) { runCase(vertexFace(1e-6)); }
TEST(HardCase, VertexFacePenetration1um_GenericRotation) { runCase(vertexFace(-1e-6)); }

// ------------------------------------------------------------------------------------------------
// Identical boxes, containment.

const Mat3d kGeneric = IntRotation::fromQuaternion(1, 2, 3, 4).toDouble();

TEST(HardCase, IdenticalBoxes_Rotated) {
  Case c;
  c.a = c.b = box(Vec3d(0.3, -0.7, 0.1), kGeneric, Vec3d(1, 0.5, 0.25));
  runCase(c);
}

TEST(HardCase, IdenticalPanels_Rotated) {
  // Two identical flat panels: zero gap along their common normal, i.e. touching (margin 0).
  Case c;
  c.a = c.b = box(Vec3d(0.3, -0.7, 0.1), kGeneric, Vec3d(1, 0.5, 0));
  c.truth = Truth::Touching;
  runCase(c);
}

TEST(HardCase, IdenticalPoints) {
  Case c;
  c.a = c.b = box(Vec3d(0.3, -0.7, 0.1), kGeneric, Vec3d::Zero());
  c.truth = Truth::Touching;  // zero distance, zero volume: closed sets meet
  runCase(c);
}

TEST(HardCase, OneInsideTheOther_SmallRotatedInBig) {
  Case c;
  c.a = box(Vec3d::Zero(), I3, Vec3d(5, 5, 5));
  c.b = box(Vec3d(1, -2, 0.5), kGeneric, Vec3d(0.5, 0.25, 1));
  runCase(c);
  std::swap(c.a, c.b);  // big around small
  runCase(c);
}

TEST(HardCase, OneInsideTheOther_InnerTouchesOuterFaceFromInside) {
  Case c;
  c.a = box(Vec3d::Zero(), I3, Vec3d(1, 1, 1));
  c.b = box(Vec3d(0.75, 0, 0), rotAbout(0, 3, 4, 5), Vec3d(0.25, 0.5, 0.5));  // x in [0.5, 1]
  runCase(c);
}

// ------------------------------------------------------------------------------------------------
// Panels (one zero half extent), poles (two), points (three) against boxes. The contact plane is
// z = 0 (A's top), so that rotated contacts are representable.

const Obb<double> kBoxBelow = box(Vec3d(0, 0, -0.5), I3, Vec3d(0.5, 0.5, 0.5));

Case onTop(const Mat3d& axes, const Vec3d& h, double lift, double xy = 0.1) {
  Case c;
  c.a = kBoxBelow;
  ld depth = 0;
  for (int k = 0; k < 3; ++k) depth += ld(h[k]) * std::fabs(ld(axes(2, k)));
  EXPECT_EQ(ld(double(depth)), depth) << "construction: depth not representable";
  c.b = box(Vec3d(xy, -xy, double(depth) + lift), axes, h);
  c.truth = lift == 0 ? Truth::Touching : lift > 0 ? Truth::Separated : Truth::Overlap;
  if (lift != 0) c.margin = (double(depth) + lift) - double(depth);
  if (lift > 0) {
    c.satAxis = 2;
    c.pairStage = OverlapStage::AabbAabb;
    c.pairAxis = 2;
  }
  return c;
}

TEST(HardCase, PanelOnBoxTop_Touching) { runCase(onTop(I3, Vec3d(0.3, 0.2, 0), 0)); }
TEST(HardCase, PanelOnBoxTop_Gap1um) { runCase(onTop(I3, Vec3d(0.3, 0.2, 0), 1e-6)); }
TEST(HardCase, RotatedPanelOnBoxTop_Touching) { runCase(onTop(rotAbout(2, 3, 4, 5), Vec3d(0.3, 0.2, 0), 0)); }
TEST(HardCase, RotatedPanelOnBoxTop_Gap1um) { runCase(onTop(rotAbout(2, 3, 4, 5), Vec3d(0.3, 0.2, 0), 1e-6)); }
TEST(HardCase, TiltedPanelEdgeOnBoxTop_Touching) {
  // Panel tilted about x: it touches the top along its lower edge.
  runCase(onTop(rotAbout(0, 3, 4, 5), Vec3d(0.3, 0.25, 0), 0));
}
TEST(HardCase, TiltedPanelEdgeOnBoxTop_Gap1um) { runCase(onTop(rotAbout(0, 3, 4, 5), Vec3d(0.3, 0.25, 0), 1e-6)); }

TEST(HardCase, VerticalPanelAgainstSide_Touching) {
  Case c;
  c.a = kBoxBelow;  // x in [-0.5, 0.5]
  c.b = box(Vec3d(0.5, 0.2, -0.3), I3, Vec3d(0, 0.4, 0.4));
  c.truth = Truth::Touching;
  runCase(c);
}

TEST(HardCase, VerticalPanelAgainstSide_Gap1um) {
  Case c;
  c.a = kBoxBelow;
  c.b = box(Vec3d(0.5 + 1e-6, 0.2, -0.3), I3, Vec3d(0, 0.4, 0.4));
  c.truth = Truth::Separated;
  c.margin = (0.5 + 1e-6) - 0.5;
  c.satAxis = 0;
  c.pairStage = OverlapStage::AabbAabb;
  c.pairAxis = 0;
  runCase(c);
}

TEST(HardCase, PoleStandingOnTop_Touching) { runCase(onTop(I3, Vec3d(0, 0, 1), 0)); }
TEST(HardCase, PoleStandingOnTop_Gap1um) { runCase(onTop(I3, Vec3d(0, 0, 1), 1e-6)); }
TEST(HardCase, TiltedPoleEndOnTop_Touching) { runCase(onTop(rotAbout(0, 3, 4, 5), Vec3d(0, 0, 0.5), 0)); }
TEST(HardCase, TiltedPoleEndOnTop_Gap1um) { runCase(onTop(rotAbout(0, 3, 4, 5), Vec3d(0, 0, 0.5), 1e-6)); }
TEST(HardCase, GenericPoleEndOnTop_Touching) {
  // q = (1, 2, 3, 4): R(2, 0) = 2/30 * ... ; pick the pole along the axis with a representable depth.
  const Mat3d R = IntRotation::fromQuaternion(1, 2, 3, 4).toDouble();
  for (int k = 0; k < 3; ++k) {
    Vec3d h = Vec3d::Zero();
    h[k] = 0.5;
    if (ld(double(ld(0.5) * std::fabs(ld(R(2, k))))) == ld(0.5) * std::fabs(ld(R(2, k)))) {
      runCase(onTop(R, h, 0));
      runCase(onTop(R, h, 1e-6));
      return;
    }
  }
  ADD_FAILURE() << "construction: no axis with a representable depth";
}

TEST(HardCase, PointOnBoxTop_Touching) { runCase(onTop(I3, Vec3d::Zero(), 0)); }
TEST(HardCase, PointOnBoxTop_Gap1um) { runCase(onTop(I3, Vec3d::Zero(), 1e-6)); }
TEST(HardCase, PointWithRotatedAxesOnBoxTop_Touching) { runCase(onTop(kGeneric, Vec3d::Zero(), 0)); }
TEST(HardCase, PointWithRotatedAxesOnBoxTop_Gap1um) { runCase(onTop(kGeneric, Vec3d::Zero(), 1e-6)); }
TEST(HardCase, PointAtBoxCorner_Touching) {
  Case c;
  c.a = kBoxBelow;
  c.b = box(Vec3d(0.5, -0.5, 0), I3, Vec3d::Zero());
  c.truth = Truth::Touching;
  runCase(c);
}
TEST(HardCase, PointOnRotatedBoxFace_Touching) {
  // The point c + a1 A_1 (exact: a1 is a power of two) is on the closed face of the rotated box.
  Case c;
  const Mat3d R = rotAbout(0, 3, 4, 5);
  c.a = box(Vec3d::Zero(), R, Vec3d(1, 0.5, 0.25));
  c.b = box(0.5 * Vec3d(R.col(1)), I3, Vec3d::Zero());
  c.truth = Truth::Touching;
  runCase(c);
}
TEST(HardCase, PointVsPoint_Gap1um) {
  Case c;
  c.a = box(Vec3d(0.25, 0.5, 0), I3, Vec3d::Zero());
  c.b = box(Vec3d(0.25, 0.5 + 1e-6, 0), kGeneric, Vec3d::Zero());
  c.truth = Truth::Separated;
  c.margin = (0.5 + 1e-6) - 0.5;
  runCase(c);
}

// ------------------------------------------------------------------------------------------------
// A 0.02 x 0.02 x 30 m pole against a 1 m box at grazing distance.

// Lying on the top face, horizontal, in a rational direction in the xy plane: its z extent is
// exactly 0.01, so touching is exact.
Case longPoleLying(double lift) {
  Case c = onTop(rotAbout(2, 3, 4, 5), Vec3d(15, 0.01, 0.01), lift, 0.05);
  return c;
}
// Tilted by ~0.02 rad (Pythagorean 200/9999/10001) about y, its lower face grazing the box's top edge
// (x = 0.5, z = 0.5 with the box centred at the origin): the pole's face axis B2 decides.
Case longPoleGrazingEdge(double g) {
  Case c;
  c.a = box(Vec3d::Zero(), I3, Vec3d(0.5, 0.5, 0.5));
  const Mat3d R = rotAbout(1, 9999, 200, 10001);  // B_2 = (sin, 0, cos)
  const Vec3<ld> n = R.col(2).cast<ld>();
  const Vec3<ld> P(0.5, 0, 0.5);
  const Vec3<ld> cb = P + (ld(0.01) + ld(g)) * n;
  c.b = box(cb.cast<double>(), R, Vec3d(15, 0.01, 0.01));
  c.truth = g > 0 ? Truth::Separated : g < 0 ? Truth::Overlap : Truth::Touching;
  if (g != 0) c.margin = g;
  if (g > 0) {
    c.satAxis = 5;  // B2
    c.pairStage = OverlapStage::AabbObb;  // A aligned: stage 2 is exact
    c.pairAxis = 5;
  }
  return c;
}

TEST(HardCase, LongPoleLyingOnBox_Gap1mm) { runCase(longPoleLying(1e-3)); }
TEST(HardCase, LongPoleLyingOnBox_Gap1um) { runCase(longPoleLying(1e-6)); }
TEST(HardCase, LongPoleLyingOnBox_Touching) { runCase(longPoleLying(0)); }
TEST(HardCase, LongPoleLyingOnBox_Penetration1um) { runCase(longPoleLying(-1e-6)); }
TEST(HardCase, LongPoleGrazingBoxEdge_Gap1mm) { runCase(longPoleGrazingEdge(1e-3)); }
TEST(HardCase, LongPoleGrazingBoxEdge_Gap1um) { runCase(longPoleGrazingEdge(1e-6)); }
TEST(HardCase, LongPoleGrazingBoxEdge_Touching) {
  // The rounded pole centre leaves the contact at ~1e-17 m; the reference margin must be ~0 and the
  // engine must answer overlap (either side of zero is inside its 1e-12 face band).
  runCase(longPoleGrazingEdge(0));
}
TEST(HardCase, LongPoleGrazingBoxEdge_Penetration1um) { runCase(longPoleGrazingEdge(-1e-6)); }

// ------------------------------------------------------------------------------------------------
// Exact contacts that an earlier engine revision (before kRoundingSlack and the outward rounding of
// aabbOf) reported as separated: a rounding error not covered by the |R| + kParallelEpsilon
// inflation, which is proportional to the half extents of the boxes and zero (or tiny) for a point
// or a small box, while the rounding is proportional to the coordinates. Kept as regression tests.

TEST(HardCase, ExactContact_PointOnAabbFace_SatAabbObbAndNested) {
  // AABB x in [0.2, 0.5] and a point at x = 0.5 (any axes): touching. satAabbObb recomputes the
  // AABB's centre 0.5 (min + max) and half extents 0.5 (max - min) with rounding; without a slack
  // (the point's half extents are 0) the earlier revision answered "separated, axis 0".
  Aabb<double> a;
  a.min = Vec3d(0.2, -1, -1);
  a.max = Vec3d(0.5, 1, 1);
  Obb<double> p;
  p.center = Vec3d(0.5, 0, 0);
  EXPECT_TRUE(a.contains(p.center));  // independent: the closed box contains the point
  const SatRef r = ldSat(a, p);
  EXPECT_EQ(r.margin, 0);
  const SatResult s = satAabbObb(a, p);
  EXPECT_TRUE(s.overlap) << "touching point reported separated on axis " << int(s.axis);
  // The same through the nested cascade: viewer = the AABB (inner OBB = the same box), object = the point.
  const NestedVolume<double> viewer{a, Obb<double>::fromAabb(a)}, object = NestedVolume<double>::fromObb(p);
  const NestedResult n = testNested(viewer, object);
  EXPECT_TRUE(n.overlap) << "testNested separated at stage " << stageName(n.stage) << " axis " << int(n.axis);
}

TEST(HardCase, ExactContact_PointAtRotatedFaceCentre) {
  // A unit box (half extents 1) rotated about x by atan(12/5) (axes entries fl(5/13), fl(12/13)), and
  // the point c + 1 * A_1: the centre of its +y face, in the closed box by the definition of Obb.
  // satObbObb computes t_1 = A_1 . A_1 = 1 + 2^-52; without a slack the earlier revision separated
  // on A1.
  const Mat3d R = rotAbout(0, 5, 12, 13);
  const Obb<double> a = box(Vec3d::Zero(), R, Vec3d(1, 1, 1));
  const Obb<double> p = box(Vec3d(R.col(1)), I3, Vec3d::Zero());
  const SatRef r = ldSat(a, p);
  EXPECT_LE(r.margin, 0) << "reference: the point is not outside";
  const SatResult s = satObbObb(a, p);
  EXPECT_TRUE(s.overlap) << "point on the face reported separated on axis " << satAxisName(s.axis);
  EXPECT_TRUE(testBoxPair(a, p).overlap) << "testBoxPair";
}

TEST(HardCase, ExactContact_TestBoxPair_LocalShiftOfTouchingAabbs) {
  // Two aligned boxes touching at x = -2.5: A centre -3, half 0.5 (max -2.5 exactly); B centre
  // -2.5 + 1.7 (computed; exact: -2.5 + fl(1.7) is representable, checked below), half 1.7, min -2.5
  // exactly. testBoxPair moves B to A's frame: fl(cB - cA) = fl(2.2 + 1e-16ish) rounds up; the
  // earlier revision's AABB-AABB stage then separated on x ("differences of nearby doubles are exact"
  // does not hold for centres of different magnitude, here -3 and -0.8). aabbOf's outward rounding
  // now covers the shift.
  const double hb = 1.7, cb = -2.5 + hb;
  EXPECT_EQ(cb - hb, -2.5);
  {  // two-sum: -2.5 + hb is exact, so B's min is -2.5 exactly
    const double s = -2.5 + hb, bb = s - (-2.5), err = (-2.5 - (s - bb)) + (hb - bb);
    EXPECT_EQ(err, 0);
  }
  const Obb<double> a = box(Vec3d(-3, 0, 0), I3, Vec3d(0.5, 1, 1));
  const Obb<double> b = box(Vec3d(cb, 0, 0), I3, Vec3d(hb, 1, 1));
  const SatRef r = ldSat(a, b);
  EXPECT_EQ(r.margin, 0);
  EXPECT_TRUE(satObbObb(a, b).overlap);                    // the plain SAT is right
  EXPECT_TRUE(satAabbAabb(aabbOf(a), aabbOf(b)).overlap);  // and so is AABB-AABB in place
  const NestedResult n = testBoxPair(a, b);
  EXPECT_TRUE(n.overlap) << "testBoxPair separated touching boxes at stage " << stageName(n.stage)
                         << " axis " << int(n.axis);
}

TEST(HardCase, ExactContact_TestBoxPair_TinyRotatedBoxOnBigAlignedBox) {
  // A: 1 mm box rotated 90 degrees about z (exact axes), at the origin; B: aligned, half extent
  // 560.8 m in x, its -x face exactly at A's +x extent (a_y = cB - eB, exact by Sterbenz). Touching.
  // testBoxPair (B aligned, A not) builds B's AABB as fl(cB -+ eB), then satAabbObb recomputes its
  // centre and half extents with rounding (~1e-13 m at 560 m) while the |R| + eps inflation is only
  // eps * (sum of A's half extents) ~ 3e-15 m: the earlier revision separated on B0.
  Mat3d rz;
  rz << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  const double eb = 560.8, cb = 560.80036130268961;
  const double ay = cb - eb;  // exact (Sterbenz)
  const Obb<double> a = box(Vec3d::Zero(), rz, Vec3d(0.0004, ay, 0.0007));
  const Obb<double> b = box(Vec3d(cb, 0.5, 0.25), I3, Vec3d(eb, 1, 1));
  const SatRef r = ldSat(a, b);
  EXPECT_EQ(r.margin, 0) << "construction: exact contact";
  EXPECT_TRUE(satObbObb(a, b).overlap);
  const NestedResult n = testBoxPair(a, b);
  EXPECT_TRUE(n.overlap) << "testBoxPair separated touching boxes at stage " << stageName(n.stage)
                         << " axis " << satAxisName(n.axis);
}

}  // namespace
}  // namespace nestwalk
