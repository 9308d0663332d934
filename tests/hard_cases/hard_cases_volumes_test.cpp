// Hard cases of the box tests (sat.h, nested.h, obb_batch.h, swept.h): float against double against
// an exact answer, on near-parallel edges, touching and flat boxes, poles, and the same pairs at UTM
// magnitudes. References (tests/geometry/sat_reference.h, written apart from the engine):
//  - exactSat: the 15 axes in integer arithmetic on rational boxes (exact verdicts), used where the
//    doubles handed to the engine are those boxes exactly (dyadic coordinates, signed-permutation
//    axes) or differ from them only across the contact (rotations about the contact normal);
//  - ldSat: the 15 axes in long double on the very doubles handed to the engine (the "margin" is the
//    separation the 15 axes certify, exact to ~1e-19 of the sizes);
//  - closed forms from the construction (the edge-edge distance d, contact times of a sweep).
// The engine's paths must never report a separation where the reference says touching or
// overlapping, and must separate wherever the reference separates by more than the path's
// documented band (sat.h: |R| + eps and a rounding slack; float: eps 1e-6, slack 2e-6 relative,
// plus the conservative rounding of the boxes to float).
#include "nestwalk/geometry/nested.h"
#include "nestwalk/geometry/obb_batch.h"
#include "nestwalk/geometry/sat.h"
#include "nestwalk/geometry/swept.h"
#include "tests/geometry/sat_reference.h"
#include "tests/geometry/scoped_simd.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace nestwalk {
namespace {

using namespace nestwalk::testref;
using V3 = Vec3<double>;
using M3 = Mat3<double>;
using V3l = Vec3<ld>;
using M3l = Mat3<ld>;

constexpr ld kUnitRound = 0x1p-53L;
constexpr ld kFloatRound = 0x1p-24L;
// The documented tolerances (sat.h) as models of sat_reference.h.
const SatModel kDoubleModel{kParallelEpsilon<double>, kRoundingSlack<double>, 0};
const SatModel kFloatModel{kParallelEpsilon<float>, kRoundingSlack<float>, 0};

Obb<double> shifted(const Obb<double>& b, const V3& by) { return {b.center + by, b.axes, b.halfExtents}; }

/// What a path answered against what it had to answer (Either: the pair is inside the path's band).
void expectVerdict(const char* path, bool overlap, Expect required, const std::string& where) {
  if (required == Expect::Either) return;
  EXPECT_EQ(overlap, required == Expect::Overlap) << path << " answered " << (overlap ? "overlap" : "separated")
                                                   << ", the reference requires " << expectName(required) << " -- " << where;
}

/// The float path as the engine takes it: the pair in a local frame centred on A, each box rounded
/// outward to float (toFloatConservative), then satObbObb<float>.
bool floatPathOverlaps(const Obb<double>& a, const Obb<double>& b) {
  const V3 c = a.center;
  return satObbObb(toFloatConservative(shifted(a, -c)), toFloatConservative(shifted(b, -c))).overlap;
}

/// The pair through testBoxPairs (query overlap's batch) on every SIMD path, with the axes checked
/// by the kernel and (where they keep Obb's contract) vouched for by the caller, as the only pair of
/// its call and as one lane of a full block of copies; every answer must be testBoxPair's, field
/// for field.
NestedResult batchResult(const Obb<double>& a, const Obb<double>& b) {
  const NestedResult want = testBoxPair(a, b);
  const bool contract = axesError(a.axes) <= kAxesTolerance<double> && axesError(b.axes) <= kAxesTolerance<double>;
  std::vector<Obb<double>> as(kBatchLanes, a), bs(kBatchLanes, b);
  for (const char* path : kSimdPaths) {
    const ScopedSimd simd(path);
    for (const bool vouched : {false, true}) {
      if (vouched && !contract) continue;
      for (const std::size_t n : {std::size_t(1), std::size_t(kBatchLanes)}) {
        std::vector<NestedResult> out(n);
        testBoxPairs({.a = as.data(), .b = bs.data(), .count = n, .orthonormalAxes = vouched}, out.data());
        for (const NestedResult& r : out) {
          const std::string where = std::string(batchKernelName(obbBatchKernel())) + (vouched ? ", axes vouched" : "");
          EXPECT_EQ(r.overlap, want.overlap) << where;
          EXPECT_EQ(r.stage, want.stage) << where;
          EXPECT_EQ(r.axis, want.axis) << where;
        }
      }
    }
  }
  return want;
}

// ------------------------------------------------------------------------------------------------
// Situation: near-parallel edges, float vs double vs exact.
//
// In A's frame (A axis-aligned, half extents a), B is A's orientation turned by theta about the
// generic axis g = (0.3, 0.5, 0.8)/|.|, half extents b. A's edge E_A runs along x at (y, z) = (a1, a2);
// B's edge E_B along B0 at B-frame (-b1, -b2). L = A0 x B0 / |A0 x B0| lies in the outward normal cone
// of A at E_A and -L in that of B at E_B (checked), so the plane normal to L through the middle of E_A
// separates the boxes when B's edge middle is placed at d L from it: the boxes are then exactly d apart
// (closed form; the closest points are the two edge middles), touching at d = 0 and crossing for
// d < 0. The pair is then turned by a generic rotation Q and placed near the origin or at UTM
// magnitudes. Exact answer: ldSat on the doubles given (its margin is checked against d).
// theta = 0 is the exactly parallel limit (L = the limit direction).
struct EdgePair {
  Obb<double> a, b;
};

EdgePair nearParallelEdges(ld theta, ld d, const V3l& where) {
  const V3l a(0.9L, 0.35L, 0.25L), b(1.1L, 0.3L, 0.2L);
  const V3l g = V3l(0.3L, 0.5L, 0.8L).normalized();
  const M3l R = Eigen::AngleAxis<ld>(theta, g).toRotationMatrix();
  V3l L = V3l::UnitX().cross(R.col(0));
  if (theta == 0) L = V3l(0, g.y(), g.z());
  L.normalize();
  EXPECT_GE(L.y(), 0) << "L outside A's normal cone at E_A";
  EXPECT_GE(L.z(), 0) << "L outside A's normal cone at E_A";
  EXPECT_GE(L.dot(R.col(1)), 0) << "-L outside B's normal cone at E_B";
  EXPECT_GE(L.dot(R.col(2)), 0) << "-L outside B's normal cone at E_B";
  const V3l pA(0, a.y(), a.z());
  const V3l cB = pA + d * L + b.y() * R.col(1) + b.z() * R.col(2);
  const M3l Q = Eigen::AngleAxis<ld>(0.7L, V3l(1, 2, 3).normalized()).toRotationMatrix();
  const V3l cA = V3l::Zero();
  EdgePair p;
  p.a = {(where + Q * cA).cast<double>(), Q.cast<double>(), a.cast<double>()};
  p.b = {(where + Q * cB).cast<double>(), (Q * R).cast<double>(), b.cast<double>()};
  return p;
}

TEST(HardCase, FloatVsDoubleSat_NearParallelEdges) {
  const ld thetas[] = {1e-1L, 1e-2L, 1e-3L, 1e-4L, 1e-5L, 1e-6L, 1e-7L, 1e-9L, 0};
  const ld gaps[] = {-1e-3L, -1e-6L, 0, 1e-12L, 1e-9L, 1e-7L, 1e-6L, 1e-5L, 1e-4L, 1e-3L, 1e-2L};
  // Near the origin and at UTM; every coordinate of both centres within a factor 2 of the other, so
  // that moving the pair to A's centre is an exact subtraction.
  const V3l places[] = {V3l(64.0L, -32.0L, 16.0L), V3l(550012.5L, 4650033.25L, 812.0L)};
  int cases = 0, floatInBand = 0, doubleInBand = 0;
  for (const V3l& place : places)
    for (ld theta : thetas) {
      // The band each path showed: the largest reference margin it still called overlapping.
      ld doubleBand = 0, floatBand = 0;
      for (ld d : gaps) {
        const EdgePair p = nearParallelEdges(theta, d, place);
        char where[160];
        std::snprintf(where, sizeof where, "theta %.0Le rad, d %+.0Le m, at %s", theta, d,
                      place.x() > 1000 ? "UTM" : "the origin");
        // The reference on the pair moved to A's centre (an exact shift of nearby doubles), so that
        // the rounding window is that of the local frame both engine paths work in.
        const Obb<double> aL = shifted(p.a, -p.a.center), bL = shifted(p.b, -p.a.center);
        ASSERT_EQ(bL.center + p.a.center, p.b.center) << "the shift must be exact";
        const SatRef r = ldSat(aL, bL);
        // The construction: margin d (the 15 axes certify the distance of an edge-edge pair), up to the
        // rounding of the boxes to double (the centre's ulp at UTM, axes' 1e-16 over 1/sin(theta)).
        if (theta >= 1e-4L && d >= 0) {
          const ld tol = 1e-12L + 1e-15L / theta + (place.x() > 1000 ? 2e-9L : 0);
          EXPECT_NEAR(double(r.margin), double(d), double(tol)) << where;
        }
        const ld wDouble = 32 * kUnitRound * (r.extent + r.absCoord);
        const ld wFloat = 64 * kFloatRound * (r.extent + r.absCoord);
        const Expect needDouble = expectInflated(r, kDoubleModel, wDouble, true);
        const Expect needFloat = expectInflated(r, kFloatModel, wFloat, true);
        const bool dbl = satObbObb(p.a, p.b).overlap;
        const bool dblLocal = satObbObb(aL, bL).overlap;
        const bool flt = floatPathOverlaps(p.a, p.b);
        const NestedResult pair = testBoxPair(p.a, p.b);
        const bool batch = batchResult(p.a, p.b).overlap;
        expectVerdict("satObbObb<double> (map frame)", dbl, needDouble, where);
        expectVerdict("satObbObb<double> (local frame)", dblLocal, needDouble, where);
        expectVerdict("testBoxPair", pair.overlap, needDouble, where);
        expectVerdict("satObbObb<float> (conservative)", flt, needFloat, where);
        expectVerdict("testBoxPairs", batch, needDouble, where);
        EXPECT_EQ(batch, pair.overlap) << "testBoxPairs must return testBoxPair's verdict -- " << where;
        if (!flt) {
          EXPECT_FALSE(dblLocal) << "float separated a pair double calls overlapping -- " << where;
        }
        ++cases;
        floatInBand += r.margin > 0 && flt;
        doubleInBand += r.margin > 0 && dblLocal;
        if (dblLocal && r.margin > doubleBand) doubleBand = r.margin;
        if (flt && r.margin > floatBand) floatBand = r.margin;
      }
      std::printf("  theta %-6.0Le at %-6s largest separation called overlap: double %.1Le m, float %.1Le m\n", theta,
                  place.x() > 1000 ? "UTM" : "origin", doubleBand, floatBand);
    }
  std::printf("  %d pairs; separated pairs reported overlapping (inside the documented bands): double %d, float %d\n",
              cases, doubleInBand, floatInBand);
}

// ------------------------------------------------------------------------------------------------
// Situation: touching and flat boxes (panels with a zero half extent, poles, points), float vs
// double vs exact. Rational boxes in units of 2^-32 m, so that a gap of 2^-30 m is an integer; the
// rotations are the identity, a quarter turn (exact in binary) or the 3-4-5 yaw about z, which
// rounds only the x and y of the axes (the contacts below are along z or along a quarter-turned
// face, so the rounded doubles have exactly the contact of the rational boxes; ldSat on the doubles
// confirms it case by case). Exact answer: exactSat (integers).
constexpr ld kUnit = 0x1p-32L;  // metres per integer unit
constexpr i64 kMetre = i64(1) << 32;

i64 metres(double m) { return i64(std::llround(m * double(kMetre))); }

ExactBox exactBox(const V3& centre, const V3& half, const IntRotation& rot) {
  ExactBox b;
  for (int k = 0; k < 3; ++k) {
    b.c[k] = metres(centre[k]);
    b.e[k] = metres(half[k]);
  }
  b.den = 1;
  b.rot = rot;
  return b;
}

struct ExactCase {
  std::string name;
  ExactBox a, b;
  i64 gap;        // the construction's offset in units (0: touching)
  bool separated;  // by construction: gap > 0, and for two parallel panels any gap != 0
};

IntRotation yaw345() { return IntRotation::aboutAxis(2, 4, 3, 5); }
IntRotation quarterYaw() { return IntRotation::aboutAxis(2, 0, 1, 1); }
IntRotation quarterPitch() { return IntRotation::aboutAxis(0, 0, 1, 1); }

std::vector<ExactCase> touchingAndFlatCases() {
  std::vector<ExactCase> out;
  const i64 gaps[] = {-(i64(1) << 2), 0, 4, i64(1) << 12, i64(1) << 22};  // -2^-30, 0, 2^-30, 2^-20, 2^-10 m
  const IntRotation I = IntRotation::identity();
  for (i64 g : gaps) {
    const std::string tag = "gap " + std::to_string(double(g) * double(kUnit)) + " m";
    // A 3-4-5 yawed panel lying on a box's top (z = 0).
    ExactCase c{"panel on box top, " + tag, exactBox(V3(0, 0, -0.5), V3(1, 0.5, 0.5), I),
                exactBox(V3(0.25, 0.125, 0), V3(0.625, 0.375, 0), yaw345()), g, g > 0};
    c.b.c[2] += g;
    out.push_back(c);
    // Two coplanar panels (both flat along z), one yawed: touching is coplanar contact.
    c = {"coplanar panels, " + tag, exactBox(V3(0, 0, 0), V3(0.75, 0.5, 0), I),
         exactBox(V3(0.25, 0.25, 0), V3(0.5, 0.25, 0), yaw345()), g, g != 0};
    c.b.c[2] += g;
    out.push_back(c);
    // A quarter-yawed vertical panel (flat along its own y, i.e. world x) against a box's +x face.
    c = {"vertical panel against a side, " + tag, exactBox(V3(0, 0, 0.5), V3(0.5, 1, 0.5), I),
         exactBox(V3(0.5, 0.25, 0.75), V3(0.75, 0, 0.5), quarterYaw()), g, g > 0};
    c.b.c[0] += g;
    out.push_back(c);
    // Boxes meeting corner to corner (B quarter-pitched: a full 15-axis case with exact axes).
    c = {"corner to corner, " + tag, exactBox(V3(0.5, 0.5, 0.5), V3(0.5, 0.5, 0.5), I),
         exactBox(V3(1.25, 1.125, 1.0625), V3(0.25, 0.0625, 0.125), quarterPitch()), g, g > 0};
    for (int k = 0; k < 3; ++k) c.b.c[k] += g;
    out.push_back(c);
    // A point (all half extents zero) on a 3-4-5 yawed box's top.
    c = {"point on a yawed box's top, " + tag, exactBox(V3(0, 0, -0.25), V3(0.5, 0.5, 0.25), yaw345()),
         exactBox(V3(0.125, 0.0625, 0), V3(0, 0, 0), I), g, g > 0};
    c.b.c[2] += g;
    out.push_back(c);
    // A zero-width pole (a segment) standing on a flat panel.
    c = {"pole on a panel, " + tag, exactBox(V3(0, 0, 0), V3(0.5, 0.5, 0), yaw345()),
         exactBox(V3(0.0625, 0.125, 1.5), V3(0, 0, 1.5), yaw345()), g, g > 0};
    c.b.c[2] += g;
    out.push_back(c);
  }
  return out;
}

TEST(HardCase, FloatVsDoubleSat_TouchingAndFlatBoxes) {
  std::map<std::string, int> floatBand;
  for (const ExactCase& c : touchingAndFlatCases()) {
    const SatRef exact = exactSat(c.a, c.b);
    ASSERT_EQ(exact.separated, c.separated) << c.name << ": the construction";
    const Obb<double> a = c.a.toObb(double(kUnit)), b = c.b.toObb(double(kUnit));
    // The rounded doubles keep the contact: same sign of the certified margin, within the rounding.
    const SatRef onDoubles = ldSat(a, b);
    EXPECT_EQ(onDoubles.margin > 1e-15L, exact.separated) << c.name << ": ld margin " << double(onDoubles.margin);
    // The distance between the boxes (0 when they touch or cross).
    const double gap = c.separated ? std::abs(double(c.gap) * double(kUnit)) : 0.0;
    // Double: exact answers here (the gaps are >= 2^-30 m, 100x the documented slack of these sizes).
    EXPECT_EQ(satObbObb(a, b).overlap, gap <= 0) << c.name << ": satObbObb<double>(A, B)";
    EXPECT_EQ(satObbObb(b, a).overlap, gap <= 0) << c.name << ": satObbObb<double>(B, A)";
    EXPECT_EQ(testBoxPair(a, b).overlap, gap <= 0) << c.name << ": testBoxPair";
    EXPECT_EQ(testNested(NestedVolume<double>::fromObb(a), NestedVolume<double>::fromObb(b)).overlap, gap <= 0)
        << c.name << ": testNested";
    EXPECT_EQ(batchResult(a, b).overlap, gap <= 0) << c.name << ": testBoxPairs";
    // Float: never a missed contact; separated beyond its band (2^-10 m here); either inside it.
    const bool flt = floatPathOverlaps(a, b);
    if (gap <= 0) {
      EXPECT_TRUE(flt) << c.name << ": float missed a contact";
    }
    if (gap >= 0x1p-10) {
      EXPECT_FALSE(flt) << c.name << ": float did not separate a 1 mm gap";
    }
    if (gap > 0 && gap < 0x1p-10 && flt) ++floatBand[c.name.substr(0, c.name.find(','))];
  }
  for (const auto& [name, n] : floatBand) std::printf("  float inside its band (2^-30 / 2^-20 m gaps called overlap): %s x%d\n", name.c_str(), n);
}

// ------------------------------------------------------------------------------------------------
// Situation: UTM magnitudes vs the origin. The exact pairs above moved to map coordinates (offsets
// whose sum with the 2^-32 m grid is exact in double: the moved pairs are the same rational boxes)
// go through testBoxPair, whose answer must be the exact one (the near-parallel pairs at UTM are
// checked against ldSat in the first case). The swept test, a local-frame operation, runs on each
// pair at the origin and moved back from every offset by an exact subtraction: A moves by
// d = 1.5 (cB - cA) (its centre crosses B's at t = 2/3, so they meet). Exact answer for the pairs
// whose axes are exact in binary (identity or quarter turns: both boxes are then world-aligned
// boxes): the first contact time by the slab intervals of the exact AABBs (Ericson 5.5.8),
// t* = max(0, max_k enter_k); the sweep must report it, never later, at most 1e-9 m earlier.
struct SlabSweep {
  bool contact;
  ld t;
};

SlabSweep exactSlabSweep(const ExactCase& c, const V3l& d) {
  auto bounds = [](const ExactBox& x, V3l& lo, V3l& hi) {
    for (int i = 0; i < 3; ++i) {
      ld h = 0;
      for (int j = 0; j < 3; ++j) h += ld(std::llabs(x.rot.m[i][j])) / ld(x.rot.s) * ld(x.e[j]) / ld(x.den);
      const ld m = ld(x.c[i]) / ld(x.den);
      lo[i] = (m - h) * kUnit;
      hi[i] = (m + h) * kUnit;
    }
  };
  V3l aLo, aHi, bLo, bHi;
  bounds(c.a, aLo, aHi);
  bounds(c.b, bLo, bHi);
  ld enter = -std::numeric_limits<ld>::infinity(), exit = std::numeric_limits<ld>::infinity();
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0) {
      if (aHi[k] < bLo[k] || bHi[k] < aLo[k]) return {false, 0};
      continue;
    }
    const ld t0 = (bLo[k] - aHi[k]) / d[k], t1 = (bHi[k] - aLo[k]) / d[k];
    enter = std::max(enter, std::min(t0, t1));
    exit = std::min(exit, std::max(t0, t1));
  }
  const bool contact = enter <= exit && enter <= 1 && exit >= 0;
  return {contact, std::max(enter, ld(0))};
}

