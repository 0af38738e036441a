// SPDX-License-Identifier: MIT
// Golden files: a digest of a whole output plus quoted lines, compared with the committed file
// or, with NAV_UPDATE_GOLDEN=1 in the environment, written instead (scripts/update-golden).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../integration/navbench_cli.hpp"

namespace nav::testing {

inline std::uint64_t fnv1a64(const std::string& bytes) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (const unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}

inline std::string hex64(std::uint64_t v) {
  char digest[32];
  std::snprintf(digest, sizeof digest, "%016llx", static_cast<unsigned long long>(v));
  return digest;
}

/// "<name>_lines N", "<name>_bytes N", "<name>_fnv1a64 H", then every `every`-th line and the
/// last, numbered: a summary of a whole text in which a reviewer sees where a change shows.
inline std::string text_digest(const std::string& name, const std::string& text, std::size_t every) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  std::ostringstream o;
  o << name << "_lines " << lines.size() << "\n"
    << name << "_bytes " << text.size() << "\n"
    << name << "_fnv1a64 " << hex64(fnv1a64(text)) << "\n";
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (i % every == 0 || i + 1 == lines.size()) o << name << ' ' << i << ' ' << lines[i] << '\n';
  }
  return o.str();
}

/// The first line where a and b differ, for the failure message.
inline std::string first_difference(const std::string& a, const std::string& b) {
  std::istringstream ia(a), ib(b);
  std::string la, lb;
  for (int n = 1;; ++n) {
    const bool ea = !std::getline(ia, la);
    const bool eb = !std::getline(ib, lb);
    if (ea && eb) return "no difference";
    if (ea || eb || la != lb) {
      return "line " + std::to_string(n) + ":\n  golden: " + (ea ? "<end>" : la) +
             "\n  now:    " + (eb ? "<end>" : lb);
    }
  }
}

/// The first line where a and b differ among the quoted lines, skipping the digest's counts and
/// hash (which say that the texts differ, not where): "" when those all agree.
inline std::string first_quoted_difference(const std::string& a, const std::string& b) {
  const auto quoted_lines = [](const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) {
      const bool digest = l.find("_fnv1a64 ") != std::string::npos ||
                          l.find("_bytes ") != std::string::npos ||
                          l.find("_lines ") != std::string::npos || l.rfind("solutions ", 0) == 0;
      if (!digest) out.push_back(l);
    }
    return out;
  };
  const auto la = quoted_lines(a);
  const auto lb = quoted_lines(b);
  for (std::size_t i = 0; i < std::max(la.size(), lb.size()); ++i) {
    const std::string x = i < la.size() ? la[i] : "<end>";
    const std::string y = i < lb.size() ? lb[i] : "<end>";
    if (x != y) return "\n  first quoted line that differs:\n  golden: " + x + "\n  now:    " + y;
  }
  return "\n  every quoted line agrees: the outputs part between them";
}

/// Compares now with the golden file (relative to the source tree), or writes it when
/// NAV_UPDATE_GOLDEN=1 (the test is then skipped).
inline void expect_golden(const std::string& golden_rel, const std::string& now,
                          const std::string& what) {
  const std::filesystem::path golden = source_path(golden_rel);
  const char* update = std::getenv("NAV_UPDATE_GOLDEN");
  if (update != nullptr && std::string(update) == "1") {
    std::filesystem::create_directories(golden.parent_path());
    std::ofstream(golden, std::ios::binary) << now;
    GTEST_SKIP() << "wrote " << golden;
  }
  ASSERT_TRUE(std::filesystem::exists(golden)) << golden << " is missing: run scripts/update-golden";
  const std::string expected = slurp(golden);
  EXPECT_TRUE(now == expected) << what << " changed at " << first_difference(expected, now)
                               << first_quoted_difference(expected, now)
                               << "\nIf the change is deliberate, run scripts/update-golden and "
                                  "commit the golden files with it.";
}

}  // namespace nav::testing
