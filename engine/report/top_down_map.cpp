// The top-down map of a walker run: the terrain's hillshade (hillshade.h), equipment footprints, the
// path, blocked frames, expectations and a legend column drawn on the drawing surface
// (drawing_surface.h) and written as PNG. What is drawn, and in which colours, is documented in
// top_down_map.h. Map coordinates are UTM-sized, so every position goes through TopDownFrame (a
// difference from the image's corner, in double) before it becomes a pixel.
#include "nestwalk/report/top_down_map.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/geometry/convex_hull.h"
#include "nestwalk/plot/axis.h"
#include "nestwalk/plot/drawing_surface.h"
#include "nestwalk/terrain/hillshade.h"
#include "nestwalk/terrain/terrain_pyramid.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <set>

namespace nestwalk {
namespace {

// Colours (top_down_map.h documents them).
constexpr Rgb kLowTint{96, 140, 96}, kHighTint{236, 214, 170};
constexpr double kAmbient = 0.35;  // terrain colour = tint * (kAmbient + (1 - kAmbient) * shade)
constexpr Rgb kHoleGrey{128, 128, 128};
constexpr Rgb kOutsideTerrain{255, 255, 255};
constexpr Rgb kWalkColour{40, 90, 255}, kFlyColour{0, 215, 255};
constexpr Rgb kRed{230, 0, 0};  // blocked marks, blocking units, failed expectations
constexpr Rgb kMetColour{0, 190, 0};
constexpr Rgb kInk{0, 0, 0}, kPaper{255, 255, 255};
constexpr Rgb kNoKindColour{255, 0, 255};

struct KindColour {
  const char* kind;
  Rgb colour;
};
constexpr KindColour kKindColours[] = {
    {"pole", {255, 215, 0}},        {"station", {0, 150, 150}},  {"solar", {30, 40, 130}},
    {"logger", {245, 240, 200}},    {"piezometer", {255, 140, 0}}, {"container", {150, 65, 25}},
    {"barrier", {205, 205, 205}},   {"vehicle", {40, 40, 40}},
};
constexpr Rgb kOtherKindColours[] = {{230, 120, 180}, {120, 170, 255}, {180, 100, 255},
                                     {255, 175, 120}, {0, 110, 80},    {150, 150, 60}};

// The sun: azimuth clockwise from north, altitude above the horizon.
constexpr double kSunAzimuthDeg = 315, kSunAltitudeDeg = 45;

// Sizes, pixels.
constexpr double kPathWidth = 3;          // the path; 3 pixels cover the pixel of every eye entirely
constexpr double kCrossArm = 4;           // blocked cross: arms reaching 4 along x and y from the eye,
constexpr double kCrossWidth = 3;         // 3 wide
constexpr double kMarkerRadius = 5;       // start and end discs
constexpr double kExpectationRadius = 6;
constexpr double kRimWidth = 1.5;         // the rims of markers, just outside them
constexpr double kTinyFootprint = 4;      // footprints narrower than this become discs
constexpr double kTinyRadius = 2;         // their disc, and its outline's radius
constexpr double kTinyRimRadius = 3;
constexpr double kBlockerWidth = 3;       // the outline of a blocking unit; a tiny one's circle:
constexpr double kTinyBlockerRadius = 4.5, kTinyBlockerWidth = 2;
constexpr double kMapFontSize = 12;       // labels on the map and in the legend column, pixels per em
// The legend column.
constexpr double kColumnPadding = 8;
constexpr double kRowHeight = 18, kSwatchWidth = 16, kSwatchGap = 6;
constexpr double kArrowLength = 28;
constexpr double kMinScaleBar = 60;       // the column leaves at least this much room for the scale bar
constexpr int kScaleBarTicks = 6;         // at most this many ticks (5 segments) on the scale bar
constexpr double kScaleBarHeight = 6;
constexpr double kLabelGap = 6;           // least gap between the scale bar's labels
constexpr std::size_t kMaxLabelChars = 20;  // kinds' labels are cut to this (bytes, at a character)

/// The first `n` bytes of UTF-8 text, not cutting a character.
std::string cutText(const std::string& s, std::size_t n) {
  if (s.size() <= n) return s;
  while (n > 0 && (static_cast<unsigned char>(s[n]) & 0xC0) == 0x80) --n;
  return s.substr(0, n);
}

Rgb kindColour(const std::string& kind) {
  if (kind.empty()) return kNoKindColour;
  for (const KindColour& k : kKindColours)
    if (kind == k.kind) return k.colour;
  std::uint32_t hash = 2166136261u;  // FNV-1a
  for (char c : kind) hash = (hash ^ static_cast<unsigned char>(c)) * 16777619u;
  return kOtherKindColours[hash % std::size(kOtherKindColours)];
}

bool finite2(const Eigen::Vector3d& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }

/// What writeTopDownMap and topDownFrame refuse; `subject` starts the message (the file's path, or
/// "top-down map").
void checkInputs(const Scene& scene, const TopDownMapOptions& options, const std::string& subject) {
  if (!scene.terrain) throw InputError(subject + ": cannot draw a top-down map: the scene has no terrain");
  if (options.maxSize < kMinTopDownMapSize)
    throw InputError(subject + ": a top-down map of at most " + std::to_string(options.maxSize) +
                     " pixels is too small (at least " + std::to_string(kMinTopDownMapSize) + ")");
}

// ---- terrain -------------------------------------------------------------------------------------

/// Per-sample shades over a window of the grid (NaN at holes).
class ShadeWindow {
 public:
  ShadeWindow(const terrain::Heightfield& hf, int firstCol, int lastCol, int firstRow, int lastRow)
      : firstCol_(firstCol), firstRow_(firstRow), cols_(lastCol - firstCol + 1),
        shade_(std::size_t(cols_) * std::size_t(lastRow - firstRow + 1), std::numeric_limits<float>::quiet_NaN()) {
    const Eigen::Vector3d sun = terrain::sunDirection(kSunAzimuthDeg, kSunAltitudeDeg);
    for (int r = firstRow; r <= lastRow; ++r)
      for (int c = firstCol; c <= lastCol; ++c)
        if (hf.valid(c, r)) shade_[index(c, r)] = float(terrain::hornShade(hf, c, r, sun));
  }
  float at(int col, int row) const { return shade_[index(col, row)]; }

