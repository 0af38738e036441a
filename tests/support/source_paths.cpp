// SPDX-License-Identifier: MIT
#include "source_paths.hpp"

namespace nav::test_paths {

std::string source_dir() { return NAV_SOURCE_DIR; }

std::string binary_dir() { return NAV_BINARY_DIR; }

}  // namespace nav::test_paths
