// SPDX-License-Identifier: MIT
// Locating the real device captures in fixtures-external (see its README.md): they live beside
// the checkout, never in it. Tests that need them derive from ExternalFixtureTest, which skips
// (not fails) when the folder is absent.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "source_paths.hpp"

namespace nav::protocols::test_support {

/// $NAV_FIXTURES_EXTERNAL if set, else the checkout/../shared/fixtures-external.
inline std::filesystem::path fixtures_external_dir() {
  if (const char* env = std::getenv("NAV_FIXTURES_EXTERNAL"); env != nullptr && *env != '\0') {
    return std::filesystem::path(env);
  }
  return std::filesystem::path(nav::test_paths::source_dir()) / ".." / "shared" / "fixtures-external";
}

/// Whole file as bytes; empty when it cannot be read.
inline std::vector<std::uint8_t> read_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Base for tests on real captures: dir() is the fixtures-external folder.
class ExternalFixtureTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fixtures_external_dir();
    if (!std::filesystem::is_directory(dir_)) {
      GTEST_SKIP() << "fixtures-external not found at " << dir_.string()
                   << " (set NAV_FIXTURES_EXTERNAL)";
    }
  }
  /// The fixtures-external folder.
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
};

}  // namespace nav::protocols::test_support
