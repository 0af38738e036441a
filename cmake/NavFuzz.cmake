# SPDX-License-Identifier: MIT
# NAV_FUZZ=ON: the folder builds the libFuzzer targets of tests/fuzz. Every library is compiled
# with coverage instrumentation, AddressSanitizer and UndefinedBehaviorSanitizer (an undefined
# behaviour stops the fuzzer like a crash); the fuzz executables link libFuzzer's main
# (tests/fuzz/CMakeLists.txt). Build only the `nav_fuzzers` target: the rest of the project is
# configured but not needed.
if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "NAV_FUZZ needs clang (libFuzzer), e.g. CXX=clang++-14; this is "
                      "${CMAKE_CXX_COMPILER_ID}")
endif()
add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined
                    -fno-omit-frame-pointer -g)
add_link_options(-fsanitize=address,undefined)
