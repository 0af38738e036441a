// SPDX-License-Identifier: MIT
// What the CAN integration tests read back: candump logs (capture-can.log, candump -L) and
// the counter groups of navd's exit line.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "nav/protocols/candump_log.hpp"

namespace nav::testing {

/// The frames of a candump log (-l / -L lines), in file order; a line that is not one fails.
inline std::vector<protocols::candump::Record> read_log(const std::filesystem::path& p) {
  namespace candump = protocols::candump;
  std::vector<candump::Record> out;
  std::ifstream f(p);
  std::string line;
  int n = 0;
  while (std::getline(f, line)) {
    ++n;
    const auto r = candump::parse_line(line);
    if (r.status == candump::LineStatus::kIgnored) continue;
    EXPECT_EQ(r.status, candump::LineStatus::kRecord) << p << ":" << n << ": " << r.error;
    if (r.record) out.push_back(*r.record);
  }
  return out;
}

/// The numbers of a `name{k=v,...}` group in navd's exit line.
inline std::map<std::string, long> group(const std::string& text, const std::string& name) {
  std::map<std::string, long> out;
  const auto at = text.find(name + "{");
  if (at == std::string::npos) return out;
  const auto end = text.find('}', at);
  std::stringstream s(text.substr(at + name.size() + 1, end - at - name.size() - 1));
  std::string kv;
  while (std::getline(s, kv, ',')) {
    const auto eq = kv.find('=');
    if (eq != std::string::npos) out[kv.substr(0, eq)] = std::atol(kv.c_str() + eq + 1);
  }
  return out;
}

}  // namespace nav::testing
