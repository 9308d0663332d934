// The top-down map of a walker run (PNG): the terrain's hillshade tinted by height, the equipment's
// footprints coloured by kind, the run's path (walking and flying), where the walker was blocked
// (and the footprint of what blocked it), where the script's expectations were checked, start and
// end markers; beside the map a column with a north arrow, a legend and a scale bar. Written
// after a run beside frames.csv.
//
// Image frame: north up, a pixel covers the same metres east and north. Pixel rows are y-up as in
// osg::Image (row 0 is the south edge; osgDB's png plugin flips rows on writing and reading, so an
// image read back through osgDB has the same rows); TopDownFrame maps map x, y to pixels. The map
// fills the image's left TopDownFrame::width columns, the legend column the rest.
//
// Drawn with cairo (drawing_surface.h): marks are antialiased, placed at the exact (continuous)
// pixel position of their map point, and have exactly their colour where they cover a pixel
// entirely (the pixel holding a path's eye, a cross's centre, a marker's centre always). Text is
// the UI font (DejaVu Sans, core/ui_font.h), 12 pixels per em.
//
// What is drawn, bottom to top (colours RGB):
//  - terrain: colour = tint × (0.35 + 0.65 × shade) per channel, rounded. tint runs linearly from
//    (96, 140, 96) at the terrain's lowest valid sample to (236, 214, 170) at its highest
//    (Heightfield::heightRange(); the middle of the ramp when they are equal), by the ground height
//    at the pixel's centre (Heightfield::groundHeight). shade = max(0, n · sun): the sun in the
//    north-west (azimuth 315°, clockwise from north) 45° up, n the unit normal from Horn's 3 x 3
//    weighted differences of the sample grid at each sample (a missing neighbour, a hole or beyond
//    the grid, is extrapolated linearly through the centre sample from the opposite one, or taken
//    as the centre's height when that is missing too, so a plane shades exactly except at the
//    grid's corners, where one diagonal pair is missing), interpolated bilinearly to the pixel's centre from the valid samples of its cell (hillshade.h; the rule of
//    GDAL's `gdaldem hillshade`, tested against it). A pixel whose centre has no ground (a hole) is
//    flat grey (128, 128, 128); beyond the outermost samples white.
//    Samples: the terrain's own, or, when the scene has the terrain's pyramid (Scene::terrainPyramid)
//    and a pixel spans two cells or more, the coarsest pyramid level whose samples are at most a pixel
//    apart (every 2^L-th sample, as the DEM stores it), read over the map's window only: a map of a
//    survey-size terrain reads about as many samples as it has pixels. A pixel centre within less
//    than a pixel of the terrain's east or south edge (past the level's last regular sample) takes
//    the nearest point inside.
//  - equipment: each instance's footprint, the x-y outline of its inner OBB (the convex hull of
//    the 8 corners' x, y), filled in its kind's colour and outlined (1 pixel) in half that colour;
//    a footprint under 4 pixels across is drawn as a disc of radius 2 with a circle of radius 3 in
//    that outline colour around it.
//    Kinds (EquipmentSpec::kind, the bundled generator's labels): pole (255, 215, 0), station
//    (0, 150, 150), solar (30, 40, 130), logger (245, 240, 200), piezometer (255, 140, 0),
//    container (150, 65, 25), barrier (205, 205, 205), vehicle (40, 40, 40); any other kind one
//    of (230, 120, 180), (120, 170, 255), (180, 100, 255), (255, 175, 120), (0, 110, 80),
//    (150, 150, 60) chosen by the kind's FNV-1a hash; no kind magenta (255, 0, 255).
//  - units that blocked the run (FrameRecord::blockedBy naming a collision unit): the footprint of
//    the unit's inner OBB outlined in red (230, 0, 0), 3 pixels wide (a tiny one: a red circle of
//    radius 4.5, 2 pixels wide).
//  - the path: a line through the records' eyes, 3 pixels wide with round joins, blue
//    (40, 90, 255) where walking, cyan (0, 215, 255) where flying (the segment into a record takes
//    that record's mode).
//  - start and end: a white disc (radius 5, black rim 1.5 pixels wide) at the first eye labelled
//    "start", a black disc (white rim) at the last labelled "end"; the labels with a white halo.
//  - expectations: a disc of radius 6 at the eye where each was checked, green (0, 190, 0) met or
//    red (230, 0, 0) failed, with a black rim.
//  - blocked frames: a red (230, 0, 0) cross at each blocked record's eye, its arms reaching 4
//    pixels along x and y from it, 3 pixels wide (on top, so that an expectation checked where the
//    walker was blocked shows both).
//  - the legend column (white, right of the map, a black line between them): "N" and a north arrow
//    at the top, then the marks the run drew ("walk", "fly", "blocked", "expectation met",
//    "expectation failed") and the scene's equipment kinds as written (sorted, cut to 20 bytes at
//    a character), then a scale bar at the bottom: the longest 1-2-5 length of metres that fits
//    the column, in 4 or 5 black and white segments at the ticks of axis.h's rule, labelled "0" and
//    "<length> m" (and at every tick when the labels fit).
//
// Thread safety: keeps no state; the scene and the records are only read (one writer per path at a
// time, core/output_file.h).
#pragma once

