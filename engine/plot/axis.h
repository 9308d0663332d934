// The one axis and tick rule of every picture the engine draws: the frame-time plot's frame and time
// axes, the methods report's scatter and bar plots, the top-down map's scale bar. An axis maps the
// values it was fitted to onto [0, 1] (a plot then maps that onto its pixels) and carries its ticks:
// values of the 1-2-5 sequence (m · 10^k, m in {1, 2, 5}) or multiples of one such step, each with
// its label as text ("0.1", "250", "1e-6", "10 µs").
//
// Linear axes: the step is the smallest 1-2-5 value that gives at most maxTicks ticks; the ticks
// are the multiples of the step; the ends are the ticks enclosing the data (or, `tight`, the data's
// own least and largest values, the ticks lying within).
//
// Log10 axes, over the positive values (each raised to the floor when one is set):
//  - data whose decades (from the least value's decade to the largest's, rounded outwards) number
//    3 or more: ticks at whole decades (every 2nd, 5th, 10th ... decade when there are more than
//    maxTicks), the ends at the decades enclosing the data;
//  - fewer decades: ticks at the 1-2-5 values, the ends at the greatest one at or below the least
//    value and the least one at or above the largest (e.g. 2 .. 50 for data from 3 to 40); whole
//    decades as above when these are more than maxTicks;
//  - but when that gives fewer than 3 ticks (e.g. from 3 to 4), or the data would fill less than
//    half of that axis (in log10; e.g. from 12 to 21 on 10 .. 50): ticks as on a linear axis over
//    the data (3.0, 3.2, ... 4.0; 12, 14, ... 22), placed on the log scale, unless the step
//    multiple below the least value is not positive.
//  A single value v is widened to [v / 2, 2 v].
// Where positions are asked: NaN, and on log axes values <= 0, lie at the lower end (fraction 0);
// positive values below the floor at the floor; values beyond the ends at the ends.
//
// Empty or all-NaN data: a linear axis runs 0 .. 1, a log one over the decade above the floor
// (1 .. 10 without a floor).
//
// Thread safety: an Axis is an immutable value once fitted; the functions are pure.
// Locale: tick labels are formatted with snprintf, which follows the process's C locale
// (LC_NUMERIC); nestwalk never changes it, and the labels above assume the default "C" locale.
#pragma once

#include <span>
#include <string>
#include <vector>

namespace nestwalk {

enum class AxisScale { Linear, Log10 };

struct AxisOptions {
  AxisScale scale = AxisScale::Linear;
  double logFloor = 0;        // log: positive values below it are shown at it (0: none)
  bool includeZero = false;   // linear: the axis reaches 0
  bool tight = false;         // linear: the ends are the data's extremes, not the enclosing ticks
  int maxTicks = 8;           // at most this many ticks (raised to 3)
  double minStep = 0;         // linear: the step is at least the 1-2-5 value at or above this
                              // (frame numbers: 1); 0 for none
  std::string unit = "";      // appended to every tick label after a space ("10 µs"); "" for none
};

struct AxisTick {
  double value = 0;
  std::string label;
};

class Axis {
 public:
  /// The axis over the finite values in `values` (see above).
  static Axis fit(std::span<const double> values, const AxisOptions& options = {});

  AxisScale scale() const { return scale_; }
  double lo() const { return lo_; }   // the lower end, a value
  double hi() const { return hi_; }   // the upper end, a value (> lo)
  const std::vector<AxisTick>& ticks() const { return ticks_; }

  /// Where `v` lies between the ends: 0 at lo, 1 at hi, linear in v or in log10 v (see above for
  /// NaN, values <= 0 and values off the axis).
  double fraction(double v) const;
  /// fraction(v) mapped linearly onto [p0, p1] (e.g. pixels).
  double position(double v, double p0, double p1) const { return p0 + fraction(v) * (p1 - p0); }

 private:
  AxisScale scale_ = AxisScale::Linear;
  double lo_ = 0, hi_ = 1, floor_ = 0;
  std::vector<AxisTick> ticks_;
};

/// The least 1-2-5 value (m · 10^k, m in {1, 2, 5}) at or above x > 0.
double niceCeil(double x);
/// The greatest 1-2-5 value at or below x > 0 (the scale bar's length).
double niceFloor(double x);

/// A tick value as text, to the digit of `resolution` (a 1-2-5 value: the step between ticks, or
/// the decade of a log tick): decimals when 1e-4 <= |value| < 1e6 ("0.05", "250", "1.0"; zero as
/// "0" or "0.0", never "-0"), else scientific with the digits the resolution needs ("1e-6",
/// "2.5e7"); then " " + unit.
std::string tickLabel(double value, double resolution, const std::string& unit = "");

}  // namespace nestwalk
