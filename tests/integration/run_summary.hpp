// SPDX-License-Identifier: MIT
// A run folder's summary.json as the integration tests read it.
#pragma once

#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "navbench_cli.hpp"

namespace nav::testing {

/// The run folder's summary.json.
inline nlohmann::json summary(const std::filesystem::path& run) {
  return nlohmann::json::parse(slurp(run / "summary.json"));
}

/// The check of that name in a summary, or null.
inline const nlohmann::json* check(const nlohmann::json& s, const std::string& name) {
  for (const auto& c : s["checks"]) {
    if (c["name"] == name) return &c;
  }
  return nullptr;
}

/// Whether a realtime run's DUT passed: exit 0 (PASS), or exit 3 (BENCH-LATE: the machine kept
/// the bench from its deadlines, as a stalled VM does now and then) with every check of the
/// DUT passed. A test of what the DUT and the bench do must not fail on the machine's stall;
/// the bench's own punctuality is measured by benchmarks/lateness, not by tests.
inline ::testing::AssertionResult dut_passed_in_realtime(const ProcessResult& r,
                                                         const std::filesystem::path& run) {
  if (r.exit_code == 0) return ::testing::AssertionSuccess();
  if (r.exit_code != 3) {
    return ::testing::AssertionFailure() << "exit " << r.exit_code << "\n" << r.out << r.err;
  }
  const auto s = summary(run);
  if (s["verdict"] != "BENCH-LATE") {
    return ::testing::AssertionFailure() << "exit 3, verdict " << s["verdict"] << "\n" << r.out;
  }
  for (const auto& c : s["checks"]) {
    if (!c["passed"].get<bool>()) {
      return ::testing::AssertionFailure() << "BENCH-LATE with check " << c["name"]
                                           << " failed\n" << r.out;
    }
  }
  return ::testing::AssertionSuccess();
}

}  // namespace nav::testing