 private:
  std::size_t index(int col, int row) const {
    return std::size_t(row - firstRow_) * std::size_t(cols_) + std::size_t(col - firstCol_);
  }
  int firstCol_, firstRow_, cols_;
  std::vector<float> shade_;
};

/// The shade at grid position (u, v) (columns east, rows south), bilinear over the cell's valid
/// samples; nullopt when none of them is valid.
std::optional<double> shadeAt(const ShadeWindow& shades, const terrain::Heightfield& hf, double u, double v) {
  const int c0 = std::min(int(u), hf.cols() - 2), r0 = std::min(int(v), hf.rows() - 2);
  const double fu = u - c0, fv = v - r0;
  double sum = 0, weights = 0;
  std::optional<double> any;
  for (int dr = 0; dr <= 1; ++dr)
    for (int dc = 0; dc <= 1; ++dc) {
      const float s = shades.at(c0 + dc, r0 + dr);
      if (std::isnan(s)) continue;
      const double w = (dc ? fu : 1 - fu) * (dr ? fv : 1 - fv);
      sum += w * s;
      weights += w;
      any = s;
    }
  if (weights > 0) return sum / weights;
  return any;
}

Rgb terrainColour(double heightFraction, double shade) {
  const double light = kAmbient + (1 - kAmbient) * shade;
  auto channel = [&](std::uint8_t low, std::uint8_t high) {
    return std::uint8_t(std::clamp(std::lround((low + heightFraction * (high - low)) * light), 0L, 255L));
  };
  return {channel(kLowTint.r, kHighTint.r), channel(kLowTint.g, kHighTint.g), channel(kLowTint.b, kHighTint.b)};
}

/// The samples a map of the frame's pixel size is drawn from, when the terrain has a pyramid and a
/// pixel spans two or more of its cells: the window of the coarsest level whose samples are at most
/// a pixel apart, over the frame with two samples to spare, as a heightfield of its own (the level's
/// stored samples moved by the scene's height shift, holes where the DEM has them). Only the level's
/// regular columns and rows (fine index a multiple of the level's step; the level's last one may
/// sit closer) are taken. nullopt: draw from the fine samples.
std::optional<terrain::Heightfield> levelWindow(const Scene& scene, const TopDownFrame& frame) {
  if (!scene.terrainPyramid) return std::nullopt;
  const terrain::TerrainPyramid& pyramid = *scene.terrainPyramid;
  const terrain::Heightfield& fine = *scene.terrain;
  const terrain::PyramidLayout& layout = pyramid.layout();
  if (layout.cols != fine.cols() || layout.rows != fine.rows()) return std::nullopt;
  const double cell = std::max(fine.dx(), fine.dy());
  int level = 0;
  while (level + 1 < layout.levels && terrain::PyramidLayout::step(level + 1) * cell <= frame.metresPerPixel) ++level;
  if (level == 0) return std::nullopt;
  const int step = terrain::PyramidLayout::step(level);
  const Eigen::Vector2d origin = fine.origin();
  const double east = frame.west + frame.width * frame.metresPerPixel;
  const double north = frame.south + frame.height * frame.metresPerPixel;
  const double sx = step * fine.dx(), sy = step * fine.dy();
  auto clampIndex = [](double i, int last) { return int(std::clamp(std::floor(i), 0.0, double(last))); };
  const int lastI = (fine.cols() - 1) / step, lastJ = (fine.rows() - 1) / step;  // the regular ones
  const int i0 = clampIndex((frame.west - origin.x()) / sx - 2, lastI), i1 = clampIndex((east - origin.x()) / sx + 3, lastI);
  const int j0 = clampIndex((origin.y() - north) / sy - 2, lastJ), j1 = clampIndex((origin.y() - frame.south) / sy + 3, lastJ);
  if (i1 - i0 < 1 || j1 - j0 < 1) return std::nullopt;
  std::vector<float> heights = pyramid.readHeights(level, i0, j0, i1 - i0 + 1, j1 - j0 + 1);
  const std::optional<float> noData = pyramid.noData();
  for (float& h : heights)
    if (!std::isfinite(h) || (noData && h == *noData))
      h = std::numeric_limits<float>::quiet_NaN();
    else if (scene.terrainHeightShift != 0.0)
      h = float(double(h) + scene.terrainHeightShift);
  return terrain::Heightfield(i1 - i0 + 1, j1 - j0 + 1, std::move(heights), origin.x() + i0 * sx,
                              origin.y() - j0 * sy, sx, sy);
}

void drawTerrain(DrawingSurface& surface, const TopDownFrame& frame, const Scene& scene) {
  const terrain::Heightfield& fine = *scene.terrain;
  const std::optional<terrain::Heightfield> level = levelWindow(scene, frame);
  const terrain::Heightfield& hf = level ? *level : fine;
  const Eigen::Vector2d origin = hf.origin();
  const double lastU = hf.cols() - 1, lastV = hf.rows() - 1;
  auto gridU = [&](double x) { return (x - origin.x()) / hf.dx(); };
  auto gridV = [&](double y) { return (origin.y() - y) / hf.dy(); };
  // The samples the pixels interpolate from, with a sample to spare on each side.
  auto clampIndex = [](double i, double last) { return int(std::clamp(std::floor(i), 0.0, last)); };
  const double east = frame.west + frame.width * frame.metresPerPixel;
  const double north = frame.south + frame.height * frame.metresPerPixel;
  const ShadeWindow shades(hf, clampIndex(gridU(frame.west) - 1, lastU), clampIndex(gridU(east) + 2, lastU),
                           clampIndex(gridV(north) - 1, lastV), clampIndex(gridV(frame.south) + 2, lastV));

  // The tint spans the whole terrain's heights, whichever samples the pixels read.
  const auto range = fine.heightRange();
  const double lowest = range ? range->first : 0, highest = range ? range->second : 0;
  const Eigen::Vector2d fineOrigin = fine.origin();
  const double fineLastX = fineOrigin.x() + (fine.cols() - 1) * fine.dx();
  const double fineLastY = fineOrigin.y() - (fine.rows() - 1) * fine.dy();
  const double lastX = origin.x() + lastU * hf.dx(), lastY = origin.y() - lastV * hf.dy();
  std::vector<Rgb> pixels(std::size_t(frame.width) * std::size_t(frame.height), kOutsideTerrain);
  for (int j = 0; j < frame.height; ++j)
    for (int i = 0; i < frame.width; ++i) {
      Rgb& out = pixels[std::size_t(j) * std::size_t(frame.width) + std::size_t(i)];
      Eigen::Vector2d p = frame.pixelCentre(i, j);
      if (!(p.x() >= fineOrigin.x() && p.x() <= fineLastX && p.y() <= fineOrigin.y() && p.y() >= fineLastY)) continue;
      // Drawn from a level: a centre past its last regular sample (less than a pixel from the
      // terrain's east or south edge) takes the nearest point of the level's window.
      p = {std::clamp(p.x(), origin.x(), lastX), std::clamp(p.y(), lastY, origin.y())};
      const double u = std::clamp(gridU(p.x()), 0.0, lastU), v = std::clamp(gridV(p.y()), 0.0, lastV);
      const std::optional<double> ground = hf.groundHeight(p.x(), p.y());
      const std::optional<double> shade = ground ? shadeAt(shades, hf, u, v) : std::nullopt;
      if (!shade) {
        out = kHoleGrey;
        continue;
      }
      const double fraction = highest > lowest ? std::clamp((*ground - lowest) / (highest - lowest), 0.0, 1.0) : 0.5;
      out = terrainColour(fraction, *shade);
    }
  surface.putPixels(0, 0, frame.width, frame.height, pixels);
}

// ---- footprints ----------------------------------------------------------------------------------

/// The x-y footprint of a local-frame OBB in continuous pixel coordinates.
std::vector<Eigen::Vector2d> footprint(const Obb<double>& box, const Scene& scene, const TopDownFrame& frame) {
  std::vector<Eigen::Vector2d> corners;
  for (int i = 0; i < 8; ++i) {
    const Vec3<double> p = box.corner(i);
    corners.push_back(frame.toPixel({p.x() + scene.origin.x(), p.y() + scene.origin.y()}));
  }
  std::vector<Eigen::Vector2d> outline;
  for (int k : convexHull2d(corners)) outline.push_back(corners[std::size_t(k)]);
  return outline;
}

struct PixelBox {
  Eigen::Vector2d min, max;
  Point centre() const { return 0.5 * (min + max); }
  bool tiny() const { return (max - min).maxCoeff() < kTinyFootprint; }
  bool meets(const DrawingSurface& surface) const {
    return max.x() >= 0 && max.y() >= 0 && min.x() <= surface.width() && min.y() <= surface.height();
  }
};

PixelBox boundsOf(const std::vector<Eigen::Vector2d>& polygon) {
  PixelBox b{polygon.front(), polygon.front()};
  for (const Eigen::Vector2d& p : polygon) {
    b.min = b.min.cwiseMin(p);
    b.max = b.max.cwiseMax(p);
  }
  return b;
}

void drawFootprint(DrawingSurface& surface, const std::vector<Eigen::Vector2d>& polygon, Rgb fill) {
  const PixelBox box = boundsOf(polygon);
  if (!box.meets(surface)) return;
  if (box.tiny()) {
    surface.disc(box.centre(), kTinyRadius, fill);
    surface.circle(box.centre(), kTinyRimRadius, 1, darker(fill));
    return;
  }
  surface.fillPolygon(polygon, fill);
  surface.strokePolygon(polygon, 1, darker(fill));
}

void drawBlockerOutline(DrawingSurface& surface, const std::vector<Eigen::Vector2d>& polygon) {
  const PixelBox box = boundsOf(polygon);
  if (!box.meets(surface)) return;
  if (box.tiny()) {
    surface.circle(box.centre(), kTinyBlockerRadius, kTinyBlockerWidth, kRed);
    return;
  }
  surface.strokePolygon(polygon, kBlockerWidth, kRed);
}

// ---- run marks -----------------------------------------------------------------------------------

/// The continuous pixel position of a map point.
Point at(const TopDownFrame& frame, const Eigen::Vector3d& map) { return frame.toPixel(map.head<2>()); }

void drawCross(DrawingSurface& surface, Point p, Rgb c) {
  for (const Point& arm : {Point(kCrossArm, kCrossArm), Point(kCrossArm, -kCrossArm)}) {
    const Point ends[] = {p - arm, p + arm};
    surface.polyline(ends, kCrossWidth, c);
  }
}

void drawMarker(DrawingSurface& surface, Point p, double radius, Rgb fill, Rgb rim) {
  surface.disc(p, radius, fill);
  surface.circle(p, radius + kRimWidth / 2, kRimWidth, rim);
}

void drawPath(DrawingSurface& surface, const TopDownFrame& frame, const std::vector<FrameRecord>& records) {
  // Runs of one mode as one line each; the segment into a record takes that record's mode, so a
  // run starts at the last eye of the run before it.
  std::vector<Point> run;
  bool flying = false;
  auto flush = [&] {
    surface.polyline(run, kPathWidth, flying ? kFlyColour : kWalkColour);
    run.clear();
  };
  for (const FrameRecord& r : records) {
    if (!finite2(r.eye)) {
      flush();
      continue;
    }
    if (!run.empty() && r.flying != flying) {
      const Point last = run.back();
      flush();
      run.push_back(last);
    }
    flying = r.flying;
    run.push_back(at(frame, r.eye));
  }
  flush();
}

/// The footprints of the collision units that blocked the run, outlined in red.
void drawBlockingUnits(DrawingSurface& surface, const TopDownFrame& frame, const Scene& scene,
                       const std::vector<FrameRecord>& records) {
  std::set<std::string> blockers;
  for (const FrameRecord& r : records)
    if (r.blocked) blockers.insert(r.blockedBy);
  for (const std::string& name : blockers) {
    const int unit = scene.findUnit(name);
    if (unit >= 0) drawBlockerOutline(surface, footprint(scene.units[std::size_t(unit)].volume.inner, scene, frame));
  }
}

void drawBlockedFrames(DrawingSurface& surface, const TopDownFrame& frame, const std::vector<FrameRecord>& records) {
  for (const FrameRecord& r : records)
    if (r.blocked && finite2(r.eye)) drawCross(surface, at(frame, r.eye), kRed);
}

void drawStartAndEnd(DrawingSurface& surface, const TopDownFrame& frame, const std::vector<FrameRecord>& records) {
  std::vector<const FrameRecord*> drawn;
  for (const FrameRecord& r : records)
    if (finite2(r.eye)) drawn.push_back(&r);
  if (drawn.empty()) return;
  const Point start = at(frame, drawn.front()->eye), end = at(frame, drawn.back()->eye);
  drawMarker(surface, end, kMarkerRadius, kInk, kPaper);
  drawMarker(surface, start, kMarkerRadius, kPaper, kInk);
  const double offset = kMarkerRadius + 4;
  TextStyle label{.size = kMapFontSize, .colour = kInk, .v = VAlign::Top, .halo = true, .haloColour = kPaper};
  surface.text(end + Point(offset, -offset), "end", label);
  label.v = VAlign::Bottom;
  surface.text(start + Point(offset, offset), "start", label);
}

void drawExpectations(DrawingSurface& surface, const TopDownFrame& frame,
                      const std::vector<ExpectationResult>& expectations) {
  for (const ExpectationResult& e : expectations)
    if (finite2(e.eye)) drawMarker(surface, at(frame, e.eye), kExpectationRadius, e.met ? kMetColour : kRed, kInk);
}

// ---- the legend column ---------------------------------------------------------------------------

struct LegendEntry {
  std::string label;
  std::function<void(DrawingSurface&, Point left)> swatch;  // draws in kSwatchWidth from `left`, about
                                                            // 5 pixels above and below it
};

/// The marks the run put on the map, then the scene's equipment kinds (sorted).
std::vector<LegendEntry> legendEntries(const Scene& scene, const std::vector<FrameRecord>& records,
                                       const std::vector<ExpectationResult>& expectations) {
  auto any = [](const auto& list, auto predicate) { return std::any_of(list.begin(), list.end(), predicate); };
  auto pathSwatch = [](Rgb c) {
    return [c](DrawingSurface& s, Point p) { s.line(p, p + Point(kSwatchWidth, 0), kPathWidth, c); };
  };
  auto discSwatch = [](Rgb c) {
    return [c](DrawingSurface& s, Point p) { drawMarker(s, p + Point(kSwatchWidth / 2, 0), 4, c, kInk); };
  };
  std::vector<LegendEntry> entries;
  if (any(records, [](const FrameRecord& r) { return !r.flying; })) entries.push_back({"walk", pathSwatch(kWalkColour)});
  if (any(records, [](const FrameRecord& r) { return r.flying; })) entries.push_back({"fly", pathSwatch(kFlyColour)});
  if (any(records, [](const FrameRecord& r) { return r.blocked; }))
    entries.push_back({"blocked", [](DrawingSurface& s, Point p) {
                         for (const Point& arm : {Point(3, 3), Point(3, -3)}) {
                           const Point ends[] = {p + Point(kSwatchWidth / 2, 0) - arm, p + Point(kSwatchWidth / 2, 0) + arm};
                           s.polyline(ends, 2, kRed);
                         }
                       }});
  if (any(expectations, [](const ExpectationResult& e) { return e.met; }))
    entries.push_back({"expectation met", discSwatch(kMetColour)});
  if (any(expectations, [](const ExpectationResult& e) { return !e.met; }))
    entries.push_back({"expectation failed", discSwatch(kRed)});
  std::set<std::string> kinds;
  for (const SceneInstance& instance : scene.instances) kinds.insert(scene.spec.equipment[instance.spec].kind);
  for (const std::string& kind : kinds) {
    const Rgb c = kindColour(kind);
    entries.push_back({kind.empty() ? "no kind" : cutText(kind, kMaxLabelChars), [c](DrawingSurface& s, Point p) {
                         const double y = std::floor(p.y());
                         s.fillRect(p.x() + 1, y - 4, p.x() + kSwatchWidth - 1, y + 5, darker(c));
                         s.fillRect(p.x() + 2, y - 3, p.x() + kSwatchWidth - 2, y + 4, c);
                       }});
  }
  return entries;
}

/// The scale bar's ticks: the bar is the longest 1-2-5 length of metres (axis.h's niceFloor) that
/// fits the column's room, its ticks those of a tight linear axis over it: 4 or 5 segments of a
/// 1-2-5 length each (1: 5 x 0.2, 2: 4 x 0.5, 5: 5 x 1).
Axis scaleBarAxis(double roomPixels, double metresPerPixel) {
  const double metres[] = {0.0, niceFloor(roomPixels * metresPerPixel)};
  return Axis::fit(metres, {.tight = true, .maxTicks = kScaleBarTicks});
}

int legendColumnWidth(const std::vector<LegendEntry>& entries) {
  double widest = 0;
  for (const LegendEntry& e : entries) widest = std::max(widest, DrawingSurface::textWidth(e.label, kMapFontSize));
  return int(std::ceil(2 * kColumnPadding + std::max(kSwatchWidth + kSwatchGap + widest, kMinScaleBar)));
}

// Column layout, top to bottom: "N" and the north arrow, the entries, the scale bar and its labels.
double textRow() {
  const DrawingSurface::FontMetrics m = DrawingSurface::fontMetrics(kMapFontSize);
  return m.ascent + m.descent;
}
double entriesTop() { return textRow() + kArrowLength + 14; }            // below the top padding
double scaleBlock() { return kScaleBarHeight + 3 + textRow(); }         // above the bottom padding

int legendColumnHeight(const std::vector<LegendEntry>& entries) {
  return int(std::ceil(2 * kColumnPadding + entriesTop() + double(entries.size()) * kRowHeight + 8 + scaleBlock()));
}

void drawNorthArrow(DrawingSurface& s, double cx, double top) {
  const TextBox n = s.text({cx, top}, "N", {.size = kMapFontSize + 2, .colour = kInk, .h = HAlign::Centre, .v = VAlign::Top});
  const double tip = n.bottom - 2;
  s.line({cx, tip - 8}, {cx, tip - kArrowLength}, 2, kInk);
  const Point head[] = {{cx, tip}, {cx - 5, tip - 11}, {cx + 5, tip - 11}};
  s.fillPolygon(head, kInk);
}

/// The scale bar: segments between the axis's ticks, alternately black and white, outlined; the
/// ticks' labels below, the last with the unit.
void drawScaleBar(DrawingSurface& s, double left, double bottom, double room, double right, double metresPerPixel) {
  const Axis axis = scaleBarAxis(room, metresPerPixel);
  const std::vector<AxisTick>& ticks = axis.ticks();
  const double barBottom = bottom + textRow() + 3, barTop = barBottom + kScaleBarHeight;
  auto xOf = [&](double metres) { return std::round(left + metres / metresPerPixel); };
  for (std::size_t i = 0; i + 1 < ticks.size(); ++i)
    s.fillRect(xOf(ticks[i].value), barBottom, xOf(ticks[i + 1].value), barTop, i % 2 ? kPaper : kInk);
  const Point outline[] = {{xOf(0) + 0.5, barBottom + 0.5}, {xOf(ticks.back().value) - 0.5, barBottom + 0.5},
                           {xOf(ticks.back().value) - 0.5, barTop - 0.5}, {xOf(0) + 0.5, barTop - 0.5}};
  s.strokePolygon(outline, 1, kInk);
  // Labels under the ticks, the last with the unit, kept inside the column: all of them when they
  // fit side by side, else the two ends only.
  const TextStyle style{.size = kMapFontSize, .colour = kInk, .h = HAlign::Centre, .v = VAlign::Top};
  std::vector<std::pair<Point, std::string>> labels;
  std::vector<TextBox> boxes;
  for (std::size_t i = 0; i < ticks.size(); ++i) {
    labels.push_back({{xOf(ticks[i].value), barBottom - 2}, ticks[i].label + (i + 1 == ticks.size() ? " m" : "")});
    TextBox b = DrawingSurface::textBox(labels.back().first, labels.back().second, style);
    const double shift = std::max(0.0, left - b.left) - std::max(0.0, b.right - right);
    labels.back().first.x() += shift;
    b.left += shift, b.right += shift;
    boxes.push_back(b);
  }
  bool all = true;
  for (std::size_t i = 1; i < boxes.size(); ++i) all = all && boxes[i].left >= boxes[i - 1].right + kLabelGap;
  for (std::size_t i = 0; i < labels.size(); ++i)
    if (all || i == 0 || i + 1 == labels.size()) s.text(labels[i].first, labels[i].second, style);
}

void drawLegendColumn(DrawingSurface& s, const TopDownFrame& frame, const std::vector<LegendEntry>& entries) {
  const double x0 = frame.width, x1 = s.width();
  s.fillRect(x0, 0, x1, s.height(), kPaper);
  s.line({x0 + 0.5, 0}, {x0 + 0.5, double(s.height())}, 1, kInk);
  const double left = x0 + kColumnPadding, top = s.height() - kColumnPadding;
  drawNorthArrow(s, std::round((x0 + x1) / 2) + 0.5, top);
  const DrawingSurface::FontMetrics m = DrawingSurface::fontMetrics(kMapFontSize);
  double rowTop = top - entriesTop();
  for (const LegendEntry& e : entries) {
    const double middle = rowTop - m.ascent + m.capHeight / 2;
    e.swatch(s, {left, middle});
    s.text({left + kSwatchWidth + kSwatchGap, middle}, e.label, {.size = kMapFontSize, .colour = kInk, .v = VAlign::Middle});
    rowTop -= kRowHeight;
  }
  drawScaleBar(s, left, kColumnPadding, x1 - x0 - 2 * kColumnPadding, x1 - kColumnPadding / 2, frame.metresPerPixel);
}

}  // namespace

Eigen::Vector2i TopDownFrame::pixelOf(const Eigen::Vector2d& map) const {
  // Clamped far outside the image so that the conversion to int stays defined.
  constexpr double kFar = 1e7;
  const Eigen::Vector2d p = toPixel(map);
  return {int(std::clamp(std::floor(p.x()), -kFar, kFar)), int(std::clamp(std::floor(p.y()), -kFar, kFar))};
}

TopDownFrame topDownFrame(const Scene& scene, const std::vector<FrameRecord>& records,
                          const std::vector<ExpectationResult>& expectations, const TopDownMapOptions& options) {
  checkInputs(scene, options, "top-down map");
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(HUGE_VAL), hi = Eigen::Vector2d::Constant(-HUGE_VAL);
  auto extend = [&](const Eigen::Vector3d& eye) {
    if (!finite2(eye)) return;
    lo = lo.cwiseMin(eye.head<2>());
    hi = hi.cwiseMax(eye.head<2>());
  };
  if (!options.wholeTerrain) {
    for (const FrameRecord& r : records) extend(r.eye);
    for (const ExpectationResult& e : expectations) extend(e.eye);
  }
  if (lo.x() <= hi.x()) {
    const double margin = std::max(0.0, options.marginMetres);
    lo -= Eigen::Vector2d::Constant(margin);
    hi += Eigen::Vector2d::Constant(margin);
    for (int axis = 0; axis < 2; ++axis)
      if (hi[axis] - lo[axis] < 1.0) {
        const double mid = 0.5 * (lo[axis] + hi[axis]);
        lo[axis] = mid - 0.5;
        hi[axis] = mid + 0.5;
      }
  } else {
    const terrain::Heightfield& hf = *scene.terrain;
    const Eigen::Vector2d northWest = hf.samplePosition(0, 0), southEast = hf.samplePosition(hf.cols() - 1, hf.rows() - 1);
    lo = {northWest.x(), southEast.y()};
    hi = {southEast.x(), northWest.y()};
  }
  const std::vector<LegendEntry> entries = legendEntries(scene, records, expectations);
  const Eigen::Vector2d size = hi - lo, centre = 0.5 * (lo + hi);
  TopDownFrame frame;
  frame.legendWidth = legendColumnWidth(entries);
  frame.metresPerPixel = std::max(size.x() / (options.maxSize - frame.legendWidth), size.y() / options.maxSize);
  frame.width = std::max(1, int(std::ceil(size.x() / frame.metresPerPixel - 1e-9)));
  frame.height = std::max(legendColumnHeight(entries), int(std::ceil(size.y() / frame.metresPerPixel - 1e-9)));
  frame.west = centre.x() - 0.5 * frame.width * frame.metresPerPixel;
  frame.south = centre.y() - 0.5 * frame.height * frame.metresPerPixel;
  return frame;
}

void writeTopDownMap(const std::string& path, const Scene& scene, const std::vector<FrameRecord>& records,
                     const std::vector<ExpectationResult>& expectations, const TopDownMapOptions& options) {
  checkInputs(scene, options, path);
  const TopDownFrame frame = topDownFrame(scene, records, expectations, options);
  DrawingSurface surface(frame.width + frame.legendWidth, frame.height, kOutsideTerrain);
  drawTerrain(surface, frame, scene);
  for (const SceneInstance& instance : scene.instances)
    drawFootprint(surface, footprint(instance.volume.inner, scene, frame),
                  kindColour(scene.spec.equipment[instance.spec].kind));
  drawBlockingUnits(surface, frame, scene, records);
  drawPath(surface, frame, records);
  drawStartAndEnd(surface, frame, records);
  drawExpectations(surface, frame, expectations);
  drawBlockedFrames(surface, frame, records);
  drawLegendColumn(surface, frame, legendEntries(scene, records, expectations));
  surface.writePng(path);
}

}  // namespace nestwalk
