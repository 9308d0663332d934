// The top-down map of a walker run: the terrain's hillshade, equipment footprints, the path, blocked
// frames, expectations and a legend column drawn on a Canvas and written as PNG. What is drawn, and
// in which colours, is documented in top_down_map.h. Map coordinates are UTM-sized, so every
// position goes through TopDownFrame (a difference from the image's corner, in double) before it
// becomes a pixel.
#include "nestwalk/report/top_down_map.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/report/canvas.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
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
constexpr int kPathRadius = 1;           // the path's brush: 3 pixels wide
constexpr int kCrossArm = 4;             // blocked cross: arms of 4, brush radius 1 -> 11 across
constexpr double kMarkerRadius = 5;      // start and end discs
constexpr double kExpectationRadius = 6;
constexpr double kTinyFootprint = 4;     // footprints narrower than this become discs
// The legend column.
constexpr int kColumnPadding = 8;
constexpr int kRowHeight = 12, kSwatchWidth = 14;
constexpr int kArrowLength = 28;
constexpr int kMinScaleBar = 60;         // the column leaves at least this much room for the scale bar
constexpr std::size_t kMaxLabelChars = 20;  // kinds' labels are cut to this

Eigen::Vector3d sunDirection() {
  const double az = kSunAzimuthDeg * std::numbers::pi / 180, alt = kSunAltitudeDeg * std::numbers::pi / 180;
  return {std::cos(alt) * std::sin(az), std::cos(alt) * std::cos(az), std::sin(alt)};
}

