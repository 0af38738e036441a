// SPDX-License-Identifier: MIT
// Where the checkout and the built programs are, for the tests, fuzz targets and benchmarks
// that read the repository's files (scenarios, fixtures, docs) or start its programs (navbench,
// navd). The two folders are compiled into one file of their own (source_paths.cpp, library
// nav_source_paths) instead of into every test as macros: a compiler cache then serves a fresh
// clone in another folder every object but that one (docs/design-notes.md, Build and CI times).
#pragma once

#include <string>

namespace nav::test_paths {

/// The checkout's top folder (CMake's PROJECT_SOURCE_DIR), without a trailing '/'.
std::string source_dir();

/// The folder of the built executables (navbench, navd, nav-group-guard, the tests).
std::string binary_dir();

}  // namespace nav::test_paths
