#!/usr/bin/env bash
# Configures and builds nestwalk into build/ (Release, portable x86-64-v2).
# Usage: tools/build.sh [cmake --build arguments, e.g. --target nestwalk]
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release ${NESTWALK_CMAKE_ARGS:-} >/dev/null
cmake --build build -j "$jobs" "$@"
