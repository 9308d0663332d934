// The peers of the bounding-volume benchmark (volume_bench.h): other libraries answering the same
// OBB-OBB question on the same pairs (do the closed boxes a[k] and b[k] meet? touching counts).
// Each factory converts the boxes to the peer's own types once, outside
// any timing, and returns a Pass (bench_runner.h) over all pairs: verdict k is 1 for overlap.
#pragma once

#include "tools/bench/bench_runner.h"

#include "nestwalk/geometry/nested.h"

#include <cstdint>
#include <vector>

namespace nestwalk::bench {

/// FCL: fcl::OBB<double>::overlap (peers/fcl_boxes.cpp).
Pass<std::uint8_t> fclBoxPairs(const std::vector<Obb<double>>& a, const std::vector<Obb<double>>& b);

/// libccd: ccdMPRIntersect (Minkowski portal refinement) with box support functions
/// (peers/ccd_boxes.cpp). It reads the boxes in place: `a` and `b` must outlive the pass.
Pass<std::uint8_t> ccdBoxPairs(const std::vector<Obb<double>>& a, const std::vector<Obb<double>>& b);

/// Bullet: btBoxBoxDetector::getClosestPoints, the ODE box-box test (peers/bullet_boxes.cpp).
Pass<std::uint8_t> bulletBoxPairs(const std::vector<Obb<double>>& a, const std::vector<Obb<double>>& b);

}  // namespace nestwalk::bench
