// SPDX-License-Identifier: MIT
// The campaign report: the comparison table, per group of scenarios the distribution of each
// figure over the seeds (empirical CDFs) and the pass rates, and a link to every run's report.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "campaign_consistency.hpp"
#include "campaign_tables.hpp"
#include "html_page.hpp"
#include "html_text.hpp"
#include "json_get.hpp"
#include "nav/reports/html_report.hpp"
#include "plot_spec.hpp"

namespace nav::reports {
namespace {

namespace fs = std::filesystem;
using detail::get_array;
using detail::get_number;
using detail::get_string;
using detail::member;
using json = nlohmann::json;

struct Scenario {
  std::string name;
  std::vector<std::pair<std::string, std::string>> labels;
  std::vector<std::size_t> runs;  ///< indices into campaign.json "runs"
};

std::string label_value(const Scenario& s, const std::string& key) {
  for (const auto& [k, v] : s.labels) {
    if (k == key) return v;
  }
  return {};
}

std::vector<Scenario> scenarios_of(const CampaignFolder& c) {
  std::vector<Scenario> out;
  for (const auto& s : get_array(c.campaign, "scenarios")) {
    Scenario sc{get_string(s, "name", "?"), {}, {}};
    if (const auto& l = member(s, "labels"); l.is_object()) {
      for (const auto& [k, v] : l.items()) sc.labels.emplace_back(k, v.is_string() ? v.get<std::string>() : v.dump());
    }
    out.push_back(std::move(sc));
  }
  const auto& runs = get_array(c.campaign, "runs");
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const std::string name = get_string(runs[i], "scenario", "");
    auto it = std::find_if(out.begin(), out.end(), [&](const Scenario& s) { return s.name == name; });
    if (it == out.end()) {
      out.push_back({name, {}, {}});
      it = out.end() - 1;
    }
    it->runs.push_back(i);
  }
  return out;
}

/// Groups: scenarios that differ only in the last label whose value varies (e.g. the
/// attitude method, grouped by path); one group when at most one label varies.
std::vector<std::pair<std::string, std::vector<std::size_t>>> groups_of(const std::vector<Scenario>& sc) {
  std::vector<std::string> keys;
  for (const auto& s : sc) {
    for (const auto& [k, v] : s.labels) {
      if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
    }
  }
  std::vector<std::string> varying;
  for (const auto& k : keys) {
    std::set<std::string> values;
    for (const auto& s : sc) values.insert(label_value(s, k));
    if (values.size() > 1) varying.push_back(k);
  }
  std::vector<std::pair<std::string, std::vector<std::size_t>>> out;
  for (std::size_t i = 0; i < sc.size(); ++i) {
    std::string title;
    for (std::size_t k = 0; k + 1 < varying.size(); ++k) {
      if (!title.empty()) title += ", ";
      title += varying[k] + " = " + label_value(sc[i], varying[k]);
    }
    if (title.empty()) title = "all scenarios";
    auto it = std::find_if(out.begin(), out.end(), [&](const auto& g) { return g.first == title; });
    if (it == out.end()) out.push_back({title, {i}});
    else it->second.push_back(i);
  }
  return out;
}

/// The figure names (check names with a unit) over a group's runs, in order of appearance.
std::vector<std::pair<std::string, std::string>> figures_of(const CampaignFolder& c,
                                                           const std::vector<Scenario>& sc,
                                                           const std::vector<std::size_t>& group) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto s : group) {
    for (const auto r : sc[s].runs) {
      for (const auto& ch : get_array(c.summaries[r], "checks")) {
        const std::string kind = get_string(ch, "kind").value_or(get_string(ch, "name", ""));
        if (kind == "dut_alive" || !detail::get_bool(ch, "judged").value_or(true)) continue;
        const std::string name = get_string(ch, "name", "");
        if (std::none_of(out.begin(), out.end(), [&](const auto& f) { return f.first == name; })) {
          out.emplace_back(name, get_string(ch, "unit", ""));
        }
      }
    }
  }
  return out;
}

