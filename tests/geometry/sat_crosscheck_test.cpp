// Randomised cross-checks of the overlap tests (sat.h, nested.h) against independent oracles:
//   (a) the exact integer reference of sat_reference.h (rational boxes, __int128),
//   (b) FCL's fcl::OBB<double>::overlap / fcl::AABB<double>::overlap,
//   (c) the float instantiation of the same SAT (near the origin), required never to miss a contact
//       and to over-report only inside its documented band.
//
// Data. Every pair is a pair of exact rational boxes: integer centres and half extents in a
// power-of-two unit (so they convert to double exactly) and rational rotations M / s from integer
// quaternions (components in [-6, 6]); the double boxes carry M / s correctly rounded, so they
// differ from the exact boxes by ~1e-16 relative. Three classes:
//   coarse: unit 2^-6 m, log-uniform half extents 0..16 m (12% of components zero: panels, poles,
//           points), centres within +-64 m;
//   tiny:   unit 2^-6 m, half extents 0..4 units, quaternions in [-2, 2]: exact touching is frequent;
//   fine:   unit 2^-40 m, centres up to 2^50 units (1 km), every bit of the double significand used.
// 20% of the pairs are snapped to exact contact along a world axis (a face of an aligned box against
// the extreme of the other box). The centre offsets are scaled to the two boxes' AABBs so that about
// half the pairs overlap. Fixed seeds.
//
// Bands (what "inside the band" means; everything outside must agree with the exact answer):
//   sat.h documents two tolerances: eps = kParallelEpsilon (1e-12 double, 1e-6 float) added to |R|,
//   and a rounding slack kRoundingSlack (1e-12 double, 2e-6 float) times M = |cB - cA|_1 + all half
//   extents on every comparison (plus, for satAabbObb, 8 epsilon times the AABB's |min| + |max|). So
//   it separates on axis L iff gap_L > eps * infl_L + slack (gap unnormalised, infl = the half
//   extents eps multiplies; see SatModel in sat_reference.h), and a "separated" verdict is exact:
//   it never misses a contact. FCL does the same with its reps = 1e-6 and no slack. Rounding
//   window of the comparison with the model: w = 32 u (|T|_1 + sum of half extents + max |centre
//   coordinate|), u = 2^-53 (double) or 2^-24 (float), which bounds the rounding of the axes (M/s),
//   t = A^T (cB - cA), R = A^T B and the AABB corners. A disagreement with the exact answer is
//   "in band" when
//     - false overlap: every axis has gap <= eps * infl + slack + w (the documented band);
//     - missed contact: never, for the engine (double and float): its slack covers its rounding and
//       the ~1e-16 rounding of the axes, so "separated" must mean exactly separated. For FCL (no
//       slack) a missed contact is in band when some axis has gap > eps * infl - w, except for pairs
//       whose doubles are exactly the rational boxes (dyadic rotations, points); FCL's misses of
//       exact contacts are counted as "uncovered-rounding misses" (FCL's, not the engine's).
//   The suggested "|margin| <= 1e-9 * size" band is printed too (max |margin| / size over
//   disagreements), but not asserted: near-parallel edge axes of these rotations have sin(theta)
//   down to ~1e-5, so the documented band (eps S + slack) / sin(theta) can exceed 1e-9 * size.
#include "tests/geometry/sat_reference.h"

#include "nestwalk/geometry/nested.h"
#include "nestwalk/geometry/sat.h"

