# Refuses an OpenSceneGraph header reachable from the simulation: the files named in SCAN, and every
# nestwalk header they include, directly or through others, may not include <osg...> (nor osgDB,
# osgViewer...). The walker, gis and report compile without OpenSceneGraph; scene reads model files
# with it, privately (its public headers are scanned). A module's header "nestwalk/M/F" is found at
# ROOT/engine/M/F, or ROOT/terrain/F for the terrain.
#   cmake -DROOT=dir -DSCAN="file;file..." -P osg_reach.cmake
# Fails naming each OSG include reached and the chain of includes that reaches it; passes silently
# otherwise.
cmake_minimum_required(VERSION 3.25)
if(NOT ROOT OR NOT SCAN)
  message(FATAL_ERROR "osg_reach.cmake: ROOT (the source tree) and SCAN (the files to check) must be set")
endif()

# The file a quoted include names, or "" when it is not one of the tree's (version.h is generated).
function(resolve_include name out)
  set(path "")
  if(name MATCHES "^nestwalk/terrain/(.+)$")
    set(path "${ROOT}/terrain/${CMAKE_MATCH_1}")
  elseif(name MATCHES "^nestwalk/([a-z_]+)/(.+)$")
    set(path "${ROOT}/engine/${CMAKE_MATCH_1}/${CMAKE_MATCH_2}")
  endif()
  if(path AND NOT EXISTS "${path}")
    set(path "")
  endif()
  set(${out} "${path}" PARENT_SCOPE)
endfunction()

set(found "")
foreach(start ${SCAN})
  # Depth-first over the include graph from `start`, each file once; `via` keeps how it was reached.
  set(queue "${start}")
  set(seen "${start}")
  set(via_${start} "${start}")
  while(queue)
    list(POP_FRONT queue file)
    file(STRINGS "${file}" lines REGEX "^[ \t]*#[ \t]*include")
    foreach(line IN LISTS lines)
      if(line MATCHES "<(osg[A-Za-z]*/[^>]+)>")
        string(APPEND found "\n  ${via_${file}}: #include <${CMAKE_MATCH_1}>")
      elseif(line MATCHES "\"([^\"]+)\"")
        resolve_include("${CMAKE_MATCH_1}" next)
        if(next AND NOT next IN_LIST seen)
          list(APPEND seen "${next}")
          list(APPEND queue "${next}")
          set(via_${next} "${via_${file}} -> ${CMAKE_MATCH_1}")
        endif()
      endif()
    endforeach()
  endwhile()
endforeach()
if(found)
  message(FATAL_ERROR "OpenSceneGraph reaches the simulation (only scene's private files and the drawing modules may include it):${found}")
endif()
