// SPDX-License-Identifier: MIT
// Small pieces of report HTML: escaped text, numbers, table rows. Private to nav_reports.
#pragma once

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "nav/reports/text.hpp"

namespace nav::reports::detail {

/// "not recorded", for what an older run folder lacks.
inline const std::string kNotRecorded = "<span class=\"missing\">not recorded</span>";

/// A number with printf's %.{digits}g, or "—" when absent or not finite.
inline std::string num(std::optional<double> v, int digits = 4) {
  if (!v || !std::isfinite(*v)) return "\u2014";
  char b[64];
  std::snprintf(b, sizeof b, "%.*g", digits, *v);
  return b;
}

/// A number with a fixed count of decimals, or "—".
inline std::string fixed(std::optional<double> v, int decimals = 3) {
  if (!v || !std::isfinite(*v)) return "\u2014";
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", decimals, *v);
  // A value that rounds to zero prints as 0.000, not -0.000.
  if (b[0] == '-' && std::string_view(b + 1).find_first_not_of("0.") == std::string_view::npos) {
    return b + 1;
  }
  return b;
}

/// <tr><th>key</th><td>value_html</td></tr>
inline std::string kv_row(const std::string& key, const std::string& value_html) {
  return "<tr><th scope=\"row\">" + html_escape(key) + "</th><td>" + value_html + "</td></tr>\n";
}

/// Escaped text, or "not recorded" when absent.
inline std::string text_or_missing(const std::optional<std::string>& s) {
  return s ? html_escape(*s) : kNotRecorded;
}

/// A header row of a table.
inline std::string header_row(const std::vector<std::string>& names) {
  std::string h = "<tr>";
  for (const auto& n : names) h += "<th scope=\"col\">" + html_escape(n) + "</th>";
  return h + "</tr>\n";
}

/// A row of cells already in HTML; align[i] == 'n' right-aligns cell i as a number (cells
/// past the end of align are text).
inline std::string row(const std::vector<std::string>& cells_html, std::string_view align = {}) {
  std::string h = "<tr>";
  for (std::size_t i = 0; i < cells_html.size(); ++i) {
    h += i < align.size() && align[i] == 'n' ? "<td class=\"n\">" : "<td>";
    h += cells_html[i] + "</td>";
  }
  return h + "</tr>\n";
}

/// An argv as one line of text, each argument quoted when it holds a space or quote.
inline std::string argv_text(const std::vector<std::string>& argv) {
  std::string out;
  for (const auto& a : argv) {
    if (!out.empty()) out += ' ';
    const bool plain = !a.empty() && a.find_first_of(" \t\n'\"\\$`") == std::string::npos;
    if (plain) {
      out += a;
      continue;
    }
    out += '\'';
    for (const char c : a) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    out += '\'';
  }
  return out;
}

}  // namespace nav::reports::detail
