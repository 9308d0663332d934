// The renderer's depth range and aerial haze for a scene: what ViewGraph sets its camera and fog
// to, and what a page drawing the same view (session/walkthrough_site.h) copies.
// Near: nothing the walker may come to is nearer to the eye than the body's horizontal half extent;
// half of the smaller one leaves the near plane's corners clear of it too (clamped to 0.05-0.5 m).
// Far: past the terrain's farthest corner from anywhere above it. Haze: linear, from
// min(1500 m, 0.3 far) to far, into the horizon's colour.
// Units: metres; colours 0-1 RGB. Thread safety: a pure function of the scene.
#pragma once

#include "nestwalk/scene/scene.h"

#include <array>

namespace nestwalk {

struct ViewDepth {
  double nearM = 0.1, farM = 10000;
  double hazeStartM = 1500, hazeEndM = 10000;
};

/// The sky's colour at the horizon (and the haze's), and at the zenith.
inline constexpr std::array<float, 3> kSkyHorizonRgb = {0.78f, 0.85f, 0.93f};
inline constexpr std::array<float, 3> kSkyZenithRgb = {0.30f, 0.50f, 0.82f};

/// The depth range and haze of `scene`'s view (see above); the scene must have a terrain.
ViewDepth viewDepth(const Scene& scene);

}  // namespace nestwalk
