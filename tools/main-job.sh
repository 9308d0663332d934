#!/usr/bin/env bash
# The main job: installs the dependencies, builds the nestwalk program and the bundled mining-dump
# scene, and plays the scene's three flythroughs headlessly (bench patrol, ramp descent, low
# flight), each into build/runs/<flythrough>/ (frames.csv, summary.json, frame_times.png,
# camera.path). Exits non-zero when a flythrough's expectations are not met.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup-deps.sh
tools/build.sh --target nestwalk bundled_scene
scene=build/assets/mining_dump
status=0
for script in bench_patrol ramp_descent low_flight; do
  build/tools/nestwalk run "$scene/scene.json" --script "$scene/scripts/$script.txt" --headless \
    --out "build/runs/$script" --overwrite "$@" || status=$?
  echo
done
echo "nestwalk: the runs are in $(pwd)/build/runs (replay one: build/tools/nestwalk export $scene/scene.json" \
     "build/runs/scene.osgb && osgviewer build/runs/scene.osgb -p build/runs/bench_patrol/camera.path)"
exit $status