#include <Eigen/Geometry>
#include <fcl/math/bv/AABB.h>
#include <fcl/math/bv/OBB.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace nestwalk {
namespace {

using namespace nestwalk::testref;

// Pairs per check (NESTWALK_SAT_PAIRS overrides, for quick runs).
const long kPairs = [] {
  const char* v = std::getenv("NESTWALK_SAT_PAIRS");
  return v ? std::atol(v) : 1'000'000L;
}();
constexpr ld kU = 1.1102230246251565e-16L;  // 2^-53
constexpr ld kUf = 5.9604644775390625e-8L;  // 2^-24
// The documented tolerances (sat.h) and FCL's.
const SatModel kEngine{kParallelEpsilon<double>, kRoundingSlack<double>, 0};
const SatModel kEngineF{kParallelEpsilon<float>, kRoundingSlack<float>, 0};
const SatModel kFcl{1e-6L, 0, 0};  // obbDisjoint's 'reps'
const SatModel kExact{};
// satAabbObb's input rounding: 8 epsilon times sum_k |min_k| + |max_k| of the AABB (units of r).
template <class T>
SatModel engineAabbObb(ld minMaxSum) {
  return {kParallelEpsilon<T>, kRoundingSlack<T>, 8 * ld(std::numeric_limits<T>::epsilon()) * minMaxSum};
}
ld minMaxSum(const ExactBox& aabb) {  // sum_k |min_k| + |max_k| of an axis-aligned ExactBox
  ld s = 0;
  for (int k = 0; k < 3; ++k) s += (std::fabs(ld(aabb.c[k] - aabb.e[k])) + std::fabs(ld(aabb.c[k] + aabb.e[k]))) / aabb.den;
  return s;
}

enum class Cls { Coarse, Tiny, Fine };

struct Gen {
  std::mt19937_64 rng;
  explicit Gen(std::uint64_t seed) : rng(seed) {}
  i64 uni(i64 lo, i64 hi) { return std::uniform_int_distribution<i64>(lo, hi)(rng); }
  double real(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
  bool chance(double p) { return real(0, 1) < p; }

  Cls cls() {
    const double r = real(0, 1);
    return r < 0.6 ? Cls::Coarse : r < 0.85 ? Cls::Tiny : Cls::Fine;
  }
  IntRotation rotation(Cls c, bool allowRotation) {
    if (!allowRotation || chance(c == Cls::Tiny ? 0.3 : 0.25)) return IntRotation::identity();
    if (chance(0.07)) {  // signed permutations (dyadic: exact in double, not the identity)
      static const int q[][4] = {{1, 1, 0, 0}, {1, 0, 1, 0}, {1, 0, 0, 1}, {0, 1, 0, 0}, {0, 0, 1, 0},
                                 {0, 0, 0, 1}, {1, 1, 1, 1}, {0, 1, 1, 0}, {1, -1, 1, -1}, {0, 1, 0, -1}};
      const auto& p = q[uni(0, 9)];
      return IntRotation::fromQuaternion(p[0], p[1], p[2], p[3]);
    }
    const i64 m = c == Cls::Tiny ? 2 : 6;
    for (;;) {
      const i64 w = uni(-m, m), x = uni(-m, m), y = uni(-m, m), z = uni(-m, m);
      if (w || x || y || z) return IntRotation::fromQuaternion(w, x, y, z);
    }
  }
  i64 halfExtent(Cls c) {
    switch (c) {
      case Cls::Tiny: return uni(0, 4);
      case Cls::Coarse: return chance(0.12) ? 0 : uni(1, i64(1) << uni(0, 10));
      case Cls::Fine: return chance(0.12) ? 0 : uni(1, i64(1) << uni(20, 40));
    }
    return 0;
  }
  i64 centreRange(Cls c) { return c == Cls::Fine ? (i64(1) << 50) : c == Cls::Tiny ? 64 : 4096; }
};

double unitOf(Cls c) { return c == Cls::Fine ? std::ldexp(1.0, -40) : 1.0 / 64; }

enum class Kind { AabbAabb, AabbObb, ObbObb };

struct Pair {
  ExactBox a, b;
  Cls cls;
  double unit;
  bool snapped = false;
};

// A rational box, optionally with half extents that are multiples of the rotation's s (then its
// extent along every world axis, sum_j |M_ij| e_j / s, is an integer: exact contact can be snapped).
ExactBox randomBox(Gen& g, Cls c, bool rotated, bool integerAabb) {
  ExactBox b;
  b.rot = g.rotation(c, rotated);
  for (int k = 0; k < 3; ++k) {
    b.e[k] = g.halfExtent(c);
    if (integerAabb && b.rot.s > 1) b.e[k] = (c == Cls::Fine ? b.e[k] / b.rot.s + 1 : b.e[k]) * b.rot.s;
  }
  return b;
}

// Extent along world axis k of an ExactBox with den 1 whose AABB half extents are integers.
i64 worldExtent(const ExactBox& b, int k) {
  i64 h = 0;
  for (int j = 0; j < 3; ++j) h += std::llabs(b.rot.m[k][j]) * b.e[j];
  return h / b.rot.s;
}

Pair makePair(Gen& g, Kind kind) {
  Pair p;
  p.cls = g.cls();
  p.unit = unitOf(p.cls);
  const bool snap = g.chance(0.2);
  p.snapped = snap;
  const i64 R = g.centreRange(p.cls);
  // B: an OBB (or an AABB for AabbAabb) with den 1.
  p.b = randomBox(g, p.cls, kind != Kind::AabbAabb, snap);
  for (int k = 0; k < 3; ++k) p.b.c[k] = g.uni(-R, R);
  // A: centre offset from B scaled to the AABBs so that about half the pairs overlap.
  ExactBox a = randomBox(g, p.cls, kind == Kind::ObbObb, snap);
  const ExactBox aa = a.aabb(), ba = p.b.aabb();
  // 8% far pairs (up to 2.5x the AABB sum away: exercises the AABB stage of the cascades).
  const double f = (kind == Kind::AabbAabb ? 1.4 : kind == Kind::AabbObb ? 1.05 : 0.7) * (g.chance(0.08) ? 2.5 : 1.0);
  for (int k = 0; k < 3; ++k) {
    const ld h = ld(aa.e[k]) / aa.den + ld(ba.e[k]) / ba.den;
    a.c[k] = p.b.c[k] + i64(std::llround(g.real(-f, f) * double(h)));
  }
  if (snap) {
    // Exact contact along world axis k: A's extreme (an aligned face or a rotated box's extreme
    // vertex/edge) at B's extreme on the other side.
    const int k = int(g.uni(0, 2));
    const i64 side = g.chance(0.5) ? 1 : -1;
    a.c[k] = p.b.c[k] + side * (worldExtent(p.b, k) + worldExtent(a, k));
  }
  if (kind == Kind::ObbObb) {
    p.a = a;
  } else {
    // A given as an AABB [min, max] (den 2). AabbAabb/AabbObb: min/max straight from integers, with
    // an odd width now and then (half-integer centre).
    std::array<i64, 3> mn, mx;
    for (int k = 0; k < 3; ++k) {
      mn[k] = a.c[k] - a.e[k];
      mx[k] = a.c[k] + a.e[k] + (snap || !g.chance(0.3) ? 0 : 1);
    }
    p.a = ExactBox::fromMinMax(mn, mx);
  }
  if (kind == Kind::AabbAabb) {
    // B as min/max too.
    std::array<i64, 3> mn, mx;
    for (int k = 0; k < 3; ++k) {
      mn[k] = p.b.c[k] - p.b.e[k];
      mx[k] = p.b.c[k] + p.b.e[k];
    }
    p.b = ExactBox::fromMinMax(mn, mx);
  }
  return p;
}

bool representable(const ExactBox& b) {
  const bool point = b.e[0] == 0 && b.e[1] == 0 && b.e[2] == 0;
  if (point) {
    ExactBox c = b;
    c.rot = IntRotation::identity();
    return c.exactInDouble();
  }
  return b.exactInDouble();
}

ld windowOf(const SatRef& r, ld u) { return 32 * u * (r.extent + r.absCoord); }

// ------------------------------------------------------------------------------------------------
// Tallies.

// An answer is acceptable when it is the exact one and the model does not contradict it, or when it
// differs from the exact one inside the band.
bool acceptable(bool got, bool exactSep, Expect e) {
  if (got == !exactSep) return !((e == Expect::Overlap && !got) || (e == Expect::Separated && got));
  return got ? e != Expect::Separated : e != Expect::Overlap;
}

struct Tally {
  explicit Tally(std::string n) : name(std::move(n)) {}
  std::string name;
  long pairs = 0, reportedOverlap = 0, agree = 0, falseOverlapInBand = 0, missedInBand = 0, outside = 0;
  long modelMismatch = 0;  // agrees with the exact answer, but contradicts the inflated model beyond w
  // Missed contacts of exactly representable pairs that are inside the rounding window: the
  // computation rounds (t = A^T (cB - cA), R = A^T B through a rotated frame) where the |R| + eps
  // inflation is zero or too small to cover it (a box with zero or tiny half extents). Reported
  // separately; the engine must have none (asserted), FCL has some (printed).
  long uncoveredRoundingMiss = 0;
  ld maxRelMargin = 0;  // max |margin| / size over the in-band disagreements
  std::vector<std::string> examples, bugExamples;

