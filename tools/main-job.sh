#!/usr/bin/env bash
# The main job: installs the dependencies, builds the nestwalk program and the bundled mining-dump
# scene, renders the default flythrough (the bench patrol) offscreen on the walker's view, with no
# display and no GPU needed, into build/runs/bench_patrol/: frames/ (PNG), flythrough.mp4,
# frames.csv (per-step timings: ground, collision, rendering), summary.json, frame_times.png,
# top_down.png and camera.path; then plays the other four flythroughs headlessly (no rendering)
# into build/runs/<flythrough>/, writes the speed-against-error report of every contact method
# (nestwalk report, full settings) into build/runs/report/, and plays the equipment walk on the
# second bundled scene, the one the build makes from GIS inputs with build-scene
# (build/assets/gis_dump), into build/runs/gis_equipment_walk/, and replays the bundled GPS track
# (routes/patrol_track.gpx) at its recorded pace, stopping at its waypoint, into
# build/runs/patrol_track/ with its results as GIS layers (results.gpkg, results.geojson). Exits
# non-zero when a flythrough's
# expectations are not met or the report cannot be made.
# Extra arguments go to the rendered run (e.g. --size 640x360, --every 1).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup-deps.sh
tools/build.sh --target nestwalk bundled_scene gis_sample_scene
scene=build/assets/mining_dump
runs=build/runs
status=0
# Every second step of the 60 Hz walk: a 30 frames-per-second video.
build/tools/nestwalk run "$scene/scene.json" --script "$scene/scripts/bench_patrol.txt" --headless \
  --render --every 2 --out "$runs/bench_patrol" --overwrite "$@" || status=$?
echo
for script in ramp_descent low_flight equipment_walk equipment_fly; do
  build/tools/nestwalk run "$scene/scene.json" --script "$scene/scripts/$script.txt" --headless \
    --out "$runs/$script" --overwrite || status=$?
  echo
done
build/tools/nestwalk report "$scene/scene.json" --out "$runs/report" --overwrite || status=$?
echo
gis=build/assets/gis_dump
build/tools/nestwalk run "$gis/scene.json" --script "${gis}_inputs/scripts/equipment_walk.txt" --headless \
  --method auto --out "$runs/gis_equipment_walk" --overwrite || status=$?
echo
build/tools/nestwalk run "$scene/scene.json" --route "$scene/routes/patrol_track.gpx" --use-times --stops waypoints \
  --headless --out "$runs/patrol_track" --overwrite || status=$?
echo
echo "nestwalk: the rendered flythrough is in $(pwd)/$runs/bench_patrol:" \
     "flythrough.mp4, frames/, frames.csv, summary.json, frame_times.png, top_down.png, camera.path"
echo "nestwalk: the other runs are in $(pwd)/$runs/{ramp_descent,low_flight,equipment_walk,equipment_fly}" \
     "and, on the scene built from GIS inputs, $(pwd)/$runs/gis_equipment_walk (replay one in osgviewer:" \
     "build/tools/nestwalk export $scene/scene.json $runs/scene.osgb && osgviewer $runs/scene.osgb -p $runs/low_flight/camera.path)"
echo "nestwalk: the methods' speed against error: $(pwd)/$runs/report/report.md"
echo "nestwalk: the GPS track replayed: $(pwd)/$runs/patrol_track (results.gpkg opens in QGIS, results.geojson on a web map)"
exit $status
