# SPDX-License-Identifier: MIT
# NAV_FUZZ=ON: the folder builds the libFuzzer targets of tests/fuzz (clang only). Every program
# of the folder gets AddressSanitizer and UndefinedBehaviorSanitizer (an undefined behaviour
# stops the fuzzer like a crash); the code the fuzz targets read their input with (the libraries
# that call nav_fuzz_coverage(), and the targets themselves) also gets libFuzzer's coverage
# counters. Not the estimators, navd, the run engine or the tests: no fuzz target exercises
# them, and the counters would slow every test that does (a comparison costs a call).
# With NAV_SANITIZE=ON as well (scripts/build --sanitize: build-sanitize/), one folder serves the
# sanitized tests and the fuzzers. The fuzz executables link libFuzzer's main
# (tests/fuzz/CMakeLists.txt); the `nav_fuzzers` target builds them alone.
if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "NAV_FUZZ needs clang (libFuzzer), e.g. CXX=clang++-14; this is "
                      "${CMAKE_CXX_COMPILER_ID}")
endif()
if(NOT NAV_SANITIZE)
  include(${CMAKE_CURRENT_LIST_DIR}/NavSanitize.cmake)
endif()
