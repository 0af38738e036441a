// SPDX-License-Identifier: MIT
// JSON text that any byte string survives, and JSON inside an HTML page.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace nav::reports {

/// j as JSON text that never throws on a string holding invalid UTF-8 (such bytes become
/// U+FFFD). indent < 0: one line.
std::string dump_json(const nlohmann::json& j, int indent = -1);
std::string dump_json(const nlohmann::ordered_json& j, int indent = -1);

/// dump_json(j) made safe inside an HTML <script> element: '<', '>' and '&' (which occur only
/// inside JSON strings) written as \u003c, \u003e, \u0026, so that no "</script>" or "<!--"
/// can end or change the element; JSON.parse gives back the same value.
std::string json_for_script(const nlohmann::json& j);

}  // namespace nav::reports
