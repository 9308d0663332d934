#!/usr/bin/env bash
# The main job: installs the dependencies, builds the nestwalk program and runs the demo.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup-deps.sh
tools/build.sh --target nestwalk
build/tools/nestwalk demo "$@"