  // got: the oracle's answer; exactSep: the exact answer; e: the model's expectation; eLoose: the
  // same without the strict no-miss rule (Either when the oracle is not described by the model).
  // Returns true when the answer is outside the band (the caller records an example).
  bool add(bool got, bool exactSep, Expect e, const SatRef& r, Expect eLoose = Expect::Either) {
    ++pairs;
    if (got) ++reportedOverlap;
    bool bad = false;
    if (got == !exactSep) {
      ++agree;
      if ((e == Expect::Overlap && !got) || (e == Expect::Separated && got)) {
        ++modelMismatch;
        bad = true;
      }
    } else if (got) {  // false overlap
      if (e == Expect::Separated) {
        ++outside;
        bad = true;
      } else {
        ++falseOverlapInBand;
      }
    } else {  // missed contact
      if (e == Expect::Overlap && eLoose != Expect::Overlap) {
        ++uncoveredRoundingMiss;
        lastWasBug = true;
        return false;
      } else if (e == Expect::Overlap) {
        ++outside;
        bad = true;
      } else {
        ++missedInBand;
      }
    }
    lastWasBug = false;
    if (got != !exactSep && !bad && r.extent > 0)
      maxRelMargin = std::max(maxRelMargin, std::fabs(r.margin) / r.extent);
    return bad;
  }
  bool lastWasBug = false;
  void note(const std::string& what) {
    if (examples.size() < 5) examples.push_back(what);
  }
  void noteBug(const std::string& what) {
    if (bugExamples.size() < 2) bugExamples.push_back(what);
  }
  void print() const {
    std::printf(
        "  %-34s pairs %8ld  overlap %8ld  agree %8ld  in band: false-overlap %6ld missed %5ld  "
        "(max |margin|/size %.2Le)  OUTSIDE %ld  model-mismatch %ld  uncovered-rounding misses %ld\n",
        name.c_str(), pairs, reportedOverlap, agree, falseOverlapInBand, missedInBand, maxRelMargin, outside,
        modelMismatch, uncoveredRoundingMiss);
    for (const auto& ex : examples) std::printf("    ! %s\n", ex.c_str());
    for (const auto& ex : bugExamples) std::printf("    bug: %s\n", ex.c_str());
  }
  void expectClean() const {
    EXPECT_EQ(outside, 0) << name;
    EXPECT_EQ(modelMismatch, 0) << name;
    for (const auto& ex : examples) ADD_FAILURE() << name << ": " << ex;
  }
};

struct Census {
  long pairs = 0, exactOverlap = 0, exactTouching = 0, representablePairs = 0, snapped = 0;
  long cls[3] = {0, 0, 0};
  void add(const Pair& p, const SatRef& r) {
    ++pairs;
    if (!r.separated) {
      ++exactOverlap;
      for (int k = 0; k < kAxes; ++k)
        if (r.len[k] > 0 && r.sign[k] == 0) {
          ++exactTouching;
          break;
        }
    }
    if (representable(p.a) && representable(p.b)) ++representablePairs;
    if (p.snapped) ++snapped;
    ++cls[int(p.cls)];
  }
  void print(const char* title) const {
    std::printf(
        "%s: %ld pairs (coarse %ld, tiny %ld, fine %ld), exact overlap %ld (%.1f%%), exact touching %ld, "
        "snapped %ld, exactly representable %ld\n",
        title, pairs, cls[0], cls[1], cls[2], exactOverlap, 100.0 * exactOverlap / std::max(1L, pairs), exactTouching,
        snapped, representablePairs);
  }
};

std::string describe(const Pair& p, const SatRef& r) {
  auto box = [](const ExactBox& b) {
    char buf[400];
    std::snprintf(buf, sizeof buf, "c=(%lld,%lld,%lld)/%lld e=(%lld,%lld,%lld)/%lld M/s s=%lld m=[%lld %lld %lld; %lld %lld %lld; %lld %lld %lld]",
                  (long long)b.c[0], (long long)b.c[1], (long long)b.c[2], (long long)b.den, (long long)b.e[0],
                  (long long)b.e[1], (long long)b.e[2], (long long)b.den, (long long)b.rot.s, (long long)b.rot.m[0][0],
                  (long long)b.rot.m[0][1], (long long)b.rot.m[0][2], (long long)b.rot.m[1][0], (long long)b.rot.m[1][1],
                  (long long)b.rot.m[1][2], (long long)b.rot.m[2][0], (long long)b.rot.m[2][1], (long long)b.rot.m[2][2]);
    return std::string(buf);
  };
  char buf[200];
  std::snprintf(buf, sizeof buf, " unit=%.3g exact %s margin=%.3Le (axis %s)", p.unit,
                r.separated ? "separated" : "overlap", r.margin, axisName(r.marginAxis).c_str());
  return "A{" + box(p.a) + "} B{" + box(p.b) + "}" + buf;
}

fcl::OBB<double> toFcl(const Obb<double>& b) { return fcl::OBB<double>(b.axes, b.center, b.halfExtents); }

// The reported separating axis: must plausibly separate under the model and be the first such in
// the engine's order; with strict, its exact gap must be > 0.
template <class What>
void axisCheck(Tally& t, const SatRef& r, int axis, const SatModel& m, ld w, bool strict, const std::string& where,
               What what) {
  const std::string why = checkReportedAxis(r, axis, m, w, strict);
  if (why.empty()) return;
  ++t.outside;
  ADD_FAILURE() << where << ": " << why << " " << what();
}

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// ------------------------------------------------------------------------------------------------

TEST(SatCrossCheck, ReferenceSelfCheck) {
  // The tester's own tests: exact rotations, corner-projection numerators, the long double
  // reference against the exact one, and both orders.
  Gen g(20240601);
  long cornerChecks = 0, ldChecks = 0, ldVerdictDiff = 0;
  for (int it = 0; it < 20000; ++it) {
    const Kind kind = it % 3 == 0 ? Kind::AabbObb : Kind::ObbObb;
    Pair p = makePair(g, kind);
    if (p.cls == Cls::Fine) continue;  // corner sums grow past __int128 with 2^50 centres
    ASSERT_TRUE(p.a.rot.isExactRotation());
    ASSERT_TRUE(p.b.rot.isExactRotation());
    const SatRef r = exactSat(p.a, p.b);
    for (int k = 0; k < kAxes; ++k) {
      // __int128 numerator = corner projections = the sign exactSat reported (its int64 path included)
      const i128 n1 = exactNumerator(p.a, p.b, k), n2 = exactNumeratorByCorners(p.a, p.b, k);
      ASSERT_TRUE(n1 == n2) << "axis " << k << " " << describe(p, r);
      ASSERT_EQ(r.sign[k], sign128(n1)) << "axis " << k << " " << describe(p, r);
      ++cornerChecks;
    }
    // Symmetry of the exact reference.
    const SatRef rb = exactSat(p.b, p.a);
    ASSERT_EQ(r.separated, rb.separated) << describe(p, r);
    const SatRef rs = swapRoles(r);  // the renaming used by the cross-checks
    for (int k = 0; k < kAxes; ++k) ASSERT_EQ(rs.sign[k], rb.sign[k]) << "axis " << k << " " << describe(p, r);
    ASSERT_EQ(rs.firstAxis, rb.firstAxis);
    ASSERT_NEAR(double(r.margin), double(rb.margin), 1e-12 * double(1 + r.extent));
    // The long double reference on the double boxes agrees with the exact reference up to the
    // rounding of the axes (margins to ~1e-15 relative); the verdict may differ only for |margin| tiny.
    const Obb<double> da = p.a.toObb(p.unit), db = p.b.toObb(p.unit);
    bool consistent = false;
    const SatRef l = ldSatBothWays(da, db, consistent);
    ASSERT_TRUE(consistent) << describe(p, r);
    const ld scale = p.unit;
    ASSERT_NEAR(double(l.margin), double(r.margin * scale), 1e-14 * double((r.extent + r.absCoord) * scale))
        << describe(p, r);
    if (l.separated != r.separated) {
      ++ldVerdictDiff;
      ASSERT_LE(std::fabs(double(r.margin * scale)), 1e-14 * double((r.extent + r.absCoord) * scale));
    }
    ++ldChecks;
  }
  // Hand-checked values: q = (1, 0, 0, 1) is 90 degrees about z.
  const IntRotation rz = IntRotation::fromQuaternion(1, 0, 0, 1);
  EXPECT_EQ(rz.s, 2);
  EXPECT_EQ(rz.m[0][1], -2);
  EXPECT_EQ(rz.m[1][0], 2);
  EXPECT_EQ(rz.m[2][2], 2);
  EXPECT_TRUE(rz.isDyadic());
  // Unit cubes touching face to face: separated iff the offset exceeds 2.
  ExactBox u;
  u.e = {1, 1, 1};
  EXPECT_FALSE(exactSat(u, u.translated({2, 0, 0})).separated);
  EXPECT_TRUE(exactSat(u, u.translated({3, 0, 0})).separated);
  EXPECT_EQ(exactSat(u, u.translated({3, 0, 0})).firstAxis, 0);
  EXPECT_EQ(exactSat(u, u.translated({2, 0, 0})).margin, 0);
  std::printf("reference self-check: %ld corner checks, %ld long-double checks (%ld verdicts differ, all at |margin| ~ 0)\n",
              cornerChecks, ldChecks, ldVerdictDiff);
}

TEST(SatCrossCheck, AabbAabb) {
  const auto t0 = std::chrono::steady_clock::now();
  Gen g(1001);
  Census census;
  Tally eng{"satAabbAabb<double> vs exact"}, fcl{"fcl::AABB::overlap vs exact"}, flt{"satAabbAabb<float> vs exact"};
  for (long it = 0; it < kPairs; ++it) {
    const Pair p = makePair(g, Kind::AabbAabb);
    const SatRef r = exactSat(p.a, p.b, true);
    census.add(p, r);
    const Aabb<double> a = p.a.toAabb(p.unit), b = p.b.toAabb(p.unit);
    // Both are exact in double: the answer must be exact, no band (eps 0, window 0, strict).
    const Expect e = expectInflated(r, kExact, 0, true, true);
    const SatResult s = satAabbAabb(a, b);
    if (eng.add(s.overlap, r.separated, e, r)) eng.note(describe(p, r));
    if (!s.overlap && r.separated) {
      // The reported axis is the first separating world axis.
      EXPECT_EQ(s.axis, r.firstAxis) << describe(p, r);
    }
    fcl::AABB<double> fa(a.min, a.max), fb(b.min, b.max);
    if (fcl.add(fa.overlap(fb), r.separated, e, r)) fcl.note(describe(p, r));
    if (p.cls != Cls::Fine) {  // float near the origin: coarse/tiny integers are exact in float
      if (flt.add(satAabbAabb(a.cast<float>(), b.cast<float>()).overlap, r.separated, e, r)) flt.note(describe(p, r));
    }
  }
  census.print("AABB-AABB");
  eng.print();
  fcl.print();
  flt.print();
  eng.expectClean();
  fcl.expectClean();
  flt.expectClean();
  EXPECT_EQ(eng.agree, eng.pairs);
  EXPECT_EQ(fcl.agree, fcl.pairs);
  EXPECT_EQ(flt.agree, flt.pairs);
  EXPECT_GT(census.exactTouching, kPairs / 20);
  EXPECT_NEAR(double(census.exactOverlap) / census.pairs, 0.5, 0.12);
  std::printf("  time %.2f s\n", seconds(t0));
}

// One OBB-type test run through the engine, FCL and float; `kind` says whether A is an AABB.
void runSatCheck(Kind kind, std::uint64_t seed, const char* title) {
  const auto t0 = std::chrono::steady_clock::now();
  Gen g(seed);
  Census census;
  Tally eng{std::string(title) + " <double> vs exact"}, fcl{"fcl::OBB::overlap vs exact"},
      flt{std::string(title) + " <float> vs exact"}, sym{"symmetry (B, A) vs exact"};
  long engFclDiff = 0, engFclDiffExplained = 0;
  for (long it = 0; it < kPairs; ++it) {
    const Pair p = makePair(g, kind);
    const SatRef r = exactSat(p.a, p.b);
    census.add(p, r);
    const bool strict = representable(p.a) && representable(p.b);
    const ld w = windowOf(r, kU);
    const Obb<double> b = p.b.toObb(p.unit);
    SatResult s;
    Obb<double> aObb;
    SatModel model = kEngine, modelF = kEngineF;
    if (kind == Kind::AabbObb) {
      const Aabb<double> a = p.a.toAabb(p.unit);
      s = satAabbObb(a, b);
      aObb = Obb<double>::fromAabb(a);
      model = engineAabbObb<double>(minMaxSum(p.a));
      modelF = engineAabbObb<float>(minMaxSum(p.a));
    } else {
      aObb = p.a.toObb(p.unit);
      s = satObbObb(aObb, b);
    }
    auto what = [&] { return describe(p, r); };
    // The engine: never a missed contact (strict for every pair).
    const Expect e = expectInflated(r, model, w, true);
    if (eng.add(s.overlap, r.separated, e, r, e)) eng.note(what());
    if (!s.overlap) axisCheck(eng, r, s.axis, model, w, true, title, what);
    if (kind == Kind::ObbObb) {
      const SatResult sb = satObbObb(b, aObb);
      const SatRef rb = swapRoles(r);
      const Expect eb = expectInflated(rb, model, w, true);
      if (sym.add(sb.overlap, rb.separated, eb, rb, eb)) sym.note(what());
      if (!sb.overlap) axisCheck(sym, rb, sb.axis, model, w, true, std::string(title) + " (B, A)", what);
    }
    // FCL: eps = 1e-6, no slack: strict only where the doubles are the exact boxes.
    const bool f = toFcl(aObb).overlap(toFcl(b));
    const Expect ef = expectInflated(r, kFcl, w, strict), efLoose = expectInflated(r, kFcl, w, false);
    if (fcl.add(f, r.separated, ef, r, efLoose)) fcl.note(what());
    if (fcl.lastWasBug) fcl.noteBug(what());
    if (f != s.overlap) {
      ++engFclDiff;
      // Explained when each answer is within its own documented band (the rounding window included).
      if (acceptable(s.overlap, r.separated, e) && acceptable(f, r.separated, efLoose)) ++engFclDiffExplained;
    }
    // Float near the origin (coarse and tiny classes: centres within 64 m): never a missed contact.
    if (p.cls != Cls::Fine) {
      const ld wf = windowOf(r, kUf);
      const Expect e32 = expectInflated(r, modelF, wf, true);
      bool got;
      if (kind == Kind::AabbObb) got = satAabbObb(p.a.toAabb(p.unit).cast<float>(), p.b.toObbFloat(p.unit)).overlap;
      else got = satObbObb(p.a.toObbFloat(p.unit), p.b.toObbFloat(p.unit)).overlap;
      if (flt.add(got, r.separated, e32, r, e32)) flt.note(what());
    }
  }
  census.print(title);
  eng.print();
  if (kind == Kind::ObbObb) sym.print();
  fcl.print();
  std::printf("  engine vs FCL: %ld disagreements, %ld explained by the two documented bands, %ld unexplained\n",
              engFclDiff, engFclDiffExplained, engFclDiff - engFclDiffExplained);
  flt.print();
  eng.expectClean();
  if (kind == Kind::ObbObb) sym.expectClean();
  fcl.expectClean();
  flt.expectClean();
  EXPECT_EQ(engFclDiff, engFclDiffExplained);
  EXPECT_EQ(eng.uncoveredRoundingMiss + sym.uncoveredRoundingMiss + flt.uncoveredRoundingMiss, 0);
  EXPECT_NEAR(double(census.exactOverlap) / census.pairs, 0.5, 0.12);
  EXPECT_GT(census.exactTouching, kPairs / 100);
  std::printf("  time %.2f s\n", seconds(t0));
}

TEST(SatCrossCheck, AabbObb) { runSatCheck(Kind::AabbObb, 2002, "satAabbObb"); }

TEST(SatCrossCheck, ObbObb) { runSatCheck(Kind::ObbObb, 3003, "satObbObb"); }

// testNested(fromObb(A), fromObb(B)) and testBoxPair(A, B): the verdict against the exact OBB pair,
// the stage and axis against the exact volumes of that stage.
void runNestedCheck(bool boxPair, std::uint64_t seed) {
  const auto t0 = std::chrono::steady_clock::now();
  Gen g(seed);
  Census census;
  Tally eng{boxPair ? "testBoxPair vs exact OBB pair" : "testNested vs exact OBB pair"};
  long stageCount[3] = {0, 0, 0}, stageSep[3] = {0, 0, 0};
  long diffFromLocalSat = 0;  // testBoxPair's verdict differs from satObbObb on the same local pair
  for (long it = 0; it < kPairs; ++it) {
    const Pair p = makePair(g, Kind::ObbObb);
    const SatRef r = exactSat(p.a, p.b);
    census.add(p, r);
    const ld w = windowOf(r, kU);
    const Obb<double> a = p.a.toObb(p.unit), b = p.b.toObb(p.unit);
    const NestedResult n = boxPair ? testBoxPair(a, b)
                                   : testNested(NestedVolume<double>::fromObb(a), NestedVolume<double>::fromObb(b));
    ++stageCount[int(n.stage)];
    if (!n.overlap) ++stageSep[int(n.stage)];
    if (boxPair) {
      Obb<double> la = a, lb = b;
      la.center.setZero();
      lb.center = b.center - a.center;
      if (satObbObb(la, lb).overlap != n.overlap) ++diffFromLocalSat;
    }
    auto what = [&] { return describe(p, r); };
    // The exact volumes of each stage and the documented model of each stage's test.
    //   stage 1: AABB-AABB of aabbOf (rounded outward by ~1e-15: inside the window), exact model;
    //   stage 2: satAabbObb(AABB of A, B), or (testBoxPair, only B aligned) satAabbObb(B, A) renamed;
    //            its slack includes 8 epsilon sum |min| + |max| of the AABB, in the frame it runs in
    //            (testNested: as given; testBoxPair: A's frame, A at the origin);
    //   stage 3: satObbObb with the engine's model.
    const bool aAligned = p.a.rot.isIdentity(), bAligned = p.b.rot.isIdentity();
    const ExactBox aBox = p.a.aabb(), bBox = p.b.aabb();
    const SatRef rAabb = exactSat(aBox, bBox, true);
    const ld wa = windowOf(rAabb, kU);
    const bool swapped = boxPair && bAligned && !aAligned;
    const SatRef r2 = swapped ? swapRoles(r) : (boxPair && aAligned) ? r : exactSat(aBox, p.b);
    ld mm;  // sum |min| + |max| of the stage-2 AABB in its frame
    if (!boxPair) {
      mm = minMaxSum(aBox);
    } else if (swapped) {
      mm = 0;
      for (int k = 0; k < 3; ++k) {
        const ld t = ld(p.b.c[k]) - ld(p.a.c[k]), h = ld(p.b.e[k]);  // den 1
        mm += std::fabs(t - h) + std::fabs(t + h);
      }
    } else {
      mm = 2 * (ld(aBox.e[0]) + ld(aBox.e[1]) + ld(aBox.e[2])) / aBox.den;
    }
    const SatModel m2 = engineAabbObb<double>(mm);
    // Verdict: "overlap" whenever the exact pair overlaps or touches (never a miss); "separated" where
    // the stage that has the last word surely separates (testBoxPair: stage 1 for two aligned boxes,
    // stage 2 for one, stage 3 otherwise; testNested: stage 3). In between, either.
    const Expect eExact = expectInflated(r, kExact, w, true);
    Expect eFinal;
    if (boxPair && aAligned && bAligned) eFinal = expectInflated(r, kExact, w, true);
    else if (boxPair && (aAligned || bAligned)) eFinal = expectInflated(r2, m2, windowOf(r2, kU), true);
    else eFinal = expectInflated(r, kEngine, w, true);
    const Expect e = eExact == Expect::Overlap ? Expect::Overlap : eFinal == Expect::Separated ? Expect::Separated : Expect::Either;
    if (eng.add(n.overlap, r.separated, e, r, e)) eng.note(what());
    // Stage and axis.
    if (boxPair && aAligned && bAligned) {
      EXPECT_EQ(n.stage, OverlapStage::AabbAabb) << what();
    }
    if (boxPair && (aAligned || bAligned)) {
      EXPECT_NE(n.stage, OverlapStage::ObbObb) << what();
    }
    if (n.stage == OverlapStage::AabbAabb) {
      if (!n.overlap) {
        ASSERT_GE(n.axis, 0);
        ASSERT_LT(n.axis, 3);
        axisCheck(eng, rAabb, n.axis, kExact, wa, true, "stage aabb-aabb", what);
      } else {
        // Stage 1 answered "overlap" and stopped: only when both are aligned (testBoxPair).
        EXPECT_TRUE(boxPair && aAligned && bAligned) << what();
      }
      continue;
    }
    // Beyond stage 1: stage 1 must not have been able to separate surely.
    EXPECT_NE(expectInflated(rAabb, kExact, wa, true, true), Expect::Separated) << "stage 1 should have separated: " << what();
    const ld w2 = windowOf(r2, kU);
    if (n.stage == OverlapStage::AabbObb) {
      if (!n.overlap) {
        axisCheck(eng, r2, swapped ? swapAxisRoles(n.axis) : n.axis, m2, w2, true, "stage aabb-obb", what);
      } else {
        EXPECT_TRUE(boxPair && (aAligned || bAligned)) << what();
      }
      continue;
    }
    // Stage 3: stage 2 must not have been able to separate surely.
    EXPECT_NE(expectInflated(r2, m2, w2, true), Expect::Separated) << "stage 2 should have separated: " << what();
    if (!n.overlap) axisCheck(eng, r, n.axis, kEngine, w, true, "stage obb-obb", what);
  }
  census.print(boxPair ? "testBoxPair" : "testNested");
  eng.print();
  std::printf("  stages: aabb-aabb %ld (separated %ld), aabb-obb %ld (separated %ld), obb-obb %ld (separated %ld)\n",
              stageCount[0], stageSep[0], stageCount[1], stageSep[1], stageCount[2], stageSep[2]);
  if (boxPair)
    std::printf("  verdict differs from satObbObb on the same local pair: %ld (each side checked against the exact "
                "answer above)\n", diffFromLocalSat);
  eng.expectClean();
  EXPECT_NEAR(double(census.exactOverlap) / census.pairs, 0.5, 0.12);
  std::printf("  time %.2f s\n", seconds(t0));
}

TEST(SatCrossCheck, NestedThreeStage) { runNestedCheck(false, 4004); }

TEST(SatCrossCheck, TestBoxPair) { runNestedCheck(true, 5005); }

// ------------------------------------------------------------------------------------------------
// General random double boxes (Eigen rotations from random quaternions, not rational), judged by the
// long double reference (no exact rationals exist here). Half the pairs are moved along their
// decisive axis to a chosen margin of +-1e-15 .. 1e-3 m, and a third of the B boxes are A's
// orientation times a rotation of 1e-10 .. 1e-2 rad (near-parallel edges, often with permuted axes),
// to populate the bands. Same models and windows as above; the engine must never separate a pair
// that the reference finds touching or overlapping.
TEST(SatCrossCheck, RandomDoubleBoxesVsLongDouble) {
  const auto t0 = std::chrono::steady_clock::now();
  std::mt19937_64 rng(6006);
  std::normal_distribution<double> nd(0, 1);
  std::uniform_real_distribution<double> ud(0, 1);
  auto rotation = [&] {
    Eigen::Quaterniond q(nd(rng), nd(rng), nd(rng), nd(rng));
    q.normalize();
    return Mat3<double>(q.toRotationMatrix());
  };
  auto half = [&] { return ud(rng) < 0.1 ? 0.0 : std::pow(10.0, -3 + 4 * ud(rng)); };
  Tally eng{"satObbObb<double> vs long double"}, sym{"satObbObb(B, A) vs long double"},
      pair{"testBoxPair vs long double"}, nest{"testNested vs long double"}, fcl{"fcl::OBB::overlap vs long double"},
      flt{"satObbObb<float> vs long double"};
  long moved = 0, nearParallel = 0, consistentFails = 0;
  const long n = std::max(1L, kPairs / 4);
  for (long it = 0; it < n; ++it) {
    Obb<double> a, b;
    a.center = Vec3<double>(nd(rng), nd(rng), nd(rng)) * 10;
    a.axes = rotation();
    a.halfExtents = Vec3<double>(half(), half(), half());
    if (ud(rng) < 0.33) {
      ++nearParallel;
      const Vec3<double> w(nd(rng), nd(rng), nd(rng));
      Mat3<double> small = Eigen::AngleAxisd(std::pow(10.0, -10 + 8 * ud(rng)), w.normalized()).toRotationMatrix();
      b.axes = a.axes * small;
      if (ud(rng) < 0.5) {  // permute the columns (keeping a rotation): other edge pairs near-parallel
        Mat3<double> p;
        p << 0, 0, 1, 1, 0, 0, 0, 1, 0;
        b.axes = b.axes * p;
      }
    } else {
      b.axes = rotation();
    }
    b.halfExtents = Vec3<double>(half(), half(), half());
    const double reach = (a.halfExtents.sum() + b.halfExtents.sum()) * 0.8 + 1e-3;
    b.center = a.center + Vec3<double>(nd(rng), nd(rng), nd(rng)).normalized() * reach * ud(rng) * 1.5;
    SatRef r = ldSat(a, b);
    if (ud(rng) < 0.5 && r.marginAxis >= 0) {
      // Move B along the unit decisive axis so that the margin becomes the target.
      ++moved;
      const double target = (ud(rng) < 0.5 ? -1 : 1) * std::pow(10.0, -15 + 12 * ud(rng));
      const int k = r.marginAxis;
      Vec3<ld> L = k < 3 ? a.axes.col(k).cast<ld>() : k < 6 ? b.axes.col(k - 3).cast<ld>()
                                                            : a.axes.col((k - 6) / 3).cast<ld>().cross(b.axes.col((k - 6) % 3).cast<ld>());
      L.normalize();
      const ld side = (b.center - a.center).cast<ld>().dot(L) >= 0 ? 1 : -1;
      b.center = (b.center.cast<ld>() + side * (ld(target) - r.margin) * L).cast<double>();
      r = ldSat(a, b);
    }
    bool consistent = true;
    ldSatBothWays(a, b, consistent);
    if (!consistent) ++consistentFails;
    const ld w = windowOf(r, kU);
    // The engine never misses a contact of the boxes as given (strict); the long double reference is
    // exact to ~1e-19 of the sizes here.
    const Expect e = expectInflated(r, kEngine, w, true);
    auto what = [&] {
      char buf[600];
      std::snprintf(buf, sizeof buf, "margin %.3Le axis %s | A c=(%.17g %.17g %.17g) h=(%.17g %.17g %.17g) | B c=(%.17g %.17g %.17g) h=(%.17g %.17g %.17g)",
                    r.margin, axisName(r.marginAxis).c_str(), a.center.x(), a.center.y(), a.center.z(), a.halfExtents.x(),
                    a.halfExtents.y(), a.halfExtents.z(), b.center.x(), b.center.y(), b.center.z(), b.halfExtents.x(),
                    b.halfExtents.y(), b.halfExtents.z());
      return std::string(buf);
    };
    const SatResult s = satObbObb(a, b);
    if (eng.add(s.overlap, r.separated, e, r)) eng.note(what());
    if (!s.overlap) axisCheck(eng, r, s.axis, kEngine, w, true, "satObbObb", what);
    const SatRef rb = swapRoles(r);
    if (sym.add(satObbObb(b, a).overlap, rb.separated, expectInflated(rb, kEngine, w, true), rb)) sym.note(what());
    // Cascades: overlap required only for overlapping pairs, separation only where stage 3 surely separates.
    const Expect eExact = expectInflated(r, kExact, w, true);
    const Expect eCascade = e == Expect::Separated ? Expect::Separated : eExact == Expect::Overlap ? Expect::Overlap : Expect::Either;
    if (pair.add(testBoxPair(a, b).overlap, r.separated, eCascade, r)) pair.note(what());
    if (nest.add(testNested(NestedVolume<double>::fromObb(a), NestedVolume<double>::fromObb(b)).overlap, r.separated, eCascade, r))
      nest.note(what());
    if (fcl.add(toFcl(a).overlap(toFcl(b)), r.separated, expectInflated(r, kFcl, w, false), r)) fcl.note(what());
    // Float: its inputs are the doubles rounded to float, so its contacts are judged within the float
    // window (not strict).
    const Expect ef = expectInflated(r, kEngineF, windowOf(r, kUf), false);
    if (flt.add(satObbObb(a.cast<float>(), b.cast<float>()).overlap, r.separated, ef, r)) flt.note(what());
  }
  std::printf("random double boxes: %ld pairs, %ld moved to a margin of +-1e-15..1e-3 m, %ld near-parallel, "
              "%ld both-ways inconsistencies of the reference\n", n, moved, nearParallel, consistentFails);
  for (const Tally* t : {&eng, &sym, &pair, &nest, &fcl, &flt}) {
    t->print();
    t->expectClean();
  }
  EXPECT_EQ(consistentFails, 0);
  std::printf("  time %.2f s\n", seconds(t0));
}

// ------------------------------------------------------------------------------------------------
// Exactly touching, exactly representable pairs must never be separated. Each family below is a
// contact between closed boxes whose doubles are exactly the rational boxes (checked with the exact
// reference: not separated, and some axis with gap exactly 0). These are the failure modes of the
// engine revision without kRoundingSlack / outward-rounded aabbOf, where rounding that the
// |R| + eps inflation did not cover (it scales with half extents, and is zero for a point) separated
// 17% to 50% of these contacts:
//   pointOnRotatedFrame: a point (any rotation) on the surface of an aligned / signed-permutation box;
//                        satObbObb(point, box) works in the point's rotated frame;
//   aabbObbFine:         satAabbObb(AABB [min, max], point on its face) with coordinates using all 53 bits:
//                        centre (min + max) / 2 and half extents (max - min) / 2 are rounded;
//   nestedFine:          the same through testNested (stage aabb-obb);
//   boxPairBigAligned:   testBoxPair(small box with 90-degree axes, big aligned box touching it):
//                        B's AABB fl(c -+ e), then its centre and half extents rounded again;
//   boxPairShift:        testBoxPair(aligned, aligned) touching, centres of different magnitude:
//                        the local shift fl(cB - cA) is not exact.
// FCL's OBB::overlap (no slack) is run on family 0 for comparison and still misses those contacts.
TEST(SatCrossCheck, ExactContactsAreNeverMissed) {
  Gen g(9009);
  const long n = std::max(1L, kPairs / 10);
  long miss[5] = {0, 0, 0, 0, 0}, total[5] = {0, 0, 0, 0, 0}, fclMiss = 0;
  auto checkTouching = [](const ExactBox& a, const ExactBox& b) {
    const SatRef r = exactSat(a, b);
    bool zero = false;
    for (int k = 0; k < kAxes; ++k) zero |= r.len[k] > 0 && r.sign[k] == 0;
    return !r.separated && zero;
  };
  const double fine = std::ldexp(1.0, -40);
  for (long it = 0; it < n; ++it) {
    {  // 0: point with a rotated frame on a representable box's surface (coarse units)
      ExactBox b;
      b.rot = g.chance(0.5) ? IntRotation::identity() : IntRotation::fromQuaternion(1, 0, 0, 1);
      for (int k = 0; k < 3; ++k) {
        b.e[k] = g.uni(1, 256);
        b.c[k] = g.uni(-4096, 4096);
      }
      ExactBox p;
      p.rot = g.rotation(Cls::Coarse, true);
      if (p.rot.isDyadic()) p.rot = IntRotation::fromQuaternion(1, 2, 3, 4);
      const int k = int(g.uni(0, 2));
      for (int q = 0; q < 3; ++q) p.c[q] = b.c[q] + g.uni(-worldExtent(b, q), worldExtent(b, q));
      p.c[k] = b.c[k] + (g.chance(0.5) ? 1 : -1) * worldExtent(b, k);
      if (!checkTouching(p, b)) ADD_FAILURE() << "construction 0";
      const Obb<double> pd = p.toObb(1.0 / 64), bd = b.toObb(1.0 / 64);
      ++total[0];
      if (!satObbObb(pd, bd).overlap) ++miss[0];
      if (!toFcl(pd).overlap(toFcl(bd))) ++fclMiss;
    }
    {  // 1, 2: AABB with 52-bit coordinates, a point on one of its faces
      std::array<i64, 3> mn, mx;
      for (int q = 0; q < 3; ++q) {
        // min + max above 2^53: the centre needs one more bit than the double has
        mn[q] = (i64(1) << 52) + g.uni(0, i64(1) << 50);
        mx[q] = mn[q] + g.uni(1, i64(1) << 51);
      }
      const ExactBox a = ExactBox::fromMinMax(mn, mx);
      ExactBox p;
      p.rot = g.rotation(Cls::Coarse, true);
      const int k = int(g.uni(0, 2));
      for (int q = 0; q < 3; ++q) p.c[q] = g.uni(mn[q], mx[q]);
      p.c[k] = g.chance(0.5) ? mx[k] : mn[k];
      if (!checkTouching(a, p)) ADD_FAILURE() << "construction 1";
      const Aabb<double> ad = a.toAabb(fine);
      const Obb<double> pd = p.toObb(fine);
      ++total[1];
      if (!satAabbObb(ad, pd).overlap) ++miss[1];
      ++total[2];
      if (!testNested(NestedVolume<double>{ad, Obb<double>::fromAabb(ad)}, NestedVolume<double>::fromObb(pd)).overlap)
        ++miss[2];
    }
    {  // 3: testBoxPair, small box with 90-degree axes at the origin vs a big aligned box
      ExactBox a;
      a.rot = IntRotation::fromQuaternion(1, 0, 0, 1);
      for (int q = 0; q < 3; ++q) a.e[q] = g.uni(1, i64(1) << 30);  // up to 1 mm in units of 2^-40 m
      ExactBox b;
      const int k = int(g.uni(0, 2));
      for (int q = 0; q < 3; ++q) {  // c + e above 2^53 along k: B's AABB max is rounded
        b.e[q] = q == k ? g.uni(i64(1) << 52, (i64(1) << 53) - (i64(1) << 32)) : (i64(1) << 45);
        b.c[q] = q == k ? 0 : g.uni(-(i64(1) << 40), i64(1) << 40);
      }
      b.c[k] = worldExtent(a, k) + b.e[k];
      if (!checkTouching(a, b)) ADD_FAILURE() << "construction 3";
      ++total[3];
      if (!testBoxPair(a.toObb(fine), b.toObb(fine)).overlap) ++miss[3];
    }
    {  // 4: testBoxPair, two aligned boxes touching in x, centres of different magnitude: A's centre
       // odd and small, B's centre even and above 2^53, so cB - cA needs 54 bits
      ExactBox a, b;
      for (int q = 0; q < 3; ++q) {
        a.e[q] = g.uni(1, i64(1) << 40);
        b.e[q] = g.uni(i64(1) << 45, i64(1) << 50);
        a.c[q] = g.uni(-(i64(1) << 38), i64(1) << 38);
        b.c[q] = a.c[q];
      }
      a.c[0] |= 1;
      if ((a.c[0] + a.e[0]) % 2 != 0) ++a.e[0];  // A's max even
      b.e[0] = 2 * g.uni(i64(1) << 52, (i64(1) << 53) - (i64(1) << 40));
      b.c[0] = a.c[0] + a.e[0] + b.e[0];  // even, below 2^54: exact in double
      if (!checkTouching(a, b)) ADD_FAILURE() << "construction 4";
      ++total[4];
      if (!testBoxPair(a.toObb(fine), b.toObb(fine)).overlap) ++miss[4];
    }
  }
  const char* names[5] = {"satObbObb(point in a rotated frame, box)", "satAabbObb(53-bit-coordinate AABB, point on face)",
                          "testNested(53-bit-coordinate viewer AABB, point)", "testBoxPair(small 90-degree box, big aligned box)",
                          "testBoxPair(aligned, aligned), centres of different magnitude"};
  for (int i = 0; i < 5; ++i) {
    std::printf("  exact contacts missed by %-62s %6ld of %ld\n", names[i], miss[i], total[i]);
    EXPECT_EQ(miss[i], 0) << names[i] << " misses exact contacts";
  }
  std::printf("  (FCL's OBB::overlap on family 0, for comparison: %ld of %ld missed: rounding without slack)\n",
              fclMiss, total[0]);
}

}  // namespace
}  // namespace nestwalk
