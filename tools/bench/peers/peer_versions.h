// The versions of the libraries the benchmarks measure nestwalk against, for the machine block of
// every benchmark's output (bench_document.h): a figure next to a peer means little without the
// peer's version and precision.
#pragma once

#include "tools/bench/result_table.h"

namespace nestwalk::bench {

/// {"eigen": "3.4.0", "fcl": "0.7.0", "ccd": "double", "bullet": "324 (btScalar float)",
///  "embree": "3.13.5", "openscenegraph": "3.6.5"}: libccd's entry is its precision (ccd_real_t).
Json peerVersions();

}  // namespace nestwalk::bench