#include "nestwalk/walker/frame_record.h"
#include "nestwalk/scene/scene.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace nestwalk {

struct TopDownMapOptions {
  int maxSize = 1600;          // longest image side (map and legend column), pixels; at least
                               // kMinTopDownMapSize
  double marginMetres = 40;    // around the path's and blocked points' extent
  bool wholeTerrain = false;   // true: the whole terrain instead of the run's surroundings
};

inline constexpr int kMinTopDownMapSize = 320;

/// Map x, y <-> image pixels. Pixel (i, j) covers map x in [west + i m, west + (i + 1) m) and map
/// y in [south + j m, south + (j + 1) m), m = metresPerPixel; j counts rows up from the south edge.
/// The map is width x height pixels; the image is legendWidth columns wider.
struct TopDownFrame {
  double west = 0, south = 0;  // map x, y of the image's south-west corner
  double metresPerPixel = 1;
  int width = 0, height = 0;   // the map's part of the image
  int legendWidth = 0;         // the legend column right of the map

  /// Continuous pixel coordinates of a map point (pixel (i, j)'s centre is (i + 0.5, j + 0.5)).
  Eigen::Vector2d toPixel(const Eigen::Vector2d& map) const {
    return {(map.x() - west) / metresPerPixel, (map.y() - south) / metresPerPixel};
  }
  /// The pixel holding a map point (it may lie outside the image).
  Eigen::Vector2i pixelOf(const Eigen::Vector2d& map) const;
  /// Map x, y of pixel (i, j)'s centre.
  Eigen::Vector2d pixelCentre(int i, int j) const {
    return {west + (i + 0.5) * metresPerPixel, south + (j + 0.5) * metresPerPixel};
  }
  bool inside(const Eigen::Vector2i& pixel) const {
    return pixel.x() >= 0 && pixel.y() >= 0 && pixel.x() < width && pixel.y() < height;
  }
};

/// The frame writeTopDownMap draws in. The area: the box around every record's eye and every
/// expectation's eye (non-finite ones skipped), grown by marginMetres on every side and to at least
/// 1 m on each axis; with wholeTerrain, or when there is no eye, the terrain's sample extent (the
/// outermost sample centres). legendWidth follows from the legend's entries; metresPerPixel is the
/// smallest that fits the area into (maxSize - legendWidth) x maxSize pixels; width and height are
/// ceil(area side / metresPerPixel), the height raised where the legend column needs more rows;
/// the area is centred in the map. Throws InputError when the scene has no terrain or maxSize <
/// kMinTopDownMapSize.
TopDownFrame topDownFrame(const Scene& scene, const std::vector<FrameRecord>& records,
                          const std::vector<ExpectationResult>& expectations, const TopDownMapOptions& options = {});

/// Draws the map described above over topDownFrame(scene, records, expectations, options) and writes
/// it as PNG to a temporary name beside `path`, renamed when complete (output_file.h). Throws
/// InputError naming `path` when the scene has no terrain, maxSize is too small or the file cannot
/// be written.
void writeTopDownMap(const std::string& path, const Scene& scene, const std::vector<FrameRecord>& records,
                     const std::vector<ExpectationResult>& expectations, const TopDownMapOptions& options = {});

}  // namespace nestwalk
