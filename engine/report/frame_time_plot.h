// The frame-time plot of a run (frame_times.png): µs per frame for each part of a step against the
// frame number, with the p50 and p99 of the whole step as dashed lines; when frames were rendered,
// the render time through the rendered frames as well. Above the plot a title and the legend (left
// out when it would leave the plot area under 60 pixels high: small images).
//
// Axes (axis.h, drawn by plot_frame.h): y is log10 over every time of the plot (the parts differ by
// orders of magnitude), each raised to 0.001 µs (kFrameTimeFloorMicros), a time of 0 at the bottom;
// its tick labels carry the unit ("10 µs"). x is linear and tight from the first record's frame to
// the last's (the centre for a single record), at least one frame per tick. The series are lines
// 2 pixels wide (kFrameTimeLineWidth), clipped to the plot area; the percentile lines are one pixel
// wide on a pixel row, dashed 6 on, 4 off.
//
// Colours (RGB): ground green (44,160,44), broad blue (31,119,180), narrow orange (255,127,14),
// total red (214,39,40), render pink (227,119,194); p50 of the step total dashed purple
// (148,103,189), p99 dashed brown (140,86,75); white background, black axes and text, light grey
// (224,224,224) grid lines at the ticks.
//
// Thread safety: keeps no state; each call draws on its own surface (one writer per path at a time,
// core/output_file.h).
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
/// The least time the y axis shows as itself, µs (a step part below it, e.g. 0 with timing off,
/// sits at this height or at the bottom).
inline constexpr double kFrameTimeFloorMicros = 1e-3;
/// The series' line width, pixels: wide enough that a pixel on the line is covered entirely (and
/// so has exactly the series' colour) at every slope.
inline constexpr double kFrameTimeLineWidth = 2;

}  // namespace nestwalk
