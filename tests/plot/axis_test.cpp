// The axis and tick rule (engine/plot/axis.h): ticks of the 1-2-5 sequence that cover the data,
// the fewest-ticks step under the limit, log axes across many decades, within a decade and within
// one 1-2-5 gap, NaN / zero / negative values, single values and empty data, values that lie
// exactly on ticks, UTM magnitudes, and the labels as text. Expected values are worked out by hand
// or checked against properties computed here (a 1-2-5 mantissa is recognised from the value's own
// digits, not through the library).
#include "nestwalk/plot/axis.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace nestwalk {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
// Relative slack when comparing tick values computed two ways (a few units in the last place).
constexpr double kRelative = 1e-12;

std::vector<double> values(const Axis& a) {
  std::vector<double> v;
  for (const AxisTick& t : a.ticks()) v.push_back(t.value);
  return v;
}
std::vector<std::string> labels(const Axis& a) {
  std::vector<std::string> v;
  for (const AxisTick& t : a.ticks()) v.push_back(t.label);
  return v;
}

/// True when x = m · 10^k with m in {1, 2, 5}, to a relative 1e-9.
bool isOneTwoFive(double x) {
  if (!(x > 0)) return false;
  const double m = x / std::pow(10.0, std::floor(std::log10(x)));
  for (double nice : {1.0, 2.0, 5.0, 10.0})
    if (std::abs(m - nice) < 1e-9 * nice) return true;
  return false;
}

/// The 1-2-5 value nearest to x > 0.
double nearestOneTwoFive(double x) {
  const double decade = std::pow(10.0, std::floor(std::log10(x)));
  double best = decade;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (std::abs(m * decade - x) < std::abs(best - x)) best = m * decade;
  return best;
}

/// Checks what every linear axis promises over data [mn, mx]: evenly spaced ticks n · step with a
/// 1-2-5 step, at most maxTicks, the ends on the first and last tick and covering the data, and no
/// smaller 1-2-5 step that would stay within maxTicks.
void expectLinearRule(const Axis& a, double mn, double mx, int maxTicks) {
  const std::vector<double> t = values(a);
  ASSERT_GE(t.size(), 2u);
  ASSERT_LE(int(t.size()), maxTicks);
  // Ticks at UTM magnitudes carry the rounding of numbers near 1e6 (a few ulps of 4.6e6 are
  // ~1e-9): differences of ticks are compared with that slack.
  const double slack = 8 * std::numeric_limits<double>::epsilon() * std::max(std::abs(t.front()), std::abs(t.back()));
  const double step = nearestOneTwoFive(t[1] - t[0]);
  EXPECT_NEAR(t[1] - t[0], step, 1e-9 * step + slack) << "the step is not of the 1-2-5 sequence";
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double n = std::round(t[i] / step);
    EXPECT_NEAR(t[i], n * step, kRelative * std::max(1.0, std::abs(t[i]))) << "tick " << i;
    if (i > 0) {
      EXPECT_NEAR(t[i] - t[i - 1], step, 1e-9 * step + slack) << "tick " << i;
    }
  }
  EXPECT_EQ(a.lo(), t.front());
  EXPECT_EQ(a.hi(), t.back());
  EXPECT_LE(a.lo(), mn);
  EXPECT_GE(a.hi(), mx);
  // The next smaller 1-2-5 step (step / 2 after a 1, / 2.5 after a 5, / 2 after a 2) needs more
  // ticks than allowed.
  const double mantissa = step / std::pow(10.0, std::floor(std::log10(step) + 1e-12));
  const double smaller = std::abs(mantissa - 5) < 1e-9 ? step / 2.5 : step / 2;
  const double count = std::ceil(mx / smaller - 1e-9) - std::floor(mn / smaller + 1e-9) + 1;
  EXPECT_GT(count, maxTicks) << "a step of " << smaller << " would have done";
}

