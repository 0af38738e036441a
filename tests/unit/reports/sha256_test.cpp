// SPDX-License-Identifier: MIT
// SHA-256 through OpenSSL against FIPS 180-2's examples.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "nav/reports/sha256.hpp"

namespace nav::reports {
namespace {

TEST(Sha256, KnownDigests) {
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  // The same digest in base64, as a Content-Security-Policy names a script.
  EXPECT_EQ(sha256_base64("abc"), "ungWv48Bz+pBQUDeXa4iI7ADYaOWF3qctBD/YfIAFa0=");
}

TEST(Sha256, FileDigestMatchesTheBytesAcrossBlocks) {
  const auto path = std::filesystem::path(::testing::TempDir()) / "navbench_sha256_test.bin";
  std::string bytes;
  for (int i = 0; i < 200000; ++i) bytes += static_cast<char>(i * 31);
  std::ofstream(path, std::ios::binary) << bytes;
  EXPECT_EQ(sha256_file(path.string()), sha256_hex(bytes));
  EXPECT_FALSE(sha256_file((path.string() + ".missing")).has_value());
}

}  // namespace
}  // namespace nav::reports
