// SPDX-License-Identifier: MIT
// A scenario (or any) text written to a file under the test's temporary folder, for the bench's
// loader tests.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace nav::bench::testing {

/// Writes `text` to <TempDir>/<folder>-<pid>/<name> and returns that path. The process id keeps
/// apart the tests of one program that ctest runs at once (each in its own process): two of
/// them writing one file raced, and a loader read the other's scenario.
inline std::string write_temp_file(const std::string& folder, const std::string& name,
                                   const std::string& text) {
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) /
                                     (folder + "-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::filesystem::path p = dir / name;
  std::ofstream(p) << text;
  return p.string();
}

}  // namespace nav::bench::testing