TEST(HardCase, UtmVsOrigin_BoxPairs) {
  const V3 offsets[] = {V3(550000, 4650000, 1000), V3(323476.0625, 5105081.9375, 1512.5), V3(-799999.75, 7999999.5, -30)};
  int pairs = 0, sweeps = 0;
  for (const ExactCase& c : touchingAndFlatCases()) {
    const bool truth = !exactSat(c.a, c.b).separated;
    const Obb<double> a = c.a.toObb(double(kUnit)), b = c.b.toObb(double(kUnit));
    const V3 d = 1.5 * (b.center - a.center);
    const bool exactAxes = c.a.rot.isDyadic() && c.b.rot.isDyadic();
    const SlabSweep want = exactSlabSweep(c, d.cast<ld>());
    auto checkSweep = [&](const Obb<double>& sa, const Obb<double>& sb, const char* frame) {
      const SweptNestedResult r = sweepNested(NestedVolume<double>::fromObb(sa), d, NestedVolume<double>::fromObb(sb));
      EXPECT_TRUE(r.contact) << c.name << " (" << frame << "): A's centre crosses B's";
      if (!exactAxes) return;
      ASSERT_TRUE(want.contact) << c.name;
      EXPECT_LE(ld(r.t), want.t + 1e-15L) << c.name << " (" << frame << "): contact reported late";
      EXPECT_LE((want.t - ld(r.t)) * ld(d.norm()), 1e-9L) << c.name << " (" << frame << "): contact reported early";
      ++sweeps;
    };
    checkSweep(a, b, "origin");
    for (const V3& off : offsets) {
      const Obb<double> am = shifted(a, off), bm = shifted(b, off);
      ASSERT_EQ(shifted(am, -off).center, a.center) << "offset not exact";
      ASSERT_EQ(shifted(bm, -off).center, b.center) << "offset not exact";
      EXPECT_EQ(testBoxPair(am, bm).overlap, truth) << c.name << " at " << off.transpose();
      checkSweep(shifted(am, -am.center), shifted(bm, -am.center), "moved back from UTM");
      ++pairs;
    }
  }
  std::printf("  %d pairs at three map offsets as exact as at the origin; %d sweeps at their exact contact time\n", pairs,
              sweeps);
}

