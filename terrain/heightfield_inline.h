// Heightfield::groundHeight, inline (the fast path of the O(1) lookup); included by heightfield.h.
// Thread safety: as Heightfield's const queries (heightfield.h).
#pragma once

#include "nestwalk/terrain/heightfield.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace nestwalk::terrain {

inline std::optional<double> Heightfield::groundHeight(double x, double y) const {
  // Every path yields a double, NaN for no ground, so that the optional is built once, in registers.
  double h = std::numeric_limits<double>::quiet_NaN();
  // Beyond the outermost sample lines (positions as samplePosition() computes them), or NaN: none.
  if (x >= originX_ && x <= xLast_ && y <= originY_ && y >= yLast_) [[likely]] {
    const double u = (x - originX_) * invDx_, v = (originY_ - y) * invDy_;
    const int c = std::min(int(u), cols_ - 2), r = std::min(int(v), rows_ - 2);
    const double fx = u - c, fy = v - r;
    // Within kSnapBand_ of a grid line the query may lie exactly on it: the full path (out of line)
    // snaps; it also settles the points whose triangle has a hole.
    // Paged samples (clean_ null) take the full path too (heightfield.h: the same arithmetic).
    if (fx < kSnapBand_ || fx > 1.0 - kSnapBand_ || fy < kSnapBand_ || fy > 1.0 - kSnapBand_ || !clean_) [[unlikely]] {
      h = groundHeightFull(x, y);
    } else {
      // Upper triangle where fx >= fy: h00 + fx (h10 - h00) + fy (h11 - h10); lower where fy > fx:
      // h00 + fy (h01 - h00) + fx (h11 - h01). Both are h00 + p (b - h00) + q (h11 - b) with
      // p = max(fx, fy), q = min(fx, fy) and b the third corner: the same operations, no branch.
      const float* H = clean_ + std::size_t(r) * std::size_t(cols_) + std::size_t(c);
      const double p = std::max(fx, fy), q = std::min(fx, fy);
      const std::ptrdiff_t third = 1 + std::ptrdiff_t(fx < fy) * std::ptrdiff_t(cols_ - 1);  // (c+1,r) or (c,r+1)
      const double h00 = H[0], h11 = H[cols_ + 1], b = H[third];
      h = h00 + p * (b - h00) + q * (h11 - b);
      if (std::isnan(h)) [[unlikely]]
        h = groundHeightFull(x, y);
    }
  }
  return std::isnan(h) ? std::nullopt : std::optional<double>(h);
}

}  // namespace nestwalk::terrain