std::string upper(std::string s) {
  for (char& c : s) c = char(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

Rgb darker(Rgb c) { return {std::uint8_t(c.r / 2), std::uint8_t(c.g / 2), std::uint8_t(c.b / 2)}; }

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

/// Horn's hillshade at a valid sample: max(0, n . sun), n from the 3 x 3 weighted differences.
double hornShade(const terrain::Heightfield& hf, int col, int row, const Eigen::Vector3d& sun) {
  const double centre = hf.sample(col, row);
  auto usable = [&](int c, int r) { return c >= 0 && r >= 0 && c < hf.cols() && r < hf.rows() && hf.valid(c, r); };
  // Neighbour (col + dc, row + dr); a missing one extrapolated through the centre.
  auto z = [&](int dc, int dr) -> double {
    if (usable(col + dc, row + dr)) return hf.sample(col + dc, row + dr);
    if (usable(col - dc, row - dr)) return 2 * centre - hf.sample(col - dc, row - dr);
    return centre;
  };
  // Rows run south: dr = -1 is the northern neighbour.
  const double dzdx = ((z(1, -1) + 2 * z(1, 0) + z(1, 1)) - (z(-1, -1) + 2 * z(-1, 0) + z(-1, 1))) / (8 * hf.dx());
  const double dzdy = ((z(-1, -1) + 2 * z(0, -1) + z(1, -1)) - (z(-1, 1) + 2 * z(0, 1) + z(1, 1))) / (8 * hf.dy());
  return std::max(0.0, Eigen::Vector3d(-dzdx, -dzdy, 1).normalized().dot(sun));
}

/// Per-sample shades over a window of the grid (NaN at holes).
class ShadeWindow {
 public:
  ShadeWindow(const terrain::Heightfield& hf, int firstCol, int lastCol, int firstRow, int lastRow)
      : firstCol_(firstCol), firstRow_(firstRow), cols_(lastCol - firstCol + 1),
        shade_(std::size_t(cols_) * std::size_t(lastRow - firstRow + 1), std::numeric_limits<float>::quiet_NaN()) {
    const Eigen::Vector3d sun = sunDirection();
    for (int r = firstRow; r <= lastRow; ++r)
      for (int c = firstCol; c <= lastCol; ++c)
        if (hf.valid(c, r)) shade_[index(c, r)] = float(hornShade(hf, c, r, sun));
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

void drawTerrain(Canvas& canvas, const TopDownFrame& frame, const terrain::Heightfield& hf) {
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

  const auto range = hf.heightRange();
  const double lowest = range ? range->first : 0, highest = range ? range->second : 0;
  for (int j = 0; j < frame.height; ++j)
    for (int i = 0; i < frame.width; ++i) {
      const Eigen::Vector2d p = frame.pixelCentre(i, j);
      const double u = gridU(p.x()), v = gridV(p.y());
      if (!(u >= 0 && v >= 0 && u <= lastU && v <= lastV)) {
        canvas.set(i, j, kOutsideTerrain);
        continue;
      }
      const std::optional<double> ground = hf.groundHeight(p.x(), p.y());
      const std::optional<double> shade = ground ? shadeAt(shades, hf, u, v) : std::nullopt;
      if (!shade) {
        canvas.set(i, j, kHoleGrey);
        continue;
      }
      const double fraction = highest > lowest ? std::clamp((*ground - lowest) / (highest - lowest), 0.0, 1.0) : 0.5;
      canvas.set(i, j, terrainColour(fraction, *shade));
    }
}

// ---- footprints ----------------------------------------------------------------------------------

double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
}

/// Andrew's monotone chain: the convex hull, counter-clockwise, without collinear points.
std::vector<Eigen::Vector2d> convexHull2d(std::vector<Eigen::Vector2d> points) {
  std::sort(points.begin(), points.end(),
            [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
  if (points.size() < 3) return points;
  std::vector<Eigen::Vector2d> hull(2 * points.size());
  std::size_t k = 0;
  for (const Eigen::Vector2d& p : points) {  // lower chain
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p) <= 0) --k;
    hull[k++] = p;
  }
  for (std::size_t i = points.size() - 1, lowerSize = k + 1; i-- > 0;) {  // upper chain
    while (k >= lowerSize && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k > 1 ? k - 1 : k);  // the last point repeats the first
  return hull;
}

/// The x-y footprint of a local-frame OBB in continuous pixel coordinates.
std::vector<Eigen::Vector2d> footprint(const Obb<double>& box, const Scene& scene, const TopDownFrame& frame) {
  std::vector<Eigen::Vector2d> corners;
  for (int i = 0; i < 8; ++i) {
    const Vec3<double> p = box.corner(i);
    corners.push_back(frame.toPixel({p.x() + scene.origin.x(), p.y() + scene.origin.y()}));
  }
  return convexHull2d(std::move(corners));
}

struct PixelBox {
  Eigen::Vector2d min, max;
  Eigen::Vector2i centre() const {
    const Eigen::Vector2d c = 0.5 * (min + max);
    return {int(std::floor(c.x())), int(std::floor(c.y()))};
  }
  bool tiny() const { return (max - min).maxCoeff() < kTinyFootprint; }
  bool meets(const Canvas& canvas) const {
    return max.x() >= 0 && max.y() >= 0 && min.x() <= canvas.width() && min.y() <= canvas.height();
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

Eigen::Vector2i pixelIndex(const Eigen::Vector2d& p) { return {int(std::floor(p.x())), int(std::floor(p.y()))}; }

void outlinePolygon(Canvas& canvas, const std::vector<Eigen::Vector2d>& polygon, int radius, Rgb c) {
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2i a = pixelIndex(polygon[i]), b = pixelIndex(polygon[(i + 1) % polygon.size()]);
    canvas.thickLine(a.x(), a.y(), b.x(), b.y(), radius, c);
  }
}

void drawFootprint(Canvas& canvas, const std::vector<Eigen::Vector2d>& polygon, Rgb fill) {
  const PixelBox box = boundsOf(polygon);
  if (!box.meets(canvas)) return;
  if (box.tiny()) {
    canvas.disc(box.centre().x(), box.centre().y(), 2, fill);
    canvas.ring(box.centre().x(), box.centre().y(), 3, darker(fill));
    return;
  }
  canvas.fillPolygon(polygon, fill);
  outlinePolygon(canvas, polygon, 0, darker(fill));
}

void drawBlockerOutline(Canvas& canvas, const std::vector<Eigen::Vector2d>& polygon) {
  const PixelBox box = boundsOf(polygon);
  if (!box.meets(canvas)) return;
  if (box.tiny()) {
    for (double r : {4.0, 5.0}) canvas.ring(box.centre().x(), box.centre().y(), r, kRed);
    return;
  }
  outlinePolygon(canvas, polygon, 1, kRed);
}

// ---- run marks -----------------------------------------------------------------------------------

void drawCross(Canvas& canvas, Eigen::Vector2i p, Rgb c) {
  canvas.thickLine(p.x() - kCrossArm, p.y() - kCrossArm, p.x() + kCrossArm, p.y() + kCrossArm, 1, c);
  canvas.thickLine(p.x() - kCrossArm, p.y() + kCrossArm, p.x() + kCrossArm, p.y() - kCrossArm, 1, c);
}

void drawMarker(Canvas& canvas, Eigen::Vector2i p, double radius, Rgb fill, Rgb rim) {
  canvas.disc(p.x(), p.y(), radius, fill);
  canvas.ring(p.x(), p.y(), radius + 1, rim);
}

/// Text in `ink` with a one-pixel `halo` around it, readable on any background.
void haloText(Canvas& canvas, int x, int top, const std::string& s, Rgb ink, Rgb halo) {
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (dx || dy) canvas.text(x + dx, top + dy, s, halo);
  canvas.text(x, top, s, ink);
}

void drawPath(Canvas& canvas, const TopDownFrame& frame, const std::vector<FrameRecord>& records) {
  std::optional<Eigen::Vector2i> previous;
  for (const FrameRecord& r : records) {
    if (!finite2(r.eye)) {
      previous.reset();
      continue;
    }
    const Eigen::Vector2i p = frame.pixelOf(r.eye.head<2>());
    const Eigen::Vector2i from = previous.value_or(p);
    canvas.thickLine(from.x(), from.y(), p.x(), p.y(), kPathRadius, r.flying ? kFlyColour : kWalkColour);
    previous = p;
  }
}

/// The footprints of the collision units that blocked the run, outlined in red.
void drawBlockingUnits(Canvas& canvas, const TopDownFrame& frame, const Scene& scene,
                       const std::vector<FrameRecord>& records) {
  std::set<std::string> blockers;
  for (const FrameRecord& r : records)
    if (r.blocked) blockers.insert(r.blockedBy);
  for (const std::string& name : blockers) {
    const int unit = scene.findUnit(name);
    if (unit >= 0) drawBlockerOutline(canvas, footprint(scene.units[std::size_t(unit)].volume.inner, scene, frame));
  }
}

void drawBlockedFrames(Canvas& canvas, const TopDownFrame& frame, const std::vector<FrameRecord>& records) {
  for (const FrameRecord& r : records)
    if (r.blocked && finite2(r.eye)) drawCross(canvas, frame.pixelOf(r.eye.head<2>()), kRed);
}

void drawStartAndEnd(Canvas& canvas, const TopDownFrame& frame, const std::vector<FrameRecord>& records) {
  std::vector<const FrameRecord*> drawn;
  for (const FrameRecord& r : records)
    if (finite2(r.eye)) drawn.push_back(&r);
  if (drawn.empty()) return;
  const Eigen::Vector2i start = frame.pixelOf(drawn.front()->eye.head<2>());
  const Eigen::Vector2i end = frame.pixelOf(drawn.back()->eye.head<2>());
  drawMarker(canvas, end, kMarkerRadius, kInk, kPaper);
  drawMarker(canvas, start, kMarkerRadius, kPaper, kInk);
  const int labelOffset = int(kMarkerRadius) + 4;
  haloText(canvas, end.x() + labelOffset, end.y() - labelOffset, "END", kInk, kPaper);
  haloText(canvas, start.x() + labelOffset, start.y() + labelOffset + kGlyphHeight, "START", kInk, kPaper);
}

void drawExpectations(Canvas& canvas, const TopDownFrame& frame, const std::vector<ExpectationResult>& expectations) {
  for (const ExpectationResult& e : expectations)
    if (finite2(e.eye)) drawMarker(canvas, frame.pixelOf(e.eye.head<2>()), kExpectationRadius, e.met ? kMetColour : kRed, kInk);
}

// ---- the legend column ---------------------------------------------------------------------------

struct LegendEntry {
  std::string label;
  std::function<void(Canvas&, int x, int y)> swatch;  // draws in [x, x + kSwatchWidth - 1] x [y - 4, y + 4]
};

/// The marks the run put on the map, then the scene's equipment kinds (sorted).
std::vector<LegendEntry> legendEntries(const Scene& scene, const std::vector<FrameRecord>& records,
                                       const std::vector<ExpectationResult>& expectations) {
  auto any = [](const auto& list, auto predicate) { return std::any_of(list.begin(), list.end(), predicate); };
  auto pathSwatch = [](Rgb c) {
    return [c](Canvas& canvas, int x, int y) { canvas.thickLine(x, y, x + kSwatchWidth - 1, y, kPathRadius, c); };
  };
  auto discSwatch = [](Rgb c) {
    return [c](Canvas& canvas, int x, int y) {
      canvas.disc(x + kSwatchWidth / 2, y, 3.5, c);
      canvas.ring(x + kSwatchWidth / 2, y, 4.5, kInk);
    };
  };
  std::vector<LegendEntry> entries;
  if (any(records, [](const FrameRecord& r) { return !r.flying; })) entries.push_back({"WALK", pathSwatch(kWalkColour)});
  if (any(records, [](const FrameRecord& r) { return r.flying; })) entries.push_back({"FLY", pathSwatch(kFlyColour)});
  if (any(records, [](const FrameRecord& r) { return r.blocked; }))
    entries.push_back({"BLOCKED", [](Canvas& canvas, int x, int y) {
                         const int cx = x + kSwatchWidth / 2;
                         canvas.line(cx - 3, y - 3, cx + 3, y + 3, kRed);
                         canvas.line(cx - 3, y + 3, cx + 3, y - 3, kRed);
                       }});
  if (any(expectations, [](const ExpectationResult& e) { return e.met; }))
    entries.push_back({"EXPECTATION MET", discSwatch(kMetColour)});
  if (any(expectations, [](const ExpectationResult& e) { return !e.met; }))
    entries.push_back({"EXPECTATION FAILED", discSwatch(kRed)});
  std::set<std::string> kinds;
  for (const SceneInstance& instance : scene.instances) kinds.insert(scene.spec.equipment[instance.spec].kind);
  for (const std::string& kind : kinds) {
    const Rgb c = kindColour(kind);
    entries.push_back({kind.empty() ? "NO KIND" : upper(kind.substr(0, kMaxLabelChars)),
                       [c](Canvas& canvas, int x, int y) {
                         canvas.fill(x + 1, y - 3, x + kSwatchWidth - 2, y + 3, darker(c));
                         canvas.fill(x + 2, y - 2, x + kSwatchWidth - 3, y + 2, c);
                       }});
  }
  return entries;
}

int legendColumnWidth(const std::vector<LegendEntry>& entries) {
  int widest = 0;
  for (const LegendEntry& e : entries) widest = std::max(widest, textWidth(e.label));
  return 2 * kColumnPadding + std::max(kSwatchWidth + kGlyphAdvance + widest, kMinScaleBar);
}

// Column layout, top to bottom: "N" and the north arrow, the entries, the scale bar and its label.
constexpr int kArrowTop = kGlyphHeight + 3;  // below the column's top padding
constexpr int kEntriesTop = kArrowTop + kArrowLength + 12;
constexpr int kScaleBarHeight = 5;
constexpr int kScaleBlock = kScaleBarHeight + 3 + kGlyphHeight;  // above the bottom padding

int legendColumnHeight(const std::vector<LegendEntry>& entries) {
  return 2 * kColumnPadding + kEntriesTop + int(entries.size()) * kRowHeight + 8 + kScaleBlock;
}

/// The longest 1-2-5 length (metres) not above `limit`.
double niceLength(double limit) {
  const double decade = std::pow(10.0, std::floor(std::log10(limit)));
  for (double m : {5.0, 2.0, 1.0})
    if (m * decade <= limit) return m * decade;
  return decade;
}

std::string metresLabel(double metres) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, metres, std::chars_format::fixed);
  return std::string(buffer, result.ptr) + " M";
}

void drawNorthArrow(Canvas& canvas, int cx, int top) {
  canvas.text(cx - kGlyphWidth / 2, top, "N", kInk);
  const int tip = top - kArrowTop;
  canvas.line(cx, tip - kArrowLength, cx, tip - 8, kInk);
  canvas.fillPolygon({{cx + 0.5, tip + 1.0}, {cx - 4.5, tip - 10.0}, {cx + 5.5, tip - 10.0}}, kInk);
}

/// A bar of alternating black and white quarters standing for a 1-2-5 length, its label below.
void drawScaleBar(Canvas& canvas, int x, int bottom, int room, double metresPerPixel) {
  const double metres = niceLength(room * metresPerPixel);
  const int length = std::max(4, int(std::lround(metres / metresPerPixel)));
  const int barBottom = bottom + kGlyphHeight + 3, barTop = barBottom + kScaleBarHeight - 1;
  for (int quarter = 0; quarter < 4; ++quarter)
    canvas.fill(x + quarter * length / 4, barBottom, x + (quarter + 1) * length / 4, barTop,
                quarter % 2 ? kPaper : kInk);
  canvas.line(x, barBottom, x + length, barBottom, kInk);
  canvas.line(x, barTop, x + length, barTop, kInk);
  canvas.line(x + length, barBottom, x + length, barTop, kInk);
  canvas.text(x, bottom + kGlyphHeight - 1, metresLabel(metres), kInk);
}

void drawLegendColumn(Canvas& canvas, const TopDownFrame& frame, const std::vector<LegendEntry>& entries) {
  const int x0 = frame.width, x1 = canvas.width() - 1;
  canvas.fill(x0, 0, x1, canvas.height() - 1, kPaper);
  canvas.line(x0, 0, x0, canvas.height() - 1, kInk);
  const int left = x0 + kColumnPadding, top = canvas.height() - 1 - kColumnPadding;
  drawNorthArrow(canvas, (x0 + x1) / 2, top);
  int rowTop = top - kEntriesTop;
  for (const LegendEntry& e : entries) {
    e.swatch(canvas, left, rowTop - kGlyphHeight / 2);
    canvas.text(left + kSwatchWidth + kGlyphAdvance, rowTop, e.label, kInk);
    rowTop -= kRowHeight;
  }
  drawScaleBar(canvas, left, kColumnPadding, x1 - x0 - 2 * kColumnPadding, frame.metresPerPixel);
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
  Canvas canvas(frame.width + frame.legendWidth, frame.height, kOutsideTerrain);
  drawTerrain(canvas, frame, *scene.terrain);
  for (const SceneInstance& instance : scene.instances)
    drawFootprint(canvas, footprint(instance.volume.inner, scene, frame),
                  kindColour(scene.spec.equipment[instance.spec].kind));
  drawBlockingUnits(canvas, frame, scene, records);
  drawPath(canvas, frame, records);
  drawStartAndEnd(canvas, frame, records);
  drawExpectations(canvas, frame, expectations);
  drawBlockedFrames(canvas, frame, records);
  drawLegendColumn(canvas, frame, legendEntries(scene, records, expectations));
  writePng(canvas, path);
}

}  // namespace nestwalk