// ------------------------------------------------------------------------------------------------
// Situation: poles. A zero-width pole (a segment, two zero half extents) and a 5 cm prism yawed by
// 3-4-5, both 3 m tall, against the walker's body box (0.25 x 0.25 x 0.9 half extents) moving north
// by steps of 0.5 m/s to 100 m per step. Exact answer (closed form): the body's front y = 0.25 meets
// the pole's near face y = 5 - w (w = the pole's half width along y: 0, or 0.025 (4 + 3)/5 = 0.035)
// at t* = (4.75 - w) / L when the x ranges meet, i.e. the lateral offset x0 satisfies
// |x0| <= 0.25 + w (touching sideways counts); none otherwise. The swept nested test must report the
// contact iff t* <= 1 and never later than t* (a late contact lets the walker into the pole); it may
// be early only by the rounding bands (1e-9 m along the motion here).
TEST(HardCase, Poles_SweptContactIsExactAndNeverLate) {
  const Obb<double> body{V3(0, 0, 0.9), M3::Identity(), V3(0.25, 0.25, 0.9)};
  struct Pole {
    const char* name;
    V3 half;
    IntRotation rot;
    ld w;  // half width along x and y
  };
  const Pole poles[] = {{"segment", V3(0, 0, 1.5), yaw345(), 0}, {"5 cm prism", V3(0.025, 0.025, 1.5), yaw345(), 0.035L}};
  const double steps[] = {0.5 / 60, 1.4 / 60, 50.0 / 60, 4.75, 10.0, 100.0};
  for (const Pole& p : poles)
    for (int lateral = 0; lateral < 5; ++lateral) {
      // Lateral offsets: centred, half-way, exactly grazing (only for the segment, where 0.25 + w is a
      // double), 1e-6 m clear, 5 cm clear.
      const ld reach = 0.25L + p.w;
      const ld x0 = lateral == 0 ? 0 : lateral == 1 ? reach / 2 : lateral == 2 ? reach : lateral == 3 ? reach + 1e-6L : reach + 0.05L;
      if (lateral == 2 && p.w != 0) continue;
      Obb<double> pole{V3(double(x0), 5, 1.5), p.rot.toDouble(), p.half};
      const bool meets = x0 <= reach;
      for (double L : steps) {
        const SweptNestedResult r = sweepNested(NestedVolume<double>::fromObb(body), V3(0, L, 0), NestedVolume<double>::fromObb(pole));
        const ld tStar = (4.75L - p.w) / ld(L);
        const bool contact = meets && tStar <= 1;
        EXPECT_EQ(r.contact, contact) << p.name << " x0 " << double(x0) << " step " << L << " t* " << double(tStar);
        if (r.contact && contact) {
          EXPECT_LE(ld(r.t), tStar + 1e-15L) << p.name << ": contact reported late, step " << L;
          EXPECT_LE((tStar - ld(r.t)) * ld(L), 1e-9L) << p.name << ": contact reported early, step " << L;
        }
      }
    }
}

}  // namespace
}  // namespace nestwalk
