// What rendering one frame of a run drew and cost, as the run's files report it (the CSV's render
// columns, the summary's "render" section, the frame-time plot's render line). The renderer has
// its own statistics (render/view_renderer.h); the run that renders copies them into these
// records, one per walker frame, so the report side needs nothing from the renderer.
// Thread safety: plain value types.
#pragma once

#include "nestwalk/core/enum_array.h"

#include <cstdint>

namespace nestwalk {

/// The timed parts of a rendered frame, in the order they run (Total: the whole frame).
enum class RenderPart : std::uint8_t { Cull, Draw, Readback, Total };
inline constexpr std::size_t kRenderParts = 4;
inline constexpr RenderPart kAllRenderParts[kRenderParts] = {RenderPart::Cull, RenderPart::Draw,
                                                             RenderPart::Readback, RenderPart::Total};
const char* renderPartName(RenderPart p);  // "cull", "draw", "readback", "total"

/// All zero for a frame that was not rendered.
struct RenderRecord {
  bool rendered = false;
  std::uint64_t triangles = 0;          // triangles drawn: terrain levels in view + equipment kept
  std::uint64_t instancesDrawn = 0;     // equipment instances kept by the view culling
  std::uint64_t culledByAabb = 0;       // instances culled by the outer AABB test
  std::uint64_t culledByObb = 0;        // instances the AABB could not decide, culled by the inner OBB
  double terrainErrorPx = 0;            // largest projected vertical error of a drawn terrain level
  EnumArray<RenderPart, kRenderParts> micros;  // wall-clock µs per part (timing columns)
};

}  // namespace nestwalk