json ecdf_plot(const CampaignFolder& c, const std::vector<Scenario>& sc,
               const std::vector<std::size_t>& group, const std::string& figure,
               const std::string& unit, const std::string& id) {
  json p = detail::plot_frame(id, figure + " over the seeds (empirical CDF)", "xy",
                              figure + (unit.empty() ? "" : " [" + unit + "]"),
                              "fraction of runs \u2264 x", 240);
  p["y"]["range"] = {0.0, 1.0};
  std::size_t colour = 0;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto s : group) {
    std::vector<double> values;
    for (const auto r : sc[s].runs) {
      for (const auto& ch : get_array(c.summaries[r], "checks")) {
        if (get_string(ch, "name", "") != figure) continue;
        if (const auto v = get_number(ch, "value")) values.push_back(*v);
      }
    }
    if (values.empty()) continue;
    std::sort(values.begin(), values.end());
    lo = std::min(lo, values.front());
    hi = std::max(hi, values.back());
    // The steps drawn out: F(x) rises from k/n to (k + 1)/n at the k-th smallest value.
    const auto n = static_cast<double>(values.size());
    std::vector<double> x, y;
    for (std::size_t k = 0; k < values.size(); ++k) {
      x.insert(x.end(), {values[k], values[k]});
      y.insert(y.end(), {static_cast<double>(k) / n, static_cast<double>(k + 1) / n});
    }
    p["series"].push_back(detail::series_json({sc[s].name + " (" + std::to_string(values.size()) + ")",
                                               detail::color::cycle(colour++), "linear", 2.0}));
    p["data"].push_back(json::array({detail::numbers(x, 7), detail::numbers(y, 7)}));
  }
  if (hi >= lo) {  // room either side, so the first and last steps show
    const double pad = hi > lo ? 0.05 * (hi - lo) : std::max(0.05 * std::abs(lo), 1e-6);
    p["x"]["range"] = {lo - pad, hi + pad};
  }
  return p;
}

std::string banner(const CampaignFolder& c, std::size_t runs, std::size_t passed) {
  const int code = static_cast<int>(get_number(c.campaign, "exit_code", -1));
  std::string cls = "pass", verdict = "ALL PASSED";
  if (code == 1) cls = "fail", verdict = "CHECKS FAILED";
  else if (code == 3 || code == 4 || code == 2) cls = "dut", verdict = "RUNS IN ERROR";
  else if (code != 0) cls = "interrupted", verdict = "INCOMPLETE";
  std::string h = "<header class=\"banner " + cls + "\" id=\"verdict\"><div class=\"verdict\">" +
                  verdict + "</div><div class=\"what\">campaign &middot; ";
  if (const auto& checks = get_array(c.campaign, "campaign_checks"); !checks.empty()) {
    const auto shown = std::count_if(checks.begin(), checks.end(), [](const json& v) {
      return detail::get_bool(v, "passed").value_or(false);
    });
    h += std::to_string(shown) + " of " + std::to_string(checks.size()) +
         " campaign checks shown &middot; ";
  }
  if (const auto& pairs = get_array(c.campaign, "paired_comparisons"); !pairs.empty()) {
    const auto worse = std::count_if(pairs.begin(), pairs.end(), [](const json& p) {
      return detail::get_bool(p, "worse").value_or(false);
    });
    h += std::to_string(worse) + " of " + std::to_string(pairs.size()) +
         " variant comparisons worse &middot; ";
  }
  h += std::to_string(passed) + " of " + std::to_string(runs) + " runs passed &middot; exit code " +
       std::to_string(code) + "</div>";
  if (!detail::get_bool(c.campaign, "complete").value_or(true)) {
    h += "<ul class=\"why\"><li>interrupted: the table is over the runs that finished</li></ul>";
  }
  return h + "</header>\n";
}

std::string identity(const CampaignFolder& c) {
  const json& j = c.campaign;
  const json& seeds = member(j, "seeds");
  std::string h = "<section id=\"identity\"><h2>Campaign</h2><table class=\"kv\">\n";
  h += detail::kv_row("Command", "<code>" + html_escape(get_string(j, "command_line", "")) + "</code>");
  h += detail::kv_row("Seeds", detail::num(get_number(seeds, "first"), 20) + " \u2013 " +
                                   detail::num(get_number(seeds, "last"), 20) + " (" +
                                   detail::num(get_number(seeds, "count"), 20) + " per scenario)");
  h += detail::kv_row("Mode", detail::text_or_missing(get_string(j, "mode")));
  h += detail::kv_row("Jobs", detail::num(get_number(j, "jobs"), 10));
  h += detail::kv_row("Started (UTC)", detail::text_or_missing(get_string(j, "started_utc")));
  h += detail::kv_row("Wall time", detail::fixed(get_number(j, "wall_time_s"), 1) + " s");
  h += detail::kv_row("navbench version", detail::text_or_missing(get_string(j, "navbench_version")));
  h += detail::kv_row("Host", detail::text_or_missing(get_string(member(j, "host"), "name")));
  return h + "</table></section>\n";
}

