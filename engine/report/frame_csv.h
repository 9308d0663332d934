// The per-frame CSV of a run (frames.csv): one row per walker step, written through a temporary
// file renamed at the end (core/output_file.h).
// Thread safety: pure apart from the file written (one writer per path at a time,
// core/output_file.h).
#pragma once

#include "nestwalk/report/render_record.h"
#include "nestwalk/walker/frame_record.h"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace nestwalk {

/// The header row's columns, in order. The timing columns (names starting with "us_") come last, so
/// that two runs with the same inputs give byte-identical files once those columns are cut:
///   frame,time,x,y,z,heading,pitch,flying,has_ground,ground,blocked,blocked_by,
///   node_tests,aabb_aabb,aabb_obb,obb_obb,np,nu,
///   rendered,triangles,instances_drawn,culled_aabb,culled_obb,terrain_error_px,
///   us_ground,us_broad,us_narrow,us_total,us_render_cull,us_render_draw,us_render_readback,us_render_total
const std::vector<std::string>& frameCsvColumns();

/// One cell of a frame's row: what the CSV writes and what the results layers (result_layers.h)
/// store, from the one function that reads the records. Integers (counters, flags, the frame) and
/// reals carry `number` (unset: an empty cell, ground without ground); blocked_by carries `text`.
enum class FrameCellKind : std::uint8_t { Integer, Real, Text };
struct FrameCell {
  FrameCellKind kind = FrameCellKind::Real;
  std::optional<double> number;
  std::string text;
  int digits = 0;  // Real: digits after the point in the CSV
};
/// The cells of one row, in frameCsvColumns()'s order (`out` is resized).
void frameCells(const FrameRecord& record, const RenderRecord& render, std::vector<FrameCell>& out);

/// Writes `records` with `renders` (one per record, or empty: nothing was rendered, the render
/// columns are 0). time %.6f s; x, y, z, ground %.4f m (ground empty without ground); heading,
/// pitch %.6f degrees; flags 0/1; counters integers; terrain_error_px %.4f; us_* %.3f µs. Numbers
/// are locale-independent (std::to_chars); blocked_by is quoted (RFC 4180) when it holds a comma,
/// a quote or a line break. Throws std::invalid_argument when `renders` is neither empty nor as
/// long as `records`, InputError naming `path` when it cannot be written.
void writeFrameCsv(const std::string& path, const std::vector<FrameRecord>& records,
                   std::span<const RenderRecord> renders = {});

}  // namespace nestwalk