TEST(Axis, NiceValuesAreTheOneTwoFiveSequence) {
  EXPECT_EQ(niceCeil(1), 1);
  EXPECT_EQ(niceCeil(1.01), 2);
  EXPECT_EQ(niceCeil(0.3), 0.5);
  EXPECT_EQ(niceCeil(7), 10);
  EXPECT_EQ(niceCeil(3e-7), 5e-7);
  EXPECT_EQ(niceCeil(0.1 + 0.2), 0.5);
  EXPECT_EQ(niceCeil(2e5), 2e5);
  EXPECT_EQ(niceFloor(7), 5);
  EXPECT_EQ(niceFloor(1000), 1000);
  EXPECT_EQ(niceFloor(999.9), 500);
  EXPECT_EQ(niceFloor(0.0999), 0.05);
  EXPECT_EQ(niceFloor(0.1 * 3), 0.2);
  EXPECT_EQ(niceFloor(12.5), 10);
}

TEST(Axis, LinearTicksCoverTheDataWithTheFewestOneTwoFiveSteps) {
  struct Case {
    double mn, mx;
    int maxTicks;
  };
  for (const Case& c : {Case{0, 1, 6}, Case{0, 600, 8}, Case{-3.7, 12.2, 8}, Case{0.001, 0.0173, 5},
                        Case{1, 2902, 10}, Case{-250, -20, 4}, Case{4649990.0, 4650010.0, 6},
                        Case{4650000.0001, 4650000.0009, 8}, Case{1e-9, 7e-9, 8}, Case{2e8, 9.5e8, 3}}) {
    SCOPED_TRACE(testing::Message() << c.mn << " .. " << c.mx << ", " << c.maxTicks << " ticks");
    const double data[] = {c.mx, (c.mn + c.mx) / 2, c.mn};
    const Axis a = Axis::fit(data, {.maxTicks = c.maxTicks});
    expectLinearRule(a, c.mn, c.mx, c.maxTicks);
  }
  // Worked by hand: 0 .. 600 in at most 8 ticks: a step of 50 needs 13, 100 needs 7.
  const double frames[] = {0, 600};
  EXPECT_EQ(values(Axis::fit(frames, {.maxTicks = 8})), (std::vector<double>{0, 100, 200, 300, 400, 500, 600}));
}

TEST(Axis, ValuesOnTicksAreOnThem) {
  // 0.3 / 0.1 is 2.9999999999999996 in double; the axis must still end at 0.3, not 0.4.
  const double a[] = {0.1, 0.3};
  const Axis axis = Axis::fit(a, {.maxTicks = 3});
  EXPECT_EQ(labels(axis), (std::vector<std::string>{"0.1", "0.2", "0.3"}));
  EXPECT_NEAR(axis.hi(), 0.3, 1e-15);
  const double b[] = {0, 1};
  EXPECT_EQ(labels(Axis::fit(b, {.maxTicks = 6})), (std::vector<std::string>{"0.0", "0.2", "0.4", "0.6", "0.8", "1.0"}));
  const double c[] = {10, 1000};  // exact decades: the ends are the data
  const Axis log = Axis::fit(c, {.scale = AxisScale::Log10});
  EXPECT_EQ(log.lo(), 10);
  EXPECT_EQ(log.hi(), 1000);
}

TEST(Axis, TightLinearAxisEndsAtTheData) {
  const double frames[] = {1, 2902};
  const Axis a = Axis::fit(frames, {.tight = true, .maxTicks = 10, .minStep = 1});
  EXPECT_EQ(a.lo(), 1);
  EXPECT_EQ(a.hi(), 2902);
  EXPECT_EQ(values(a), (std::vector<double>{500, 1000, 1500, 2000, 2500}));
  EXPECT_EQ(a.position(1, 100, 200), 100);
  EXPECT_EQ(a.position(2902, 100, 200), 200);
  // A minimum step keeps frame numbers whole.
  const double few[] = {3, 5};
  EXPECT_EQ(values(Axis::fit(few, {.tight = true, .maxTicks = 8, .minStep = 1})), (std::vector<double>{3, 4, 5}));
}

TEST(Axis, LinearAxisReachesZeroWhenAsked) {
  const double v[] = {3.2, 7.9};
  const Axis a = Axis::fit(v, {.includeZero = true, .maxTicks = 6});
  EXPECT_EQ(a.lo(), 0);
  EXPECT_EQ(a.hi(), 8);
  EXPECT_EQ(values(a), (std::vector<double>{0, 2, 4, 6, 8}));
}