std::string comparison(const CampaignFolder& c) {
  const auto& rows = get_array(c.campaign, "comparison");
  std::vector<std::string> keys;
  for (const auto& r : rows) {
    if (const auto& l = member(r, "labels"); l.is_object()) {
      for (const auto& [k, v] : l.items()) {
        if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
      }
    }
  }
  std::vector<std::string> head = keys;
  for (const char* h : {"scenario", "runs", "passed", "endpoint error mean \u00b1 std [m]",
                        "min [m]", "max [m]", "horizontal [m]", "vertical [m]",
                        "mean position error [m]", "mean attitude error [deg]"}) {
    head.emplace_back(h);
  }
  const auto mean_std = [](const json& e) {
    std::string ms = detail::fixed(get_number(e, "mean"));
    if (get_number(e, "std")) ms += " \u00b1 " + detail::fixed(get_number(e, "std"));
    return ms;
  };
  // Nine figure columns after the labels: the table scrolls sideways on a narrow page.
  std::string h = "<section id=\"comparison\"><h2>Comparison</h2><div class=\"scroll\"><table>\n" +
                  detail::header_row(head);
  for (const auto& r : rows) {
    std::vector<std::string> cells;
    for (const auto& k : keys) cells.push_back(html_escape(get_string(member(r, "labels"), k.c_str(), "")));
    const json& e = member(r, "endpoint_error_m");
    cells.push_back(html_escape(get_string(r, "scenario", "?")));
    cells.push_back(detail::num(get_number(r, "runs"), 10));
    cells.push_back(detail::num(get_number(r, "passed"), 10));
    cells.push_back(mean_std(e));
    cells.push_back(detail::fixed(get_number(e, "min")));
    cells.push_back(detail::fixed(get_number(e, "max")));
    for (const char* figure : {"endpoint_horizontal_m", "endpoint_vertical_m",
                               "mean_position_error_m", "mean_attitude_error_deg"}) {
      cells.push_back(mean_std(member(r, figure)));
    }
    h += detail::row(cells, std::string(keys.size() + 1, 't') + "nnnnnnnnn");
  }
  return h + "</table></div><p class=\"note\">Endpoint error: the value of each scenario's "
             "endpoint_error check; horizontal and vertical: the parts of the final "
             "solution's error; mean position and attitude errors: averaged over each run's "
             "solutions (the time average). All over the runs that reached the end (exit 0 or "
             "1); std is the sample standard deviation.</p></section>\n";
}

/// The campaign's own checks: statements over each scenario's runs, with what the runs show.
std::string campaign_checks(const CampaignFolder& c) {
  const auto& checks = get_array(c.campaign, "campaign_checks");
  if (checks.empty()) return {};
  std::string h = "<section id=\"campaign-checks\"><h2>Campaign checks</h2><table>\n" +
                  detail::header_row({"verdict", "scenario", "requirement", "statement",
                                      "what the runs show"});
  for (const auto& v : checks) {
    const bool passed = detail::get_bool(v, "passed").value_or(false);
    const json& check = member(v, "check");
    std::string req = html_escape(get_string(check, "req", ""));
    if (const auto title = get_string(check, "title")) req += (req.empty() ? "" : ": ") + html_escape(*title);
    h += "<tr class=\"" + std::string(passed ? "pass" : "fail") + "\">";
    h += "<td class=\"tag\">" + std::string(passed ? "PASS" : "FAIL") + "</td>";
    h += "<td>" + html_escape(get_string(v, "scenario", "?")) + "</td>";
    h += "<td>" + (req.empty() ? std::string("\u2014") : req) + "</td>";
    h += "<td>" + html_escape(get_string(v, "statement", "")) + "</td>";
    h += "<td>" + html_escape(get_string(v, "finding", "")) + "</td></tr>\n";
  }
  return h + "</table><p class=\"note\">Decided without assuming a distribution: a quantile "
             "statement by order statistics (it holds with confidence P(Binomial(n, q) \u2264 "
             "n \u2212 j \u2212 1) when j of n runs are above its limit), a pass rate by its "
             "one-sided Clopper\u2013Pearson bound. A run whose DUT measured nothing, crashed "
             "or hung counts against them; a run in bench error is left out. Where campaign "
             "checks are given, they decide the scenario's verdict, not each run's own checks."
             "</p></section>\n";
}

