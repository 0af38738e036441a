# SPDX-License-Identifier: MIT
# Every compile of every build folder (build/, build-sanitize/) goes through ccache when it is
# installed (scripts/setup installs Debian's), by cmake/ccache-launch, which sets what lets a
# fresh clone in another folder hit the objects another clone left in the cache (~/.cache/ccache).
# A launcher given on the command line (-DCMAKE_CXX_COMPILER_LAUNCHER=...) wins; -DNAV_CCACHE=OFF
# compiles without one.
option(NAV_CCACHE "Compile through ccache when it is installed (cmake/ccache-launch)" ON)
if(NAV_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  find_program(NAV_CCACHE_PROGRAM ccache)
  if(NAV_CCACHE_PROGRAM)
    set(CMAKE_CXX_COMPILER_LAUNCHER ${PROJECT_SOURCE_DIR}/cmake/ccache-launch
                                    ${NAV_CCACHE_PROGRAM})
  endif()
endif()

# __FILE__ (NAV_ENSURE's messages, GoogleTest's failures) relative to the checkout, with or
# without the cache: ccache hands the compiler paths relative to the build folder
# ("../bench/src/..."), which Ninja runs every compile from; a compile without it sees
# absolute ones.
file(RELATIVE_PATH nav_source_from_build ${CMAKE_BINARY_DIR} ${PROJECT_SOURCE_DIR})
string(REGEX REPLACE "/$" "" nav_source_from_build "${nav_source_from_build}")
add_compile_options(-fmacro-prefix-map=${PROJECT_SOURCE_DIR}/=)
if(NOT nav_source_from_build STREQUAL "")
  add_compile_options(-fmacro-prefix-map=${nav_source_from_build}/=)
endif()
