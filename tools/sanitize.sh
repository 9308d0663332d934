#!/usr/bin/env bash
# The test suite under the sanitizers (README: the optional third command; .ci/run runs it after
# the README's test command):
#   1. AddressSanitizer + UndefinedBehaviorSanitizer: everything built in build-asan/ (-O1 -g,
#      -fno-sanitize-recover=all) and the whole ctest suite run, halting on the first report; leaks
#      are reported for our code, with the suppressions in tools/sanitizers/lsan.supp (each entry
#      names the library and why).
#   2. ThreadSanitizer over the threaded parts (the frame writer thread and the ffmpeg pipe of
#      `run --render`, engine/render/frame_writers.h; the guarded model reader's child process):
#      the render module, its tests and the program built in build-tsan/, and the tests that
#      drive those parts run (-R below), with tools/sanitizers/tsan.supp for the uninstrumented
#      libraries' own threads (Mesa's llvmpipe).
# Usage: tools/sanitize.sh [asan|tsan|all] (default all). Extra ctest arguments in
# NESTWALK_SANITIZE_CTEST_ARGS. Exit status: non-zero on the first failure.
set -euo pipefail
cd "$(dirname "$0")/.."
which="${1:-all}"
tools/setup-deps.sh
jobs=$(nproc 2>/dev/null || echo 2)
root=$(pwd)

export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:abort_on_error=0:detect_stack_use_after_return=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export LSAN_OPTIONS="suppressions=$root/tools/sanitizers/lsan.supp:print_suppressions=0"
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$root/tools/sanitizers/tsan.supp"

flags_asan="-O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=all"
flags_tsan="-O1 -g -fsanitize=thread"

configure() {  # build-dir flags
  cmake -S . -B "$1" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$2" \
    -DCMAKE_C_FLAGS_RELWITHDEBINFO="$2" -DCMAKE_EXE_LINKER_FLAGS="${2#-O1 -g }" \
    -DCMAKE_SHARED_LINKER_FLAGS="${2#-O1 -g }" >/dev/null
}

if [ "$which" = asan ] || [ "$which" = all ]; then
  echo "nestwalk: sanitize: AddressSanitizer + UndefinedBehaviorSanitizer, whole suite (build-asan/)"
  start=$(date +%s)
  configure build-asan "$flags_asan"
  cmake --build build-asan -j "$jobs"
  (cd build-asan && ctest --output-on-failure -j "$jobs" ${NESTWALK_SANITIZE_CTEST_ARGS:-})
  echo "nestwalk: sanitize: asan+ubsan passed in $(( $(date +%s) - start )) s"
fi

if [ "$which" = tsan ] || [ "$which" = all ]; then
  echo "nestwalk: sanitize: ThreadSanitizer, the threaded parts (build-tsan/)"
  start=$(date +%s)
  configure build-tsan "$flags_tsan"
  cmake --build build-tsan -j "$jobs" --target nestwalk render_tests tool_tests core_tests scene_tests bundled_scene
  (cd build-tsan && ctest --output-on-failure -j "$jobs" \
     -R 'FrameWriter|RunRender|GuardedProcess|ModelFile|ModelCache|Render' ${NESTWALK_SANITIZE_CTEST_ARGS:-})
  echo "nestwalk: sanitize: tsan passed in $(( $(date +%s) - start )) s"
fi