/// DUT variants against the baseline, pair by seed.
std::string paired_comparisons(const CampaignFolder& c) {
  const auto& pairs = get_array(c.campaign, "paired_comparisons");
  if (pairs.empty()) return {};
  std::string h = "<section id=\"variants\"><h2>Variants paired by seed</h2><table>\n" +
                  detail::header_row({"finding", "scenario", "candidate", "baseline", "figure",
                                      "median paired difference", "one-sided p", "pairs"});
  for (const auto& p : pairs) {
    const bool worse = detail::get_bool(p, "worse").value_or(false);
    const std::string finding = get_string(p, "finding", "");
    const double p_value = finding == "better" ? get_number(p, "p_better", 1.0)
                                               : get_number(p, "p_worse", 1.0);
    const std::string unit = get_string(p, "unit", "");
    h += "<tr class=\"" + std::string(worse ? "fail" : "pass") + "\">";
    h += "<td class=\"tag\">" + html_escape(finding) + "</td>";
    h += "<td>" + html_escape(get_string(p, "scenario", "?")) + "</td>";
    h += "<td>" + html_escape(get_string(p, "candidate", "?")) + "</td>";
    h += "<td>" + html_escape(get_string(p, "baseline", "?")) + "</td>";
    h += "<td>" + html_escape(get_string(p, "figure", "?")) + "</td>";
    h += "<td class=\"n\">" + detail::fixed(get_number(p, "median_difference")) +
         (unit.empty() ? "" : " " + html_escape(unit)) + "</td>";
    h += "<td class=\"n\">" + detail::fixed(p_value, 4) + "</td>";
    h += "<td class=\"n\">" + detail::num(get_number(p, "pairs"), 10) + "</td></tr>\n";
  }
  return h + "</table><p class=\"note\">Each variant against the baseline (the first "
             "--variant) on the same scenario and seeds: same truth and sensor data, so the runs "
             "pair by seed. Wilcoxon's signed-rank test of the differences (candidate minus "
             "baseline), one-sided: worse (or better) when p &lt; 0.05; differences below 0.0005 "
             "in the figure's unit (printed 0.000) are ties. A run whose DUT measured "
             "nothing, crashed or hung counts as an infinite error; a worse candidate makes the "
             "campaign exit 1.</p></section>\n";
}

std::string runs_table(const CampaignFolder& c) {
  const auto& runs = get_array(c.campaign, "runs");
  std::string h = "<section id=\"runs\"><h2>Runs</h2><table>\n" +
                  detail::header_row({"scenario", "seed", "verdict", "exit", "endpoint error [m]",
                                      "wall [s]", "report"});
  for (const auto& r : runs) {
    const std::string folder = get_string(r, "run_folder", "");
    std::string link = "\u2014";
    std::error_code ec;
    if (!folder.empty() && fs::exists(fs::path(c.dir) / folder / "report.html", ec)) {
      link = "<a href=\"" + html_escape(folder + "/report.html") + "\">report</a>";
    } else if (!folder.empty() && fs::exists(fs::path(c.dir) / folder, ec)) {
      link = "<a href=\"" + html_escape(folder + "/") + "\">folder</a>";
    }
    const std::string verdict = get_string(r, "verdict", get_string(r, "status", ""));
    h += "<tr class=\"" + std::string(verdict == "PASS" ? "pass" : "fail") + "\">";
    h += "<td>" + html_escape(get_string(r, "scenario", "?")) + "</td>";
    h += "<td class=\"n\">" + html_escape(member(r, "seed").dump()) + "</td>";
    h += "<td class=\"tag\">" + html_escape(verdict) + "</td>";
    h += "<td class=\"n\">" + detail::num(get_number(r, "exit_code"), 4) + "</td>";
    h += "<td class=\"n\">" + detail::fixed(get_number(r, "endpoint_error_m")) + "</td>";
    h += "<td class=\"n\">" + detail::fixed(get_number(r, "wall_time_s"), 1) + "</td>";
    h += "<td>" + link + "</td></tr>\n";
  }
  return h + "</table></section>\n";
}

}  // namespace

