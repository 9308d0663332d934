// The methods report (`nestwalk report`): every contact method of the walker run over a
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
//  - accuracy: every sweep also run on an exact nested+mesh world (reference_comparison.h, set on
//    the method's world for the play by ObservedSweeps):
//    missed contacts (the real geometry was touched before the method's contact, or the method
//    found none) and false blocks (the method stopped a sweep whose path touches no triangle);
//    the BV tests (hierarchy nodes, the three nested stages, the mesh trees' nodes) and triangle
//    tests per frame; and, after every step blocked by equipment, the stop gap: the exact distance
//    from the body box to the nearest unit's triangles (MeshWorld::distance).
// Terrain (terrain_lod_table.h): the scene's terrain as the renderer's chunk quadtree (chunks of
// 64 cells); random map points, per level the height of the level's grid surface against
// Heightfield::groundHeight (the full-resolution surface), and ns per query.
// Fitters (fitter_table.h, the one file compiled with CGAL): per model of the scene, the
// volume of the covariance and hull-search boxes fitted to all of the model's vertices, against
// the volume of CGAL's optimal oriented bounding box, and the fitting time (hull included).
//
// Thread safety: run it on one thread with nothing else running: it loads the scene (model reads
// fork, core/guarded_process.h), and its timings assume an otherwise idle process. `log` is the
// caller's stream.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace nestwalk {

struct MethodReportOptions {
  std::string scene;                 // scene file
  std::vector<std::string> scripts;  // its flythroughs
  std::string out;                   // folder for the report's files (created when absent)
  bool quick = false;                // one timing play, fewer terrain points and fitter repetitions
  bool overwrite = false;            // replace the report's files when they exist
};

/// The files the report writes into its folder.
inline const std::vector<std::string>& reportFiles() {
  static const std::vector<std::string> files = {"report.md",   "report.json",     "pareto.png",      "methods.png",
                                                 "terrain_lod.png", "model_weight.png", "contacts.gpkg"};
  return files;
}

/// Runs everything, writes the files and prints a short summary (the method table, the targets,
/// the files) to `log`. Throws InputError for bad input, and (naming the file) when a report file
/// exists and `overwrite` is off. Returns 0: the targets are reported (met / NOT met), not enforced.
int runMethodReport(const MethodReportOptions& options, std::ostream& log);

}  // namespace nestwalk
