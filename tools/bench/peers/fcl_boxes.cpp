// FCL's box tests as peers of the bounding-volume benchmark (box_peers.h). Conversion: a
// nestwalk::Obb<double> becomes an fcl::OBB<double> with the same axes (columns), centre and half
// extents, exactly (both are double); an outer box becomes an fcl::AABB<double> of its corners.
#include "tools/bench/peers/box_peers.h"

#include <fcl/math/bv/AABB.h>
#include <fcl/math/bv/OBB.h>

#include <memory>

namespace nestwalk::bench {
namespace {

fcl::OBB<double> toFcl(const Obb<double>& b) {
  fcl::OBB<double> f;
  f.axis = b.axes;
  f.To = b.center;
  f.extent = b.halfExtents;
  return f;
}

}  // namespace

Pass<std::uint8_t> fclBoxPairs(const std::vector<Obb<double>>& a, const std::vector<Obb<double>>& b) {
  auto fa = std::make_shared<std::vector<fcl::OBB<double>>>(), fb = std::make_shared<std::vector<fcl::OBB<double>>>();
  for (std::size_t k = 0; k < a.size(); ++k) {
    fa->push_back(toFcl(a[k]));
    fb->push_back(toFcl(b[k]));
  }
  return [fa, fb](std::uint8_t* verdicts) {
    const std::vector<fcl::OBB<double>>&a = *fa, &b = *fb;
    return answerAll(a.size(), verdicts, [&](std::size_t k) { return a[k].overlap(b[k]); });
  };
}

}  // namespace nestwalk::bench
