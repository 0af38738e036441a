// SPDX-License-Identifier: MIT
// The campaign report's filter consistency section (campaign_consistency.hpp).
#include "campaign_consistency.hpp"

#include <algorithm>

#include "html_page.hpp"
#include "html_text.hpp"
#include "json_get.hpp"
#include "plot_spec.hpp"

namespace nav::reports::detail {
namespace {

using json = nlohmann::json;

/// One table row per entry of `entries` ("nees" or "nis"), and a plot of each averaged series
/// with its bounds appended to plots.
std::string averaged_table(const json& entries, const std::string& quantity,
                           const std::string& what, json& specs, std::size_t& plot_no,
                           std::string& plots) {
  std::string h = "<table>\n" + header_row({"scenario", what, "runs", "mean " + quantity,
                                            "95 % bounds", "time outside"});
  for (const auto& n : entries) {
    const double runs = get_number(n, "runs", 0);
    const double dof = get_number(n, "dof", 3);
    const json& bounds = member(n, "bounds");
    const bool has = bounds.is_array() && bounds.size() == 2;
    const double outside = get_number(n, "fraction_outside", 0.0);
    const std::string block = get_string(n, "block", "?");
    const std::string block_cell = quantity != "NIS" ? block
                                   : dof > 0         ? block + " (" + num(dof, 10) + " dof)"
                                                     : std::string("\u2014");
    h += row({html_escape(get_string(n, "scenario", "?")), html_escape(block_cell),
              num(runs, 10),
              has ? num(get_number(n, "time_mean"), 4) : html_escape(get_string(n, "text", "")),
              has ? "[" + fixed(bounds[0].get<double>()) + ", " + fixed(bounds[1].get<double>()) +
                        "]"
                  : std::string("\u2014"),
              has ? fixed(100.0 * outside, 0) + " %" : std::string("\u2014")},
             "ttnnnn");
    if (!has) continue;
    json p = plot_frame("plot-" + std::string(quantity == "NIS" ? "nis-" : "nees-") +
                            std::to_string(plot_no++),
                        get_string(n, "scenario", "?") + ": " + block + " " + quantity +
                            ", averaged over " + num(runs, 10) + " runs",
                        "time", "scenario time [s]", quantity + " (" + num(dof, 10) + " dof)",
                        220);
    p["y"]["log"] = true;
    p["series"].push_back(series_json({"mean " + quantity, color::kEstimate}));
    const json& series = member(n, "series");
    p["data"] = json::array({member(series, "t_s"), member(series, "mean")});
    // The bounds in view, however far the average is from them.
    double lo = bounds[0].get<double>(), hi = bounds[1].get<double>();
    for (const auto& v : member(series, "mean")) {
      if (v.is_number() && v.get<double>() > 0.0) {
        lo = std::min(lo, v.get<double>());
        hi = std::max(hi, v.get<double>());
      }
    }
    p["y"]["range"] = log_range(lo, hi);
    p["hlines"] = json::array({{{"y", bounds[0]}, {"label", "2.5 %"}, {"color", color::kLimit}},
                               {{"y", bounds[1]}, {"label", "97.5 %"}, {"color", color::kLimit}}});
    plots += figure_html(p);
    specs.push_back(std::move(p));
  }
  return h + "</table>";
}

}  // namespace

std::string consistency_section(const json& campaign, json& specs, std::size_t& plot_no) {
  const auto& nees = get_array(campaign, "nees");
  const auto& nis = get_array(campaign, "nis");
  if (nees.empty() && nis.empty()) return {};
  std::string h = "<section id=\"consistency\"><h2>Filter consistency</h2>\n";
  std::string plots;
  if (!nees.empty()) {
    h += averaged_table(nees, "NEES", "block", specs, plot_no, plots) +
         "<p class=\"note\">The NEES eᵀP⁻¹e of the covariance the DUT stated with each solution "
         "($PNVBCOV), at each whole second averaged over the runs (each its own seed), against "
         "the two-sided 95 % bounds of a consistent filter, [χ²<sub>3N</sub>(0.025)/N, "
         "χ²<sub>3N</sub>(0.975)/N] for N runs. Above: the DUT claims less uncertainty than it "
         "has; below: more. Reported, not judged.</p>\n";
  }
  if (!nis.empty()) {
    h += averaged_table(nis, "NIS", "measurement", specs, plot_no, plots) +
         "<p class=\"note\">The NIS νᵀS⁻¹ν of each measurement update the DUT stated "
         "($PNVBINN: its innovation ν and the covariance S it predicted for it), per "
         "measurement of m dimensions, at each whole second averaged over the runs, against "
         "[χ²<sub>mN</sub>(0.025)/N, χ²<sub>mN</sub>(0.975)/N]. It needs no truth: above, the "
         "measurements surprise the filter more than it predicts (S too small: too little "
         "process or measurement noise); below, less. Reported, not judged.</p>\n";
  }
  return h + "<div class=\"plots pair\">\n" + plots + "</div></section>\n";
}

}  // namespace nav::reports::detail
