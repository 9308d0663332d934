// A recorded run published as a static web page (`nestwalk publish RUN_DIR --out SITE`): a folder
// anyone can open with any static file server (or from file:// where the browser allows a page to
// read the files beside it), holding
//   index.html, walkthrough.js  the page and its script (three.js bundled in at build time:
//                               tools/web; found in WalkthroughSiteOptions::pageFolder);
//   scene.glb                   the run's scene as glTF (render/scene_gltf.h: the terrain's cut at
//                               maxErrorM with its imagery, the equipment instanced with
//                               EXT_mesh_gpu_instancing, which three.js draws in one call per
//                               model mesh), without volumes;
//   run.json                    what the page plays (below);
//   *.png                       the run's figures (top-down map, frame times) and, with a report
//                               folder, the report's (speed against error, ...).
// run.json: {"title", "summary", "fov_y_deg", "near_m", "far_m", "haze_m": [start, end],
//   "sky_horizon_rgb" (the renderer's camera and haze, render/view_depth.h), "scene": "scene.glb",
//   "map_origin": [x, y, z],
//   "crs_name", "frames": {"t", "x", "y", "z", "heading", "pitch", "blocked"} (arrays, one entry
//   per frames.csv row; positions in the local frame: map minus map_origin, metres),
//   "contacts": [{"unit", "kind", "time_s", "frame", "stop_gap_m", "approach_deg", "x", "y", "z"}]
//   (results.geojson's contacts, placed at their frame's eye), "expectations": [{"text", "met"}],
//   "figures": [{"file", "title"}]}.
// Inputs: the run's summary.json (its "scene", unless the options name one, and "expectations"),
// frames.csv and results.geojson, as `nestwalk run` writes them; none is changed.
// Thread safety: one call at a time (the scene's glTF is written with OSG's plugins).
#pragma once

#include "nestwalk/render/gltf_scene_writer.h"

#include <cstddef>
#include <string>

namespace nestwalk {

struct WalkthroughSiteOptions {
  std::string runFolder;     // a run's folder (`nestwalk run --out`)
  std::string sceneFile;     // "" : the scene summary.json names (as written, else beside the run folder)
  std::string reportFolder;  // "" : no report figures; else a `nestwalk report --out` folder
  std::string pageFolder;    // the page's files (index.html, walkthrough.js)
  double maxErrorM = 0.8;    // the terrain cut's error: one pixel of a 1280 x 720 view from 500 m
  double fovYDegrees = 60;   // the page's camera, as the offscreen renderer's (RenderOptions)
};

struct WalkthroughSite {
  std::string sceneFile;  // the scene published
  std::size_t frames = 0, contacts = 0, expectations = 0, figures = 0;
  GltfWriteStats gltf;
};

/// Writes the site into `folder` (an existing, empty folder: the caller's temporary one). Throws
/// InputError naming the file and what is wrong: a run folder without summary.json or frames.csv
/// ("is not a run's folder: summary.json missing"), a scene that cannot be found or loaded, a
/// page folder without its files, a figure or frame that cannot be read.
WalkthroughSite writeWalkthroughSite(const WalkthroughSiteOptions& options, const std::string& folder);

}  // namespace nestwalk
