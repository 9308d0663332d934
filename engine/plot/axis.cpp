// The axis and tick rule (axis.h). Tick values are computed as whole multiples of a step (n · step)
// or as m · 10^k with 10^k exact (k >= 0) or divided by an exact 10^-k (k < 0), never accumulated,
// so that 0.1 + 0.2 never becomes a tick.
#include "nestwalk/plot/axis.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>

namespace nestwalk {
namespace {

// A value within this fraction of a step (or of a decade, on log axes) from a tick counts as on it:
// it absorbs the rounding of a division such as 0.3 / 0.1 = 2.9999999999999996.
constexpr double kOnTick = 1e-9;
// Tick labels use decimals from 1e-4 up to (not including) 1e6, scientific notation beyond.
constexpr double kPlainFrom = 1e-4, kPlainBelow = 1e6;
// Decades of data from which a log axis ticks whole decades only.
constexpr int kDecadeTicksFrom = 3;
// A log axis keeps the 1-2-5 values as ticks when they give at least this many ticks and the data
// fills at least this share of the axis (in log10); otherwise it ticks linear steps over the data.
constexpr std::size_t kFewestLogTicks = 3;
constexpr double kLeastLogFill = 0.5;

constexpr double kMantissas[] = {1, 2, 5};

/// 10^k, exact for the k that matter (|k| <= 22).
double pow10(int k) { return k >= 0 ? std::pow(10.0, k) : 1.0 / std::pow(10.0, -k); }
/// m · 10^k with one rounding.
double scaled(double m, int k) { return k >= 0 ? m * std::pow(10.0, k) : m / std::pow(10.0, -k); }

/// The k with 10^k <= x < 10^(k + 1), for x > 0.
int decadeOf(double x) {
  int k = int(std::floor(std::log10(x)));
  while (k > -400 && pow10(k) > x) --k;
  while (k < 400 && pow10(k + 1) <= x) ++k;
  return k;
}

/// The next value of the 1-2-5 sequence above the 1-2-5 value `step`.
double nextNice(double step) {
  const int k = decadeOf(step);
  const double m = std::round(step / pow10(k));
  return m < 1.5 ? scaled(2, k) : m < 3.5 ? scaled(5, k) : scaled(1, k + 1);
}

/// Floor and ceiling of a value in steps (value / step), counting one within kOnTick of a step, or
/// within the division's own rounding (a few ulps of x, which matter at UTM magnitudes), as on it.
double onTickSlack(double x) { return kOnTick + 4 * std::numeric_limits<double>::epsilon() * std::abs(x); }
double snapFloor(double x) { return std::floor(x + onTickSlack(x)); }
double snapCeil(double x) { return std::ceil(x - onTickSlack(x)); }

/// Multiples of the smallest 1-2-5 step giving at most maxTicks ticks over [lo, hi] (lo < hi):
/// from the one at or below lo to the one at or above hi, or (tight) those within.
struct StepTicks {
  double step = 1, first = 0, last = 1;  // ticks first · step .. last · step
};
StepTicks stepTicks(double lo, double hi, int maxTicks, bool tight, double minStep = 0) {
  StepTicks t;
  t.step = std::max(niceCeil((hi - lo) / double(maxTicks - 1)), minStep > 0 ? niceCeil(minStep) : 0.0);
  for (;;) {
    t.first = tight ? snapCeil(lo / t.step) : snapFloor(lo / t.step);
    t.last = tight ? snapFloor(hi / t.step) : snapCeil(hi / t.step);
    if (t.last - t.first + 1 <= maxTicks) return t;
    t.step = nextNice(t.step);
  }
}

}  // namespace

double niceCeil(double x) {
  const int k = decadeOf(x);
  for (double m : kMantissas)
    if (scaled(m, k) >= x * (1 - kOnTick)) return scaled(m, k);
  return scaled(1, k + 1);
}

double niceFloor(double x) {
  const int k = decadeOf(x);
  if (scaled(1, k + 1) <= x * (1 + kOnTick)) return scaled(1, k + 1);
  for (int i = 2; i >= 0; --i)
    if (scaled(kMantissas[i], k) <= x * (1 + kOnTick)) return scaled(kMantissas[i], k);
  return scaled(1, k);
}

std::string tickLabel(double value, double resolution, const std::string& unit) {
  const std::string suffix = unit.empty() ? "" : " " + unit;
  resolution = std::abs(resolution);
  if (!std::isfinite(value)) return "-" + suffix;
  if (!(resolution > 0) || !std::isfinite(resolution)) resolution = value != 0 ? std::abs(value) : 1;
  const int kRes = decadeOf(resolution);
  const int decimals = std::max(0, -kRes);
  const double a = std::abs(value);
  // std::to_chars: a point as the decimal separator whatever locale the program set.
  auto format = [](double v, std::chars_format f, int precision) {
    char buffer[400];  // %f of the largest double is 309 digits
    const auto r = std::to_chars(buffer, buffer + sizeof buffer, v, f, precision);
    return std::string(buffer, r.ptr);
  };
  if (a < resolution * kOnTick * 1e3) {  // zero, or rounding noise around it; never "-0"
    if (resolution < kPlainFrom) return "0" + suffix;
    return format(0.0, std::chars_format::fixed, decimals) + suffix;
  }
  if (a >= kPlainFrom && a < kPlainBelow && resolution >= kPlainFrom)
    return format(value, std::chars_format::fixed, decimals) + suffix;
  // Scientific: as many significant digits as the resolution needs, trailing zeros dropped.
  const int kValue = decadeOf(a);
  const int digits = std::clamp(kValue - kRes + 1, 1, 15);
  std::string s = format(value, std::chars_format::scientific, digits - 1);
  const std::size_t e = s.find('e');
  std::string mantissa = s.substr(0, e);
  if (mantissa.find('.') != std::string::npos) {
    while (mantissa.back() == '0') mantissa.pop_back();
    if (mantissa.back() == '.') mantissa.pop_back();
  }
  return mantissa + "e" + std::to_string(std::stoi(s.substr(e + 1))) + suffix;
}

Axis Axis::fit(std::span<const double> values, const AxisOptions& options) {
  Axis a;
  a.scale_ = options.scale;
  const int maxTicks = std::max(options.maxTicks, 3);
  double mn = HUGE_VAL, mx = -HUGE_VAL;

  if (options.scale == AxisScale::Linear) {
    for (double v : values)
      if (std::isfinite(v)) {
        mn = std::min(mn, v);
        mx = std::max(mx, v);
      }
    if (options.includeZero) {
      mn = std::min(mn, 0.0);
      mx = std::max(mx, 0.0);
    }
    if (mn > mx) mn = 0, mx = 1;
    if (mn == mx && mn == 0) {
      mx = 1;
    } else if (mn == mx) {
      const double d = 0.5 * std::abs(mn);
      mn -= d, mx += d;
    }
    const StepTicks t = stepTicks(mn, mx, maxTicks, options.tight, options.minStep);
    a.lo_ = options.tight ? mn : t.first * t.step;
    a.hi_ = options.tight ? mx : t.last * t.step;
    for (double n = t.first; n <= t.last; ++n) a.ticks_.push_back({n * t.step, tickLabel(n * t.step, t.step, options.unit)});
    return a;
  }

  a.floor_ = options.logFloor > 0 && std::isfinite(options.logFloor) ? options.logFloor : 0;
  for (double v : values)
    if (std::isfinite(v) && v > 0) {
      mn = std::min(mn, std::max(v, a.floor_));
      mx = std::max(mx, std::max(v, a.floor_));
    }
  if (mn > mx) {
    a.lo_ = a.floor_ > 0 ? a.floor_ : 1;
    a.hi_ = 10 * a.lo_;
    mn = a.lo_, mx = a.hi_;
  } else if (mn == mx) {
    mn /= 2, mx *= 2;
  }
  const int k0 = decadeOf(mn), k1 = mx > pow10(decadeOf(mx)) * (1 + kOnTick) ? decadeOf(mx) + 1 : decadeOf(mx);
  auto decadeTicks = [&] {
    // Every stride-th decade (stride 1, 2, 5, 10 ...), the ends on multiples of the stride.
    auto firstOf = [&](int stride) { return int(std::floor(double(k0) / stride)) * stride; };
    auto lastOf = [&](int stride) { return int(std::ceil(double(k1) / stride)) * stride; };
    int stride = 1;
    while ((lastOf(stride) - firstOf(stride)) / stride + 1 > maxTicks) stride = int(nextNice(double(stride)));
    const int first = firstOf(stride), last = lastOf(stride);
    for (int k = first; k <= last; k += stride) a.ticks_.push_back({pow10(k), tickLabel(pow10(k), pow10(k), options.unit)});
    a.lo_ = pow10(first);
    a.hi_ = pow10(last);
    return a;
  };
  if (k1 - k0 >= kDecadeTicksFrom) return decadeTicks();
  // 1-2-5 values from the one at or below mn to the one at or above mx.
  std::vector<std::pair<double, int>> marks;  // value, its decade
  for (int k = k0; k <= k1; ++k)
    for (double m : kMantissas) marks.push_back({scaled(m, k), k});
  auto below = std::find_if(marks.rbegin(), marks.rend(), [&](const auto& p) { return p.first <= mn * (1 + kOnTick); });
  auto above = std::find_if(marks.begin(), marks.end(), [&](const auto& p) { return p.first >= mx * (1 - kOnTick); });
  const std::size_t from = std::size_t(marks.rend() - below) - 1, to = std::size_t(above - marks.begin());
  if (int(to - from + 1) > maxTicks) return decadeTicks();
  // Few 1-2-5 values, or data in a small part of their range: linear steps over the data, unless
  // the step multiple below the least value is not positive.
  const StepTicks t = stepTicks(mn, mx, maxTicks, false);
  const double fill = std::log10(mx / mn) / std::log10(marks[to].first / marks[from].first);
  if ((to - from + 1 >= kFewestLogTicks && fill >= kLeastLogFill) || t.first * t.step <= 0) {
    for (std::size_t i = from; i <= to; ++i)
      a.ticks_.push_back({marks[i].first, tickLabel(marks[i].first, pow10(marks[i].second), options.unit)});
    a.lo_ = marks[from].first;
    a.hi_ = marks[to].first;
    return a;
  }
  a.lo_ = t.first * t.step;
  a.hi_ = t.last * t.step;
  for (double n = t.first; n <= t.last; ++n) a.ticks_.push_back({n * t.step, tickLabel(n * t.step, t.step, options.unit)});
  return a;
}

double Axis::fraction(double v) const {
  if (std::isnan(v)) return 0;
  double f;
  if (scale_ == AxisScale::Log10) {
    if (!(v > 0)) return 0;
    f = (std::log10(std::max(v, floor_)) - std::log10(lo_)) / (std::log10(hi_) - std::log10(lo_));
  } else {
    f = (v - lo_) / (hi_ - lo_);
  }
  return std::clamp(f, 0.0, 1.0);
}

}  // namespace nestwalk
