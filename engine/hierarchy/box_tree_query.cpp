#include "nestwalk/hierarchy/box_tree_query.h"

#include <bit>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace nestwalk::hierarchy_detail {

namespace {

constexpr int kStackEntries = 128;  // 7 pending siblings per level for delta = 8 x 18 levels

struct FloatQuery {
  float lo[3], hi[3];
};

#if defined(__SSE2__)
/// The query's float box broadcast to all lanes, once per query.
struct Lanes {
  __m128 lo[3], hi[3];
  explicit Lanes(const FloatQuery& q) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = _mm_set1_ps(q.lo[k]);
      hi[k] = _mm_set1_ps(q.hi[k]);
    }
  }
};

/// Bit l set when lane l's float box overlaps the query's (closed).
inline unsigned overlapMask(const Block& b, const Lanes& q) {
  __m128 m = _mm_and_ps(_mm_cmple_ps(_mm_load_ps(b.lo[0]), q.hi[0]), _mm_cmpge_ps(_mm_load_ps(b.hi[0]), q.lo[0]));
  m = _mm_and_ps(m, _mm_cmple_ps(_mm_load_ps(b.lo[1]), q.hi[1]));
  m = _mm_and_ps(m, _mm_cmpge_ps(_mm_load_ps(b.hi[1]), q.lo[1]));
  m = _mm_and_ps(m, _mm_cmple_ps(_mm_load_ps(b.lo[2]), q.hi[2]));
  m = _mm_and_ps(m, _mm_cmpge_ps(_mm_load_ps(b.hi[2]), q.lo[2]));
  return unsigned(_mm_movemask_ps(m));
}
/// Bit l set when lane l holds a unit (child < 0: the sign bits).
inline unsigned unitLanes(const Block& b) {
  return unsigned(_mm_movemask_ps(_mm_castsi128_ps(_mm_load_si128(reinterpret_cast<const __m128i*>(b.child)))));
}
#else
struct Lanes {
  FloatQuery q;
  explicit Lanes(const FloatQuery& f) : q(f) {}
};
inline unsigned overlapMask(const Block& b, const Lanes& l) {
  unsigned m = 0;
  for (int i = 0; i < kTreeLanes; ++i) {
    bool o = true;
    for (int k = 0; k < 3; ++k) o = o && b.lo[k][i] <= l.q.hi[k] && b.hi[k][i] >= l.q.lo[k];
    m |= o ? 1u << i : 0u;
  }
  return m;
}
inline unsigned unitLanes(const Block& b) {
  unsigned m = 0;
  for (int i = 0; i < kTreeLanes; ++i) m |= b.child[i] < 0 ? 1u << i : 0u;
  return m;
}
#endif

inline bool overlapsExact(const Leaf& f, const Aabb<double>& q) {
  return f.lo[0] <= q.max[0] && q.min[0] <= f.hi[0] && f.lo[1] <= q.max[1] && q.min[1] <= f.hi[1] &&
         f.lo[2] <= q.max[2] && q.min[2] <= f.hi[2];
}

/// Visits the node [first, first + span) and everything below it. The first child node hit is
/// descended into directly (no stack round trip on the common single path), the others wait on
/// the stack.
template <bool kCount>
void traverse(const TreeData& t, std::uint32_t first, std::uint32_t span, const Lanes& q, const Aabb<double>& box,
              std::vector<std::uint32_t>& out, BroadPhaseCounters* counters) {
  struct Entry {
    std::uint32_t first, span;
  };
  Entry stack[kStackEntries];
  int sp = 0;
  const Block* blocks = t.blocks.data();
  const Leaf* leaves = t.leaves.data();
  for (;;) {
    std::uint32_t nextFirst = 0, nextSpan = 0;  // nextSpan 0: no child node hit yet
    for (std::uint32_t bi = first; bi < first + span; ++bi) {
      const Block& b = blocks[bi];
      const unsigned hit = overlapMask(b, q);
      const unsigned units = unitLanes(b);
      if constexpr (kCount) {
        for (int l = 0; l < kTreeLanes; ++l) {
          if (b.child[l] == kEmptyLane) continue;
          if (b.child[l] >= 0) ++counters->nodeTests;
          else ++counters->leafTests;
        }
      }
      for (unsigned m = hit & ~units; m != 0; m &= m - 1) {
        const int l = std::countr_zero(m);
        const std::uint32_t c = std::uint32_t(b.child[l]);
        __builtin_prefetch(blocks + c);
        if (nextSpan == 0) {
          nextFirst = c;
          nextSpan = b.span[l];
        } else if (sp < kStackEntries) {
          stack[sp++] = {c, b.span[l]};
        } else {
          traverse<kCount>(t, c, b.span[l], q, box, out, counters);
        }
      }
      for (unsigned m = hit & units; m != 0; m &= m - 1) {
        const Leaf& f = leaves[~b.child[std::countr_zero(m)]];
        if (overlapsExact(f, box)) {
          out.push_back(f.unit);
          if constexpr (kCount) ++counters->leafHits;
        }
      }
    }
    if (nextSpan != 0) {
      first = nextFirst;
      span = nextSpan;
    } else if (sp > 0) {
      --sp;
      first = stack[sp].first;
      span = stack[sp].span;
    } else {
      return;
    }
  }
}

}  // namespace

void queryTree(const TreeData& t, const Aabb<double>& box, std::vector<std::uint32_t>& out,
               BroadPhaseCounters* counters) {
  if (t.rootSpan == 0) return;
  FloatQuery q;
  for (int k = 0; k < 3; ++k) {
    q.lo[k] = roundDown(box.min[k] - t.origin[k]);
    q.hi[k] = roundUp(box.max[k] - t.origin[k]);
  }
  const Lanes lanes(q);
  if (counters) traverse<true>(t, 0, t.rootSpan, lanes, box, out, counters);
  else traverse<false>(t, 0, t.rootSpan, lanes, box, out, nullptr);
}

}  // namespace nestwalk::hierarchy_detail
