// The model-read benchmark (`nestwalk bench models`): what the guard around model files
// (scene/model_file.h: a child process, the scene graph handed back as .osgb) costs on good
// models. Per model, the least (and, in the JSON, the median) milliseconds over the repetitions,
// alternated, of: a direct read in this process (readModelFileUnguarded), a guarded read with the
// validated-model cache off (what a file's first read costs) and a guarded read from the cache
// (model_cache.h: every later read of the same file version), with the ratios to the direct read.
// Models: the bundled scene's (build/assets/mining_dump/models), the hand-made weather station,
// the GIS sample's pickup in millimetres, and the shared real models where present
// (../shared/data/models); each OBJ model is also read as glTF, from a copy assimp writes (Debian's
// assimp-utils), so that nestwalk's glTF reader (scene/gltf_model.h) is timed against OSG's OBJ
// plugin on the same mesh. Targets: a cached guarded read at most 1.2 times a direct one, on every
// model an OSG plugin reads (a glTF read is faster than the .osgb parse of its cache entry, which
// is printed apart); a glTF copy's direct read at most 1.2 times its OBJ's. The cache and the copies live in
// temporary folders of the benchmark's own.
#pragma once

#include "tools/bench/bench_runner.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace nestwalk::bench {

struct ModelReadBenchOptions : BenchOptions {
  int repetitions = 15;             // reads of each kind per model; quick: 3
  std::vector<std::string> models;  // model files; empty: the bundled, GIS-sample and shared ones
};

/// Times the reads and prints the table and the target (or one JSON document) to `out`. Returns 0,
/// or 1 when a model could not be read.
int runBenchmark(const ModelReadBenchOptions& opts, std::ostream& out);

}  // namespace nestwalk::bench
