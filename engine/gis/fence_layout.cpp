#include "nestwalk/gis/fence_layout.h"

#include "nestwalk/core/angles.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace nestwalk::gis {
namespace {

/// How far a joint (+ gap, - overlap, metres) goes beyond its limit (0: within it).
double excess(double joint, double maxGap, double maxOverlap) {
  return joint >= 0 ? std::max(0.0, joint - maxGap) : std::max(0.0, -joint - maxOverlap);
}

}  // namespace

FenceLayout layoutFence(std::span<const Eigen::Vector2d> line, bool closed, double pieceLength, double maxGap,
                        double maxOverlap) {
  FenceLayout out;
  const std::size_t segments = line.size() < 2 ? 0 : (closed ? line.size() : line.size() - 1);
  std::vector<double> joints(segments, 0.0);  // the joint of each segment: + gap, - overlap
  for (std::size_t k = 0; k < segments; ++k) {
    const Eigen::Vector2d a = line[k], b = line[(k + 1) % line.size()];
    const double length = (b - a).norm();
    if (!(length > 0)) continue;
    const double fit = length / pieceLength;
    const std::size_t lo = std::max<std::size_t>(1, std::size_t(std::floor(fit)));
    const std::size_t hi = std::max<std::size_t>(1, std::size_t(std::ceil(fit)));
    // The count within the limits whose joints are closest to end to end; with neither within
    // them, the one that exceeds its limit least.
    std::size_t n = lo;
    auto jointOf = [&](std::size_t count) { return length / double(count) - pieceLength; };
    const double eLo = excess(jointOf(lo), maxGap, maxOverlap), eHi = excess(jointOf(hi), maxGap, maxOverlap);
    if (eLo == 0.0 && eHi == 0.0) n = std::abs(jointOf(hi)) < std::abs(jointOf(lo)) ? hi : lo;
    else if (eHi < eLo) n = hi;
    const double joint = jointOf(n);
    joints[k] = joint;
    if (excess(joint, maxGap, maxOverlap) > 0.0) {
      char text[200];
      std::snprintf(text, sizeof text,
                    "segment %zu (%.3f m) cannot be covered by %.3f m pieces within max_gap %.3f m and max_overlap "
                    "%.3f m: its joints %s %.3f m",
                    k, length, pieceLength, maxGap, maxOverlap, joint >= 0 ? "leave" : "overlap", std::abs(joint));
      out.problems.push_back(text);
    }
    const Eigen::Vector2d along = (b - a) / length;
    const double heading = headingOf(along.x(), along.y());
    const double spacing = length / double(n);
    for (std::size_t i = 0; i < n; ++i) out.pieces.push_back({a + along * ((double(i) + 0.5) * spacing), heading, k});
    if (n > 1) {
      out.largestGap = std::max(out.largestGap, joint);
      out.largestOverlap = std::max(out.largestOverlap, -joint);
    }
  }
  // The joints at the vertices between segments: the two half joints.
  for (std::size_t k = 0; k + 1 < segments || (closed && k < segments && segments > 1); ++k) {
    const double vertex = 0.5 * (joints[k] + joints[(k + 1) % segments]);
    out.largestGap = std::max(out.largestGap, vertex);
    out.largestOverlap = std::max(out.largestOverlap, -vertex);
  }
  return out;
}

}  // namespace nestwalk::gis
