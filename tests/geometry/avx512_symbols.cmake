# The AVX-512 file of testBoxPairs (engine/geometry/obb_batch_avx512.cpp) is compiled for AVX-512
# while the rest of the build is portable. A weak (inline, template) symbol defined there could be
# chosen by the linker for every caller and run AVX-512 instructions on a processor without them,
# so the file may define exactly its one entry point: checked on the module's static library.
# Weak data objects (nm's V and v: typeinfo the sanitizers emit, the personality routine's
# reference) hold no instructions and are allowed.
#   cmake -DNM=nm -DLIBRARY=libnestwalk_geometry.a -P avx512_symbols.cmake
# Fails naming each other symbol the member defines; prints the one it found otherwise.
cmake_minimum_required(VERSION 3.22)
if(NOT NM OR NOT LIBRARY)
  message(FATAL_ERROR "avx512_symbols.cmake: NM and LIBRARY must be set")
endif()
execute_process(COMMAND ${NM} -C --defined-only ${LIBRARY} OUTPUT_VARIABLE listing RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "avx512_symbols.cmake: ${NM} ${LIBRARY} failed (${rc})")
endif()
string(REPLACE "\n" ";" lines "${listing}")
set(member "")
set(found "")
set(wrong "")
foreach(line ${lines})
  if(line MATCHES "^(.+\\.o):$")
    set(member "${CMAKE_MATCH_1}")
  elseif(member MATCHES "obb_batch_avx512" AND line MATCHES "^[0-9a-f]* ([A-Za-z]) (.*)$")
    set(kind "${CMAKE_MATCH_1}")
    set(name "${CMAKE_MATCH_2}")
    if(kind MATCHES "^[trbdnVv]$")  # local to the file (text, data), or weak data
      continue()
    elseif(kind STREQUAL "T" AND name MATCHES "^nestwalk::obb_batch_detail::boxPairsAvx512\\(")
      list(APPEND found "${name}")
    else()
      list(APPEND wrong "${kind} ${name}")
    endif()
  endif()
endforeach()
if(wrong)
  string(REPLACE ";" "\n  " text "${wrong}")
  message(FATAL_ERROR "obb_batch_avx512.cpp defines symbols other than its entry point:\n  ${text}")
endif()
if(NOT found)
  message(FATAL_ERROR "obb_batch_avx512.cpp: boxPairsAvx512 not found in ${LIBRARY}")
endif()
message(STATUS "obb_batch_avx512.cpp defines only: ${found}")
