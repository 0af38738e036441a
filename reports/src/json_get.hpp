// SPDX-License-Identifier: MIT
// Reading a JSON document written by some navbench (perhaps an older one, perhaps edited by
// hand) without trusting its types: a missing key or a value of another type gives the
// default, never an exception. Private to nav_reports.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace nav::reports::detail {

inline const nlohmann::json& member(const nlohmann::json& j, const char* key) {
  static const nlohmann::json kNull;
  if (!j.is_object()) return kNull;
  const auto it = j.find(key);
  return it == j.end() ? kNull : *it;
}

inline std::optional<std::string> get_string(const nlohmann::json& j, const char* key) {
  const auto& v = member(j, key);
  if (!v.is_string()) return std::nullopt;
  return v.get<std::string>();
}

inline std::string get_string(const nlohmann::json& j, const char* key, const std::string& def) {
  return get_string(j, key).value_or(def);
}

inline std::optional<double> get_number(const nlohmann::json& j, const char* key) {
  const auto& v = member(j, key);
  if (!v.is_number()) return std::nullopt;
  return v.get<double>();
}

inline double get_number(const nlohmann::json& j, const char* key, double def) {
  return get_number(j, key).value_or(def);
}

inline std::optional<bool> get_bool(const nlohmann::json& j, const char* key) {
  const auto& v = member(j, key);
  if (!v.is_boolean()) return std::nullopt;
  return v.get<bool>();
}

/// The array at key, or an empty array.
inline const nlohmann::json& get_array(const nlohmann::json& j, const char* key) {
  static const nlohmann::json kEmpty = nlohmann::json::array();
  const auto& v = member(j, key);
  return v.is_array() ? v : kEmpty;
}

/// Whether a check of summary.json judged a peer's DUT: its `vehicle` is not the primary's
/// (the first of `vehicles`). The run's timeseries and plots are the primary's.
inline bool of_peer(const nlohmann::json& summary, const nlohmann::json& check) {
  const auto vehicle = get_string(check, "vehicle");
  const auto& vehicles = get_array(summary, "vehicles");
  return vehicle && !vehicles.empty() && get_string(vehicles.front(), "name") != vehicle;
}

}  // namespace nav::reports::detail
