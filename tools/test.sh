#!/usr/bin/env bash
# Installs the dependencies, builds everything (engine, program, tests, benchmarks) and runs the
# whole test suite through ctest. Extra arguments go to ctest (e.g. -R Sat). Prints the time of
# each phase (dependencies, build, tests).
set -euo pipefail
cd "$(dirname "$0")/.."
phase_start=$(date +%s)
phase_done() { local now; now=$(date +%s); echo "nestwalk: test.sh: $1 in $(( now - phase_start )) s"; phase_start=$now; }
tools/setup-deps.sh
phase_done "dependencies"
tools/build.sh
phase_done "build"
jobs=$(nproc 2>/dev/null || echo 2)
(cd build && ctest --output-on-failure -j "$jobs" "$@")
phase_done "tests"