Result<CampaignFolder> read_campaign_folder(const std::string& dir) {
  CampaignFolder c;
  c.dir = dir;
  const fs::path path = fs::path(dir) / "campaign.json";
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail(ErrorCode::kNotFound, dir + ": not a campaign folder (no campaign.json)");
  std::ostringstream text;
  text << in.rdbuf();
  c.campaign = json::parse(text.str(), nullptr, false);
  if (c.campaign.is_discarded() || !c.campaign.is_object() || !member(c.campaign, "runs").is_array()) {
    return fail(ErrorCode::kParse, path.string() + ": not a navbench campaign.json (damaged, or no \"runs\")");
  }
  for (const auto& r : get_array(c.campaign, "runs")) {
    json summary;
    const std::string folder = get_string(r, "run_folder", "");
    std::ifstream s(fs::path(dir) / folder / "summary.json", std::ios::binary);
    if (!folder.empty() && s) {
      std::ostringstream t;
      t << s.rdbuf();
      summary = json::parse(t.str(), nullptr, false);
      if (summary.is_discarded()) summary = nullptr;
    }
    c.summaries.push_back(std::move(summary));
  }
  return c;
}

std::string campaign_report_html(const CampaignFolder& c) {
  const auto sc = scenarios_of(c);
  std::size_t runs = 0, passed = 0;
  for (const auto& r : get_array(c.campaign, "runs")) {
    ++runs;
    passed += get_number(r, "exit_code", -1) == 0 ? 1 : 0;
  }
  json specs = json::array();
  std::string body = banner(c, runs, passed);
  const std::string checks = campaign_checks(c);
  body += "<nav class=\"toc\"><a href=\"#identity\">campaign</a> ";
  const std::string pairs = paired_comparisons(c);
  if (!checks.empty()) body += "<a href=\"#campaign-checks\">campaign checks</a> ";
  if (!pairs.empty()) body += "<a href=\"#variants\">variants</a> ";
  body += "<a href=\"#comparison\">comparison</a> ";
  const std::string vehicles = detail::vehicles_table(c.campaign);
  const std::string values = detail::check_values_table(c.campaign);
  if (!vehicles.empty()) body += "<a href=\"#vehicles\">every vehicle</a> ";
  if (!values.empty()) body += "<a href=\"#check-values\">check values</a> ";
  body += "<a href=\"#distributions\">distributions</a> ";
  if (!get_array(c.campaign, "nees").empty() || !get_array(c.campaign, "nis").empty()) {
    body += "<a href=\"#consistency\">consistency</a> ";
  }
  body += "<a href=\"#runs\">runs</a></nav>\n<main>\n";
  body += identity(c) + checks + pairs + comparison(c) + vehicles + values;
  body += "<section id=\"distributions\"><h2>Distributions over the seeds</h2>\n";
  std::size_t plot_no = 0;
  for (const auto& [title, group] : groups_of(sc)) {
    body += "<h3>" + html_escape(title) + "</h3>\n<table>\n" +
            detail::header_row({"scenario", "runs", "passed", "pass rate"});
    for (const auto s : group) {
      std::size_t n = 0, ok = 0;
      for (const auto r : sc[s].runs) {
        const auto& run = get_array(c.campaign, "runs")[r];
        if (get_string(run, "status", "") != "finished") continue;
        ++n;
        ok += get_number(run, "exit_code", -1) == 0 ? 1 : 0;
      }
      body += detail::row({html_escape(sc[s].name), std::to_string(n), std::to_string(ok),
                           n ? detail::fixed(100.0 * static_cast<double>(ok) / static_cast<double>(n), 1) + " %"
                             : std::string("\u2014")},
                           "tnnn");
    }
    body += "</table>\n<div class=\"plots pair\">\n";
    for (const auto& [figure, unit] : figures_of(c, sc, group)) {
      json p = ecdf_plot(c, sc, group, figure, unit, "plot-ecdf-" + std::to_string(plot_no++));
      body += detail::figure_html(p);
      specs.push_back(std::move(p));
    }
    body += "</div>\n";
  }
  body += "</section>\n" + detail::consistency_section(c.campaign, specs, plot_no) + runs_table(c) +
          "</main>\n";
  return detail::render_page({"navbench campaign", body, specs});
}

}  // namespace nav::reports
