// The methods report (`nestwalk report`, issue 3): every contact method of the walker run over a
// scene's flythroughs and measured against the exact reference, the ground following's terrain
// levels of detail against the full-resolution surface, and the OBB fitters against CGAL's optimal
// box; written as a Markdown report with PNG plots and the numbers as JSON.
//
// Methods (scene_file.h VolumeMethod): nested, aabb, obb, nested+mesh, kdop18, each with the
// scene's hierarchy and fitter. Per method and flythrough, two plays of the script:
//  - timing: the walker's own µs per step (ground, broad, narrow; StepPart::Total per frame), the
//    plays repeated and interleaved across methods, each frame's time the least over the repeats
//    (the plays are deterministic, so frame i is the same step every time; the least is the one
//    least disturbed by the rest of the machine);
//  - accuracy: every sweep also run on an exact nested+mesh world (CollisionWorld::compareWith):
//    missed contacts (the real geometry was touched before the method's contact, or the method
//    found none) and false blocks (the method stopped a sweep whose path touches no triangle);
//    the BV tests (hierarchy nodes, the three nested stages, the mesh trees' nodes) and triangle
//    tests per frame; and, after every step blocked by equipment, the stop gap: the exact distance
//    from the body box to the nearest unit's triangles (MeshWorld::distance).
// Terrain (terrain_lod_report.cpp): the scene's terrain cut into TerrainMesh tiles of 128 cells
// (as the renderer does); random map points, per level the height of the level's surface against
// Heightfield::groundHeight (the full-resolution surface), and ns per query.
// Fitters (fitter_report.cpp, the one file compiled with CGAL): per model of the scene, the
// volume of the covariance and hull-search boxes fitted to all of the model's vertices, against
// the volume of CGAL's optimal oriented bounding box, and the fitting time (hull included).
#pragma once

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <iosfwd>
#include <limits>
#include <string>
#include <vector>

namespace nestwalk {
struct Scene;
namespace terrain {
class Heightfield;
}
}  // namespace nestwalk

namespace nestwalk::bench {

struct MethodReportOptions {
  std::string scene;                 // scene file
  std::vector<std::string> scripts;  // its flythroughs
  std::string out;                   // folder for the report's files (created when absent)
  bool quick = false;                // one timing play, fewer terrain points and fitter repetitions
  bool overwrite = false;            // replace the report's files when they exist
};

/// The files the report writes into its folder.
inline const std::vector<std::string>& reportFiles() {
  static const std::vector<std::string> files = {"report.md", "report.json", "pareto.png", "methods.png",
                                                 "terrain_lod.png"};
  return files;
}

/// Runs everything, writes the files and prints a short summary (the method table, the targets,
/// the files) to `log`. Throws InputError for bad input, and (naming the file) when a report file
/// exists and `overwrite` is off. Returns 0: the targets are reported (met / NOT met), not enforced.
int runMethodReport(const MethodReportOptions& options, std::ostream& log);

/// The least wall-clock time, in seconds, of `repetitions` calls of `run` (at least one call).
template <class Run>
double leastSeconds(int repetitions, const Run& run) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < std::max(repetitions, 1); ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    run();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}

/// One row of the terrain table: a level of the terrain mesh (or the heightfield itself).
struct TerrainLodRow {
  std::string name;           // "full" (Heightfield::groundHeight) or "L0", "L1", ...
  int level = -1;             // -1 for the heightfield
  int step = 1;               // samples per coarse cell side (2^level)
  std::size_t tiles = 0;      // tiles that have the level
  double tableMaxError = 0;   // TerrainMesh::levelTable()'s exact maximum error, metres
  std::size_t points = 0;     // sample points where both surfaces exist
  double maxError = 0, meanError = 0;  // measured |level - full resolution|, metres
  double nsPerQuery = 0;      // the least over the timing repetitions
};

/// Ground following per level of detail: `points` uniform random map points over the terrain's
/// sample extent (fixed seed), each query loop timed `repetitions` times.
std::vector<TerrainLodRow> measureTerrainLod(const terrain::Heightfield& hf, std::size_t points, int repetitions);

/// One row of the fitter table: a model of the scene.
struct FitterRow {
  std::string model;              // the file name
  std::size_t triangles = 0, vertices = 0, hullPoints = 0;
  double covarianceVolume = 0, hullSearchVolume = 0, optimalVolume = 0;  // m^3 (model units cubed)
  double covarianceMicros = 0, hullSearchMicros = 0, optimalMicros = 0;  // per fit, least over repetitions
};

/// The fitters on every model of a loaded scene (all of its vertices, as loadModelGeometry reads
/// them), each fit repeated `repetitions` times; CGAL with a fixed seed.
std::vector<FitterRow> measureFitters(const Scene& scene, int repetitions);

}  // namespace nestwalk::bench
