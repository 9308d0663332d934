#!/usr/bin/env bash
# Installs the dependencies, builds everything (engine, program, tests, benchmarks) and runs the
# whole test suite through ctest. Extra arguments go to ctest (e.g. -R Sat).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup-deps.sh
tools/build.sh
jobs=$(nproc 2>/dev/null || echo 2)
cd build && ctest --output-on-failure -j "$jobs" "$@"
