// The exact vertical error of one coarse terrain cell against the full-resolution grid: the one
// computation behind every error the level-of-detail rule uses, shared by the chunk builder
// (terrain_chunk.cpp, which explains why the maximum lies where it is evaluated here) and the
// pyramid writer (terrain_pyramid_writer.cpp, which runs it over every level at import).
//
// A coarse cell has the corners (ca, ra), (cb, ra), (cb, rb), (ca, rb) in fine (column, row)
// indices, cb > ca, rb > ra, and is split along its north-west to south-east diagonal like the fine
// cells (heightfield.h): upper triangle (ca, ra), (cb, ra), (cb, rb); lower (ca, ra), (cb, rb),
// (ca, rb). A coarse triangle exists only when its three corners are valid. The error is
//   max |fine(p) - coarse(p)| over every point p where both surfaces exist,
// found at the valid fine samples inside an existing coarse triangle (closed) and, when the cell is
// not square (the last column or row of a level), where its diagonal crosses a fine column, row or
// diagonal. Each such crossing lies on a fine edge (or at a fine sample): the fine surface exists
// there when the edge's two samples are valid and is their linear interpolation, computed from the
// exact integer position of the crossing. Heights are floats widened to double; the result is
// metres, 0 when neither coarse triangle exists.
//
// `Fine` is any grid with `bool valid(int col, int row) const` and `double height(int col, int row)
// const` in fine indices covering the closed cell (the heightfield, or a window of rows of it).
// Thread safety: a pure function of the grid it reads.
#pragma once

#include "nestwalk/terrain/heightfield.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>

namespace nestwalk::terrain {

/// A Heightfield seen as the `Fine` grid below.
struct HeightfieldGrid {
  const Heightfield& hf;
  bool valid(int col, int row) const { return hf.valid(col, row); }
  double height(int col, int row) const { return hf.sample(col, row); }
};

template <class Fine>
double coarseCellError(const Fine& fine, int ca, int ra, int cb, int rb) {
  const bool va = fine.valid(ca, ra), vb = fine.valid(cb, ra), vc = fine.valid(cb, rb), vd = fine.valid(ca, rb);
  const bool up = va && vb && vc, low = va && vc && vd;
  if (!up && !low) return 0.0;
  const double ha = fine.height(ca, ra), hb = fine.height(cb, ra), hc = fine.height(cb, rb), hd = fine.height(ca, rb);
  const int w = cb - ca, h = rb - ra;
  const double invW = 1.0 / w, invH = 1.0 / h;
  double err = 0;
  for (int v = 0; v <= h; ++v)
    for (int u = 0; u <= w; ++u) {
      if (!fine.valid(ca + u, ra + v)) continue;
      // Upper triangle: on or above the diagonal from (0, 0) to (w, h), i.e. u h >= v w.
      const std::int64_t side = std::int64_t(u) * h - std::int64_t(v) * w;
      double coarse;
      if (side >= 0 && up)
        coarse = ha + (u * invW) * (hb - ha) + (v * invH) * (hc - hb);
      else if (side <= 0 && low)
        coarse = ha + (v * invH) * (hd - ha) + (u * invW) * (hc - hd);
      else
        continue;
      err = std::max(err, std::abs(fine.height(ca + u, ra + v) - coarse));
    }
  if (w == h) return err;
  // The diagonal (t w, t h), t in [0, 1], crosses fine columns at t = k / w, fine rows at t = k / h
  // and fine diagonals (u - v = +-m) at t = m / |w - h|. At t = n / d the crossing is the fine point
  // (n w / d, n h / d): `along` gives the fine surface on the edge through it that runs in the
  // direction (du, dv) (0, 1: a column; 1, 0: a row; 1, 1: a diagonal).
  auto crossing = [&](std::int64_t n, std::int64_t d, int du, int dv) {
    // Whole and fractional parts of the crossing along the edge's own direction.
    const std::int64_t pu = n * w, pv = n * h;
    const std::int64_t q = dv ? pv : pu;           // the coordinate that varies along the edge
    const std::int64_t whole = q / d, rest = q % d;
    const double frac = double(rest) / double(d);
    int u0, v0;
    if (du == 0) {  // a column: u is whole
      u0 = int(pu / d), v0 = int(whole);
    } else if (dv == 0) {  // a row: v is whole
      u0 = int(whole), v0 = int(pv / d);
    } else {  // a diagonal: u - v is whole, v = whole + frac
      v0 = int(whole), u0 = int((pu - pv) / d) + v0;
    }
    const int c0 = ca + u0, r0 = ra + v0;
    if (!fine.valid(c0, r0)) return;
    double f = fine.height(c0, r0);
    if (rest != 0) {
      if (!fine.valid(c0 + du, r0 + dv)) return;
      f += frac * (fine.height(c0 + du, r0 + dv) - f);
    }
    const double t = double(n) / double(d);
    err = std::max(err, std::abs(f - (ha + t * (hc - ha))));
  };
  for (int k = 1; k < w; ++k) crossing(k, w, 0, 1);
  for (int k = 1; k < h; ++k) crossing(k, h, 1, 0);
  const int d = std::abs(w - h);
  for (int m = 1; m < d; ++m) crossing(m, d, 1, 1);
  return err;
}

}  // namespace nestwalk::terrain
