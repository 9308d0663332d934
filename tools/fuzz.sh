#!/usr/bin/env bash
# Fuzzing with libFuzzer (Debian's clang and its compiler-rt): builds every fuzz target of
# tests/fuzz/ in build-fuzz/ (clang, NESTWALK_FUZZ=ON: coverage, AddressSanitizer and
# UndefinedBehaviorSanitizer on the code under test) and runs each for SECONDS (default 600),
# starting from its committed corpus (tests/fuzz/corpus/<target>/, copied to build-fuzz/corpus/).
# Limits per input: 10 s, 2048 MB. A finding (crash, hang, leak, sanitizer report, an exception
# other than InputError) is copied into the committed corpus as regression-<name>, so that the
# normal test run replays it; the script then exits non-zero. Prints executions and corpus sizes.
# Usage: tools/fuzz.sh [SECONDS] [TARGET...]  (targets: scene_json script animation_path
# points_csv pairs_csv catalog dem pyramid gltf; default all).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-600}"
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(scene_json script animation_path points_csv pairs_csv catalog dem pyramid gltf)
fi
jobs=$(nproc 2>/dev/null || echo 2)
CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DNESTWALK_FUZZ=ON >/dev/null
cmake --build build-fuzz -j "$jobs" --target "${targets[@]/#/fuzz_}"
status=0
for t in "${targets[@]}"; do
  work=build-fuzz/corpus/$t findings=build-fuzz/findings/$t
  rm -rf "$findings"  # only this run's findings are new
  mkdir -p "$work" "$findings"
  cp -n tests/fuzz/corpus/"$t"/* "$work"/ 2>/dev/null || true
  echo "nestwalk: fuzz: $t for $seconds s"
  if ! build-fuzz/tests/fuzz/fuzz_"$t" "$work" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
       -max_len=65536 -print_final_stats=1 -artifact_prefix="$findings"/ 2>build-fuzz/fuzz_"$t".log; then
    status=1
  fi
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb|stat::new_units_added" build-fuzz/fuzz_"$t".log | tr '\n' ' '
  echo "corpus $(ls "$work" | wc -l) files"
  for f in "$findings"/*; do
    [ -e "$f" ] || continue
    echo "nestwalk: fuzz: $t: finding $f (copied to tests/fuzz/corpus/$t/regression-$(basename "$f"))"
    cp "$f" tests/fuzz/corpus/"$t"/regression-"$(basename "$f")"
    status=1
  done
done
exit $status
