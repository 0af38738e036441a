# SPDX-License-Identifier: MIT
# Warnings as an interface target, linked PRIVATE by every project target.
add_library(nav_warnings INTERFACE)
target_compile_options(nav_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion
  $<$<BOOL:${NAV_WERROR}>:-Werror>)

# nav_add_test(NAME n SOURCES s... LIBS l... LABELS unit|integration)
function(nav_add_test)
  cmake_parse_arguments(T "" "NAME" "SOURCES;LIBS;LABELS" ${ARGN})
  add_executable(${T_NAME} ${T_SOURCES})
  target_link_libraries(${T_NAME} PRIVATE ${T_LIBS} GTest::gtest_main nav_source_paths
                                          nav_warnings)
  nav_use_test_pch(${T_NAME})
  set(props TIMEOUT 300)
  if("integration" IN_LIST T_LABELS)
    # Integration tests measure timing on ptys: never alongside another test.
    list(APPEND props RUN_SERIAL TRUE)
  endif()
  gtest_discover_tests(${T_NAME} PROPERTIES ${props} DISCOVERY_TIMEOUT 60)
  # The labels are set once the tests are discovered: gtest_discover_tests() passes its
  # PROPERTIES on as a flat list, where a second label would be read as a property name.
  set(labels_file "${CMAKE_CURRENT_BINARY_DIR}/${T_NAME}_labels.cmake")
  file(WRITE "${labels_file}"
    "if(${T_NAME}_TESTS)\n"
    "  set_tests_properties(\${${T_NAME}_TESTS} PROPERTIES LABELS \"${T_LABELS}\")\n"
    "endif()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${labels_file}")
  if(NOT "unit" IN_LIST T_LABELS AND NOT "integration" IN_LIST T_LABELS)
    nav_not_in_sanitized_build(${T_NAME})
  endif()
endfunction()

# nav_add_vcan_test(NAME n SOURCES s... LIBS l...): a GoogleTest binary that needs vcan0.
# ctest runs the whole binary as ONE test (label vcan) through scripts/with-vcan, which brings
# vcan0 up on the host or boots user-mode Linux for it (about 1.5 s per boot, hence one test
# per binary rather than per case). RUN_SERIAL: the cases share vcan0. The harness's own
# timeout (exit 124, with a message) comes before ctest's.
function(nav_add_vcan_test)
  cmake_parse_arguments(T "" "NAME" "SOURCES;LIBS" ${ARGN})
  add_executable(${T_NAME} ${T_SOURCES})
  target_link_libraries(${T_NAME} PRIVATE ${T_LIBS} GTest::gtest_main nav_source_paths
                                          nav_warnings)
  nav_use_test_pch(${T_NAME})
  add_test(NAME ${T_NAME}
    COMMAND ${PROJECT_SOURCE_DIR}/scripts/with-vcan $<TARGET_FILE:${T_NAME}>)
  # 77: neither the host, user-mode Linux nor a virtual machine (scripts/vcan-vm) can give vcan0
  # on this machine (with-vcan --help).
  set_tests_properties(${T_NAME} PROPERTIES LABELS vcan RUN_SERIAL TRUE TIMEOUT 300
    ENVIRONMENT WITH_VCAN_TIMEOUT=280 SKIP_RETURN_CODE 77)
  nav_not_in_sanitized_build(${T_NAME})
endfunction()

# nav_not_in_sanitized_build(target): the sanitized folder runs only the tests labelled unit or
# integration (scripts/test --sanitize); a test program with neither label (vcan: user-mode
# Linux; golden: the unit tests cover its code) is not built there.
function(nav_not_in_sanitized_build target)
  if(NAV_SANITIZE)
    set_target_properties(${target} PROPERTIES EXCLUDE_FROM_ALL TRUE)
  endif()
endfunction()

# nav_use_test_pch(target): the test program compiles with nav_test_pch's precompiled header
# (tests/CMakeLists.txt), and so with its language level and include paths, without which GCC
# would refuse the header (-Winvalid-pch says why) and parse it as text.
function(nav_use_test_pch target)
  if(TARGET nav_test_pch)
    target_precompile_headers(${target} REUSE_FROM nav_test_pch)
    target_compile_features(${target} PRIVATE cxx_std_20)
    target_link_libraries(${target} PRIVATE Eigen3::Eigen)
    # GCC before 13 forgets the `#pragma GCC diagnostic` of a precompiled header (GCC bug
    # 64117), so libstdc++ 12's own silencing of these three warnings in char_traits.h is lost
    # and std::string's operator+ trips them falsely. The test programs do without them; the
    # project's own code keeps them, and the sanitized build checks bounds at run time.
    if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
      target_compile_options(${target} PRIVATE
        -Wno-array-bounds -Wno-stringop-overflow -Wno-stringop-overread)
    endif()
  endif()
endfunction()

# nav_precompile_headers(target [HEADER...]): the target's sources compile with a precompiled
# header of the C++ library, Eigen and tl::expected, and the third-party HEADERs given (those
# most of its sources include, e.g. <nlohmann/json.hpp>): parsed once per target instead of once
# per source. For the libraries and navd, whose sources spend most of their time in headers:
# the Quick start's build takes a fifth less time with it (docs/design-notes.md, Build and CI
# times).
function(nav_precompile_headers target)
  target_precompile_headers(${target} PRIVATE
    <algorithm> <array> <chrono> <cmath> <cstdint> <cstdio> <filesystem> <functional> <map>
    <memory> <optional> <string> <string_view> <unordered_map> <utility> <variant> <vector>
    <Eigen/Core> <Eigen/Geometry> <tl/expected.hpp> ${ARGN})
endfunction()

# nav_fuzz_coverage(target): with NAV_FUZZ, the target carries libFuzzer's coverage counters
# (-fsanitize=fuzzer-no-link): a library a fuzz target reads its input with (cmake/NavFuzz.cmake).
function(nav_fuzz_coverage target)
  if(NAV_FUZZ)
    target_compile_options(${target} PRIVATE -fsanitize=fuzzer-no-link)
  endif()
endfunction()