TEST(Axis, LogAxisOverThreeDecadesOrMoreTicksWholeDecades) {
  // The frame-time plot's data: 0.1 µs (ground) to 55 µs (a spiky total): decades -1 .. 2.
  const double us[] = {0.1, 0.11, 5.2, 55};
  const Axis a = Axis::fit(us, {.scale = AxisScale::Log10, .unit = "µs"});
  EXPECT_EQ(values(a), (std::vector<double>{0.1, 1, 10, 100}));
  EXPECT_EQ(labels(a), (std::vector<std::string>{"0.1 µs", "1 µs", "10 µs", "100 µs"}));
  EXPECT_NEAR(a.fraction(1), 1.0 / 3, 1e-12);
  EXPECT_NEAR(a.fraction(std::sqrt(10.0)), 0.5, 1e-12);
  EXPECT_NEAR(a.position(10, 0, 300), 200, 1e-9);
  // Small values in scientific notation.
  const double tiny[] = {3e-7, 2e-3};
  EXPECT_EQ(labels(Axis::fit(tiny, {.scale = AxisScale::Log10})),
            (std::vector<std::string>{"1e-7", "1e-6", "1e-5", "0.0001", "0.001", "0.01"}));
  // 18 decades in at most 8 ticks: every 5th decade (every 2nd would need 10).
  const double wide[] = {1e-9, 1e9};
  const Axis w = Axis::fit(wide, {.scale = AxisScale::Log10, .maxTicks = 8});
  EXPECT_EQ(values(w), (std::vector<double>{1e-10, 1e-5, 1, 1e5, 1e10}));
  EXPECT_EQ(labels(w), (std::vector<std::string>{"1e-10", "1e-5", "1", "100000", "1e10"}));
}

TEST(Axis, LogAxisBelowThreeDecadesTicksOneTwoFive) {
  const double v[] = {3, 40};
  const Axis a = Axis::fit(v, {.scale = AxisScale::Log10});
  EXPECT_EQ(values(a), (std::vector<double>{2, 5, 10, 20, 50}));
  for (double t : values(a)) EXPECT_TRUE(isOneTwoFive(t)) << t;
  // More 1-2-5 values than allowed: whole decades.
  EXPECT_EQ(values(Axis::fit(v, {.scale = AxisScale::Log10, .maxTicks = 3})), (std::vector<double>{1, 10, 100}));
  const double w[] = {0.31, 0.7};
  EXPECT_EQ(labels(Axis::fit(w, {.scale = AxisScale::Log10})), (std::vector<std::string>{"0.2", "0.5", "1"}));
}

TEST(Axis, LogAxisWithinOneGapTicksLinearSteps) {
  // 3 .. 4 lies between the 1-2-5 values 2 and 5: steps of 0.2 over the data instead.
  const double v[] = {3, 4};
  const Axis a = Axis::fit(v, {.scale = AxisScale::Log10, .maxTicks = 8});
  EXPECT_EQ(labels(a), (std::vector<std::string>{"3.0", "3.2", "3.4", "3.6", "3.8", "4.0"}));
  EXPECT_NEAR(a.lo(), 3, 1e-12);
  EXPECT_NEAR(a.hi(), 4, 1e-12);
  EXPECT_NEAR(a.fraction(std::sqrt(12.0)), 0.5, 1e-12);  // log scale: the geometric mean halfway
  // 12 .. 21 ns would fill 35 % of 10 .. 50: steps of 2 over the data.
  const double ns[] = {12.5, 21};
  EXPECT_EQ(values(Axis::fit(ns, {.scale = AxisScale::Log10, .maxTicks = 8})),
            (std::vector<double>{12, 14, 16, 18, 20, 22}));
}

