// SPDX-License-Identifier: MIT
// A run folder's summary.json as the integration tests read it.
#pragma once

#include <filesystem>
#include <string>

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

}  // namespace nav::testing
