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
  target_link_libraries(${T_NAME} PRIVATE ${T_LIBS} GTest::gtest_main nav_warnings)
  target_compile_definitions(${T_NAME} PRIVATE
    NAV_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    NAV_BINARY_DIR="${CMAKE_RUNTIME_OUTPUT_DIRECTORY}")
  set(props LABELS "${T_LABELS}" TIMEOUT 300)
  if("integration" IN_LIST T_LABELS)
    # Integration tests measure timing on ptys: never alongside another test.
    list(APPEND props RUN_SERIAL TRUE)
  endif()
  gtest_discover_tests(${T_NAME} PROPERTIES ${props} DISCOVERY_TIMEOUT 60)
endfunction()