TEST(Axis, NanZeroAndNegativeValues) {
  const double clean[] = {5, 50};
  const double dirty[] = {-1, 0, kNaN, 5, kInf, 50, -kInf};
  const Axis a = Axis::fit(clean, {.scale = AxisScale::Log10}), b = Axis::fit(dirty, {.scale = AxisScale::Log10});
  EXPECT_EQ(values(a), values(b));
  EXPECT_EQ(b.fraction(-1), 0);
  EXPECT_EQ(b.fraction(0), 0);
  EXPECT_EQ(b.fraction(kNaN), 0);
  EXPECT_EQ(b.fraction(1e9), 1);
  // Linear: NaN and infinities are left out of the fit, NaN sits at the lower end.
  const double lin[] = {kNaN, -2, kInf, 3};
  const Axis l = Axis::fit(lin, {.maxTicks = 6});
  EXPECT_EQ(values(l), (std::vector<double>{-2, -1, 0, 1, 2, 3}));
  EXPECT_EQ(l.fraction(kNaN), 0);
  EXPECT_EQ(l.fraction(-100), 0);
  EXPECT_EQ(l.fraction(100), 1);
  EXPECT_EQ(labels(l)[2], "0");  // never "-0"
}

TEST(Axis, LogFloorLiftsSmallValues) {
  // The terrain plot: errors below 0.1 mm (and exact zeros) are shown on the floor.
  const double errors[] = {0, 1e-7, 3e-3, 2e-2};
  const Axis a = Axis::fit(errors, {.scale = AxisScale::Log10, .logFloor = 1e-4});
  EXPECT_EQ(a.lo(), 1e-4);
  EXPECT_EQ(a.fraction(1e-7), 0);
  EXPECT_EQ(a.fraction(0), 0);
  EXPECT_EQ(a.fraction(1e-4), 0);
  EXPECT_GT(a.fraction(2e-4), 0);
}

TEST(Axis, SingleValuesAndNoData) {
  const double none[] = {kNaN};
  const Axis emptyLinear = Axis::fit({}, {}), emptyLog = Axis::fit(none, {.scale = AxisScale::Log10});
  EXPECT_EQ(emptyLinear.lo(), 0);
  EXPECT_EQ(emptyLinear.hi(), 1);
  EXPECT_EQ(emptyLog.lo(), 1);
  EXPECT_EQ(emptyLog.hi(), 10);
  const double zero[] = {0};
  const Axis z = Axis::fit(zero, {});
  EXPECT_EQ(z.lo(), 0);
  EXPECT_EQ(z.hi(), 1);
  // One value v: widened to [v / 2, 2 v] on a log axis (2 .. 20 around 7), by half of it on a
  // linear one (3.5 .. 10.5 around 7).
  const double seven[] = {7};
  EXPECT_EQ(values(Axis::fit(seven, {.scale = AxisScale::Log10})), (std::vector<double>{2, 5, 10, 20}));
  const Axis lin = Axis::fit(seven, {.maxTicks = 8});
  expectLinearRule(lin, 3.5, 10.5, 8);
  EXPECT_EQ(lin.fraction(7), (7 - lin.lo()) / (lin.hi() - lin.lo()));
}

TEST(Axis, TickLabels) {
  EXPECT_EQ(tickLabel(0, 0.1), "0.0");
  EXPECT_EQ(tickLabel(-0.0, 1), "0");
  EXPECT_EQ(tickLabel(-1e-17, 0.1), "0.0");  // rounding noise around zero
  EXPECT_EQ(tickLabel(0, 1e-6), "0");
  EXPECT_EQ(tickLabel(0.05, 0.01), "0.05");
  EXPECT_EQ(tickLabel(-0.2, 0.1), "-0.2");
  EXPECT_EQ(tickLabel(250, 50), "250");
  EXPECT_EQ(tickLabel(0.0001, 0.0001), "0.0001");
  EXPECT_EQ(tickLabel(1e-6, 1e-6), "1e-6");
  EXPECT_EQ(tickLabel(2.5e-7, 1e-8), "2.5e-7");
  EXPECT_EQ(tickLabel(2e7, 1e7), "2e7");
  EXPECT_EQ(tickLabel(4650000, 1000), "4.65e6");
  EXPECT_EQ(tickLabel(10, 10, "µs"), "10 µs");
  EXPECT_EQ(tickLabel(50, 10, "m"), "50 m");
}

}  // namespace
}  // namespace nestwalk
