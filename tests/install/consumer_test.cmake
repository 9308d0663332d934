# The install test (ctest Install.ConsumerBuildsAgainstTheInstalledPackage): installs the build into
# a fresh prefix with `cmake --install`, configures and builds tests/install/consumer against it
# with find_package(nestwalk), and runs it on the bundled scene: the bench patrol's start, 100
# steps at 30 m/s along the lane, which must end blocked by the station standing in it; then the
# bench patrol played through the session module into a run folder (play_script), which must meet
# its expectations and write a CSV row per frame.
# Variables: BUILD_DIR (nestwalk's build), SOURCE_DIR, WORK_DIR (scratch), SCENE_DIR (the bundled
# scene; the start and the blocker are read from its scripts/bench_patrol.txt).
file(STRINGS ${SCENE_DIR}/scripts/bench_patrol.txt start REGEX "^start ")
file(STRINGS ${SCENE_DIR}/scripts/bench_patrol.txt blocker REGEX "^expect blocked by ")
if(NOT start MATCHES "^start ([-0-9.]+) ([-0-9.]+) heading ([-0-9.]+)")
  message(FATAL_ERROR "no start line in ${SCENE_DIR}/scripts/bench_patrol.txt")
endif()
set(X ${CMAKE_MATCH_1})
set(Y ${CMAKE_MATCH_2})
set(HEADING ${CMAKE_MATCH_3})
string(REPLACE "expect blocked by " "" EXPECT "${blocker}")
set(SCENE ${SCENE_DIR}/scene.json)
file(REMOVE_RECURSE ${WORK_DIR})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${rc})")
endif()
foreach(f bin/nestwalk include/nestwalk/version.h include/nestwalk/walker/walker.h
          lib/cmake/nestwalk/nestwalkConfig.cmake lib/libnestwalk_walker.a)
  if(NOT EXISTS ${WORK_DIR}/prefix/${f})
    message(FATAL_ERROR "not installed: ${f}")
  endif()
endforeach()
# The public surface is closed: every "nestwalk/..." an installed header includes is installed too
# (a header left out of a module's INSTALL_HEADERS would break a consumer that includes its user).
file(GLOB_RECURSE installed_headers ${WORK_DIR}/prefix/include/nestwalk/*.h)
set(missing "")
foreach(header ${installed_headers})
  file(STRINGS ${header} includes REGEX "^#include \"nestwalk/")
  foreach(line IN LISTS includes)
    string(REGEX REPLACE "^#include \"(nestwalk/[^\"]+)\".*" "\\1" included "${line}")
    if(NOT EXISTS ${WORK_DIR}/prefix/include/${included})
      string(APPEND missing "\n  ${header} includes ${included}, which is not installed")
    endif()
  endforeach()
endforeach()
if(missing)
  message(FATAL_ERROR "the installed headers are not closed under their includes:${missing}")
endif()
list(LENGTH installed_headers installed_count)
message(STATUS "installed headers: ${installed_count}")

execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/install/consumer -B ${WORK_DIR}/build
                        -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "configuring the consumer failed:\n${out}\n${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/build RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "building the consumer failed:\n${out}\n${err}")
endif()
# Runs one of the consumer's programs with its arguments: its standard output printed and left in
# `out`; the test fails when it exits non-zero.
function(run_consumer program)
  execute_process(COMMAND ${WORK_DIR}/build/${program} ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE output
                  ERROR_VARIABLE err)
  message("${output}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${program} failed (${rc}): ${output}${err}")
  endif()
  set(out "${output}" PARENT_SCOPE)
endfunction()

run_consumer(walk_box ${SCENE} ${X} ${Y} ${HEADING} 30)
if(NOT out MATCHES "blocked by ${EXPECT}")
  message(FATAL_ERROR "walk_box was not blocked by ${EXPECT}")
endif()
if(NOT out MATCHES "walked 100 steps")
  message(FATAL_ERROR "walk_box did not walk its 100 steps")
endif()
# The bench patrol played through the session module into a run folder.
run_consumer(play_script ${SCENE} ${SCENE_DIR}/scripts/bench_patrol.txt ${WORK_DIR}/run)
if(NOT out MATCHES "^([0-9]+) frames, ([0-9]+) of ([0-9]+) expectations met")
  message(FATAL_ERROR "play_script printed no frame count: ${out}")
endif()
set(frames ${CMAKE_MATCH_1})
if(NOT CMAKE_MATCH_2 EQUAL CMAKE_MATCH_3)
  message(FATAL_ERROR "play_script did not meet the bench patrol's expectations: ${out}")
endif()
file(STRINGS ${WORK_DIR}/run/frames.csv rows)
list(LENGTH rows row_count)
math(EXPR expected_rows "${frames} + 1")
if(NOT row_count EQUAL expected_rows)
  message(FATAL_ERROR "play_script's frames.csv has ${row_count} lines for ${frames} frames")
endif()
foreach(f summary.json frame_times.png top_down.png camera.path)
  if(NOT EXISTS ${WORK_DIR}/run/${f})
    message(FATAL_ERROR "play_script wrote no ${f}")
  endif()
endforeach()
file(REMOVE_RECURSE ${WORK_DIR})
