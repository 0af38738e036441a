// SPDX-License-Identifier: MIT
// The table of every error check's value (campaign_check_values.hpp). Pure.
#include "nav/bench/campaign_check_values.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "nav/bench/runner.hpp"

namespace nav::bench {
namespace {

bool measures_an_error(const std::string& unit) { return unit == "m" || unit == "deg"; }

std::string fixed(double v) {
  if (std::isnan(v)) return "\u2014";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3f", v);
  return buf;
}

}  // namespace

std::vector<CheckValueRow> check_value_rows(
    const std::vector<CampaignCell>& cells,
    const std::vector<std::optional<CampaignResult>>& results) {
  std::vector<CheckValueRow> rows;
  for (const auto& cell : cells) {
    std::vector<std::string> order;
    std::map<std::string, std::pair<std::string, std::vector<double>>> by_check;  // unit, values
    for (const auto& r : results) {
      if (!r || r->scenario != cell.name) continue;
      if (r->exit_code != kExitPass && r->exit_code != kExitFail) continue;  // not to the end
      for (const auto& c : r->checks) {
        if (!measures_an_error(c.unit) || !c.value) continue;
        if (std::find(order.begin(), order.end(), c.name) == order.end()) order.push_back(c.name);
        auto& [unit, values] = by_check[c.name];
        unit = c.unit;
        values.push_back(*c.value);
      }
    }
    for (const auto& name : order) {
      const auto& [unit, values] = by_check[name];
      rows.push_back({cell.name, cell.variant, name, unit, sample_stats(values)});
    }
  }
  return rows;
}

std::string check_value_markdown(const std::vector<CheckValueRow>& rows) {
  if (rows.empty()) return {};
  std::string o =
      "| scenario | variant | check | runs | mean \u00b1 std | min | max |\n"
      "|---|---|---|---:|---:|---:|---:|\n";
  for (const auto& r : rows) {
    const auto& s = r.values;
    o += "| " + r.cell + " | " + (r.variant.empty() ? "\u2014" : r.variant) + " | " + r.check +
         " [" + r.unit + "] | " + std::to_string(s.n) + " | " + fixed(s.mean) + " \u00b1 " +
         fixed(s.stddev) + " | " + fixed(s.min) + " | " + fixed(s.max) + " |\n";
  }
  return o;
}

}  // namespace nav::bench
