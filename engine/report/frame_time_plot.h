// The frame-time plot of a run (frame_times.png): µs per frame for each part of a step against the
// frame number, with the p50 and p99 of the whole step as dashed lines and a legend; when frames
// were rendered, the render time through the rendered frames as well. The y axis is log10 over
// whole decades (the parts differ by orders of magnitude; a time of 0 sits on the floor), the x
// axis runs from the first record's frame to the last's. Colours (RGB): ground green (44,160,44),
// broad blue (31,119,180), narrow orange (255,127,14), total red (214,39,40), render pink
// (227,119,194); p50 of the step total dashed purple (148,103,189), p99 dashed brown (140,86,75);
// white background, black axes and text, light grey (224,224,224) grid.
#pragma once

#include "nestwalk/report/render_record.h"
#include "nestwalk/walker/frame_record.h"

#include <span>
#include <string>
#include <vector>

namespace nestwalk {

/// Writes the plot as PNG through a temporary file renamed at the end. `renders`: one per record,
/// or empty. Throws InputError naming `path` for a size below kMinFrameTimePlotWidth x
/// kMinFrameTimePlotHeight pixels or when the PNG cannot be written.
void writeFrameTimePlot(const std::string& path, const std::vector<FrameRecord>& records,
                        std::span<const RenderRecord> renders = {}, int width = 1200, int height = 500);

inline constexpr int kMinFrameTimePlotWidth = 200, kMinFrameTimePlotHeight = 120;

}  // namespace nestwalk
