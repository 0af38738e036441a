// SPDX-License-Identifier: MIT
// Reading a member of a JSON file the bench did not necessarily write (plan.json,
// result.json): a const json's operator[] must not be given a missing key. Private to
// nav_bench's campaign/.
#pragma once

namespace nav::bench::detail {

/// j[key], or null when j is no object or has no such key.
template <class Json>
const Json& json_at(const Json& j, const char* key) {
  static const Json null;
  if (!j.is_object()) return null;
  const auto it = j.find(key);
  return it == j.end() ? null : *it;
}

}  // namespace nav::bench::detail
