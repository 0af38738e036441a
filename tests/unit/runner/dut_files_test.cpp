// SPDX-License-Identifier: MIT
// The files a DUT's command names (nav/bench/runner.hpp, dut_argument_files): an argument that
// is a regular file's path is hashed, in argument order; the program itself, device lines,
// folders and missing paths are not; a changed file changes its hash.
#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "nav/bench/runner.hpp"

namespace nav::bench {
namespace {

namespace fs = std::filesystem;

// SHA-256 of "a: 1\n" (sha256sum).
constexpr const char* kOne = "37b128c59f1f5097f73f82691cb519f1f568667faab5ced1b4ab979d36837eae";

TEST(DutArgumentFiles, AreTheArgumentsThatNameRegularFilesInTheirOrder) {
  const fs::path dir = fs::temp_directory_path() / ("dut-files-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path config = dir / "navd.yaml", other = dir / "other.yaml";
  std::ofstream(config) << "a: 1\n";
  std::ofstream(other) << "b\n";
  const std::vector<std::string> argv{config.string(),  // the program: not an argument
                                      "--config",        other.string(),
                                      "--ahrs",          "/dev/null",
                                      "--log",           dir.string(),
                                      "--missing",       (dir / "nope.yaml").string(),
                                      "--again",         config.string()};
  const auto files = dut_argument_files(argv);
  ASSERT_EQ(files.size(), 2U);
  EXPECT_EQ(files[0].path, other.string());
  EXPECT_EQ(files[1].path, config.string());
  EXPECT_EQ(files[1].sha256, kOne);
  EXPECT_EQ(files[0].sha256.size(), 64U);

  std::ofstream(config) << "a: 2\n";
  const auto changed = dut_argument_files(argv);
  ASSERT_EQ(changed.size(), 2U);
  EXPECT_EQ(changed[0], files[0]);
  EXPECT_NE(changed[1].sha256, kOne);
  EXPECT_TRUE(dut_argument_files({"navd"}).empty());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace nav::bench
