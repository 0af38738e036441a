// SPDX-License-Identifier: MIT
// The campaign report's tables of campaign_tables.hpp.
#include "campaign_tables.hpp"

#include <cstdio>

#include "html_page.hpp"
#include "html_text.hpp"
#include "json_get.hpp"

namespace nav::reports::detail {

using json = nlohmann::json;

std::string vehicles_table(const nlohmann::json& campaign) {
  const auto& rows = get_array(campaign, "vehicles");
  if (rows.empty()) return {};
  std::string h = "<section id=\"vehicles\"><h2>Every vehicle</h2><div class=\"scroll\"><table>\n" +
                  header_row({"scenario", "variant", "vehicle", "runs",
                                      "mean position error mean \u00b1 std [m]",
                                      "improvement over the baseline"});
  for (const auto& r : rows) {
    const json& e = member(r, "mean_position_error_m");
    std::string mean_std = fixed(get_number(e, "mean"));
    if (get_number(e, "std")) mean_std += " \u00b1 " + fixed(get_number(e, "std"));
    const std::string vehicle = get_string(r, "vehicle", "?");
    std::string improvement = "\u2014";
    if (const auto pct = get_number(r, "improvement_pct")) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%+.1f %%", *pct);
      improvement = std::string(buf) + " (vs " + html_escape(get_string(r, "baseline", "?")) + ")";
    }
    h += row({html_escape(get_string(r, "scenario", "?")),
                      html_escape(get_string(r, "variant", "\u2014")),
                      vehicle == "all" ? std::string("<b>all</b> (mean)") : html_escape(vehicle),
                      num(get_number(e, "n"), 10), mean_std, improvement},
                     "tttnnn");
  }
  return h + "</table></div><p class=\"note\">Each vehicle's time-averaged 3-D position error "
             "over the runs that reached the end; <b>all</b>: per run the mean over its "
             "vehicles. Improvement: 100 (b \u2212 m) / b against the same vehicle in the "
             "first variant's cell (positive is better).</p></section>\n";
}

std::string check_values_table(const nlohmann::json& campaign) {
  const auto& rows = get_array(campaign, "check_values");
  if (rows.empty()) return {};
  std::string h =
      "<section id=\"check-values\"><h2>Every error check's value</h2><div class=\"scroll\">"
      "<table>\n" +
      header_row({"scenario", "variant", "check", "runs", "mean \u00b1 std", "min", "max"});
  for (const auto& r : rows) {
    const nlohmann::json& v = member(r, "values");
    std::string mean_std = fixed(get_number(v, "mean"));
    if (get_number(v, "std")) mean_std += " \u00b1 " + fixed(get_number(v, "std"));
    h += row({html_escape(get_string(r, "scenario", "?")),
              html_escape(get_string(r, "variant", "\u2014")),
              html_escape(get_string(r, "check", "?")) + " [" +
                  html_escape(get_string(r, "unit", "?")) + "]",
              num(get_number(v, "n"), 10), mean_std, fixed(get_number(v, "min")),
              fixed(get_number(v, "max"))},
             "tttnnnn");
  }
  return h + "</table></div><p class=\"note\">The value each check measured (its largest "
             "error in a run; the end-point error; the error at its time), over the runs that "
             "reached the end (exit 0 or 1); std is the sample standard deviation.</p>"
             "</section>\n";
}

}  // namespace nav::reports::detail
