# Refuses quoted includes that climb out of their folder ("../walker/walker.h"): a module's headers
# are reached only through the include roots (nestwalk/<module>/<file>.h), which is what lets the
# build refuse an include across a forbidden edge; a relative path would walk around it.
#   cmake -DROOTS="dir;dir..." -P relative_includes.cmake
# Fails listing every FILE:LINE that has one; passes silently otherwise.
if(NOT ROOTS)
  message(FATAL_ERROR "relative_includes.cmake: ROOTS (the folders to scan) is not set")
endif()
set(found "")
foreach(root ${ROOTS})
  file(GLOB_RECURSE sources "${root}/*.h" "${root}/*.cpp" "${root}/*.in")
  foreach(source ${sources})
    file(STRINGS "${source}" lines)
    set(number 0)
    foreach(line IN LISTS lines)
      math(EXPR number "${number} + 1")
      if(line MATCHES "^[ \t]*#[ \t]*include[ \t]*\"[^\"]*\\.\\./")
        string(APPEND found "\n  ${source}:${number}: ${line}")
      endif()
    endforeach()
  endforeach()
endforeach()
if(found)
  message(FATAL_ERROR "includes that climb out of their module (use \"nestwalk/<module>/<file>.h\"):${found}")
endif()
