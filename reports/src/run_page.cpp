// SPDX-License-Identifier: MIT
// The run report: verdict banner, identity, checks, plots, tables and the DUT log's tail,
// from a run folder's files alone.
#include <ctime>

#include "html_page.hpp"
#include "html_text.hpp"
#include "json_get.hpp"
#include "nav/reports/html_report.hpp"
#include "nav/reports/run_record.hpp"
#include "run_plots.hpp"

namespace nav::reports {
namespace {

using detail::get_array;
using detail::get_number;
using detail::get_string;
using detail::fixed;
using detail::member;
using detail::num;
using json = nlohmann::json;

std::string verdict_class(const std::string& verdict) {
  if (verdict == "PASS") return "pass";
  if (verdict == "FAIL") return "fail";
  if (verdict == "BENCH-LATE") return "late";
  if (verdict == "INTERRUPTED") return "interrupted";
  return "dut";  // DUT crashed, DUT hung
}

std::vector<std::string> strings(const json& a) {
  std::vector<std::string> out;
  if (!a.is_array()) return out;
  for (const auto& s : a) out.push_back(s.is_string() ? s.get<std::string>() : s.dump());
  return out;
}

/// "name [req]" of a check, escaped.
std::string check_label(const json& c) {
  std::string h = "<code>" + html_escape(get_string(c, "name", "?")) + "</code>";
  if (const auto req = get_string(c, "req")) h += " <span class=\"req\">" + html_escape(*req) + "</span>";
  return h;
}

std::string banner(const RunFolder& f) {
  const json& s = f.summary;
  const std::string verdict = get_string(s, "verdict", "?");
  const json& sc = member(s, "scenario");
  std::string h = "<header class=\"banner " + verdict_class(verdict) + "\" id=\"verdict\">\n";
  h += "<div class=\"verdict\">" + html_escape(verdict) + "</div>\n<div class=\"what\">";
  h += html_escape(get_string(sc, "name", "?"));
  if (const auto seed = member(s, "seed"); seed.is_number()) h += " &middot; seed " + html_escape(seed.dump());
  h += " &middot; " + html_escape(get_string(s, "mode", "?"));
  if (const auto code = get_number(s, "exit_code")) h += " &middot; exit code " + num(*code);
  h += "</div>\n<ul class=\"why\">";
  std::size_t lines = 0;
  for (const auto& c : get_array(s, "checks")) {
    if (detail::get_bool(c, "judged").value_or(true) && !detail::get_bool(c, "passed").value_or(false)) {
      h += "<li>" + check_label(c) + ": " + html_escape(get_string(c, "detail", "failed")) + "</li>";
      ++lines;
    }
  }
  const std::string dut_status = get_string(member(s, "dut"), "status", "");
  if (verdict == "DUT crashed" || verdict == "DUT hung") {
    h += "<li>DUT: " + html_escape(dut_status) + "</li>";
    ++lines;
  }
  if (verdict == "BENCH-LATE") {
    const json& bl = member(s, "bench_lateness");
    const bool median = get_string(bl, "judged", "p99") == "p50";
    h += "<li>bench lateness " + std::string(median ? "median " : "p99 ") +
         fixed(get_number(bl, median ? "p50_ms" : "p99_ms")) + " ms over its budget of " +
         fixed(get_number(bl, "budget_p99_ms")) + " ms" +
         (median ? " (fewer than " + std::to_string(kMinMessagesForP99) +
                       " messages: the median judged)"
                 : std::string()) +
         ": the bench, not the DUT, was late</li>";
    ++lines;
  }
  for (const auto& n : strings(member(s, "notes"))) {
    h += "<li>" + html_escape(n) + "</li>";
    ++lines;
  }
  // Not the verdict, but what the reader must not miss beside it.
  std::string asides;
  if (const auto bad = get_number(member(s, "dut"), "malformed_output"); bad && *bad > 0) {
    asides += "<li>the DUT wrote " + num(*bad, 10) +
              " malformed lines (the first ones: <a href=\"#timing\">Timing</a>)</li>";
  }
  for (const auto& c : get_array(s, "logs_cut")) {
    asides += "<li>" + html_escape(get_string(c, "file", "?")) +
              " was cut at its limit (<a href=\"#timing\">Timing</a>)</li>";
  }
  if (verdict == "INTERRUPTED") {
    const auto at = get_number(s, "stopped_at_s");
    h += "<li>stopped by a signal (SIGINT or SIGTERM) " +
         (at ? "at t=" + fixed(at, 2) + " s of " + fixed(get_number(s, "duration_s"), 1) + " s"
             : std::string("before the end of the scenario")) +
         "; checks that need the rest of the run are not judged</li>";
    ++lines;
  }
  if (lines == 0) h += "<li>every judged check passed</li>";
  return h + asides + "</ul>\n</header>\n";
}

std::string sha_html(const json& holder) {
  const auto sha = get_string(holder, "sha256");
  return sha ? "<code class=\"sha\">" + html_escape(*sha) + "</code>" : detail::kNotRecorded;
}

std::string identity(const RunFolder& f) {
  const json& s = f.summary;
  const json& sc = member(s, "scenario");
  const json& dut = member(s, "dut");
  const json& host = member(s, "host");
  std::string labels;
  if (const auto& l = member(s, "labels"); l.is_object()) {
    for (const auto& [k, v] : l.items()) {
      if (!labels.empty()) labels += ", ";
      labels += html_escape(k) + " = " + html_escape(v.is_string() ? v.get<std::string>() : v.dump());
    }
  }
  std::string h = "<section id=\"identity\"><h2>Identity</h2><table class=\"kv\">\n";
  h += detail::kv_row("Scenario", "<strong>" + html_escape(get_string(sc, "name", "?")) + "</strong>");
  if (const auto d = get_string(sc, "description"); d && !d->empty()) {
    h += detail::kv_row("Description", html_escape(*d));
  }
  if (!labels.empty()) h += detail::kv_row("Labels", labels);
  h += detail::kv_row("Scenario file", detail::text_or_missing(get_string(sc, "file")));
  h += detail::kv_row("Scenario SHA-256", sha_html(sc));
  const auto seed = member(s, "seed");
  h += detail::kv_row("Seed", seed.is_number() ? html_escape(seed.dump()) : detail::kNotRecorded);
  h += detail::kv_row("Mode", detail::text_or_missing(get_string(s, "mode")));
  h += detail::kv_row("Started (UTC)", detail::text_or_missing(get_string(s, "started_utc")));
  h += detail::kv_row("Duration", fixed(get_number(s, "duration_s"), 1) + " s scenario time, " +
                                      fixed(get_number(s, "wall_time_s"), 1) + " s wall time");
  if (const auto cpu = get_number(s, "bench_cpu_s")) {
    const auto wall = get_number(s, "wall_time_s").value_or(0.0);
    h += detail::kv_row("Bench CPU", fixed(*cpu, 1) + " s (" +
                                         (wall > 0 ? fixed(100.0 * *cpu / wall, 1) : std::string("?")) +
                                         " % of one core; its DUTs not counted)");
  }
  h += detail::kv_row("navbench version",
                      detail::text_or_missing(get_string(member(s, "versions"), "navbench")));
  const auto argv = strings(member(dut, "command"));
  h += detail::kv_row("DUT command", argv.empty() ? detail::kNotRecorded
                                                  : "<code>" + html_escape(detail::argv_text(argv)) + "</code>");
  h += detail::kv_row("DUT executable", detail::text_or_missing(get_string(dut, "executable")));
  h += detail::kv_row("DUT SHA-256", sha_html(dut));
  // The files its arguments name (its configuration), each with its SHA-256.
  for (const auto& file : get_array(dut, "files")) {
    h += detail::kv_row("DUT file", detail::text_or_missing(get_string(file, "path")) + "<br>" +
                                        sha_html(file));
  }
  h += detail::kv_row("DUT status", detail::text_or_missing(get_string(dut, "status")));
  h += detail::kv_row("Host", detail::text_or_missing(get_string(host, "name")));
  h += detail::kv_row("Kernel", detail::text_or_missing(get_string(host, "kernel")));
  return h + "</table></section>\n";
}

std::string limit_text(const json& c) {
  const std::string unit = get_string(c, "unit", "");
  const std::string kind = get_string(c, "kind").value_or(get_string(c, "name", ""));
  if (kind == "dut_alive") return "alive to the end";
  if (kind == "consistency") {  // two-sided: the summary keeps the upper bound
    if (!detail::get_bool(c, "judged").value_or(true)) return "\u2014";
    std::string t = "within its 95 % bounds (upper " + num(get_number(c, "limit")) + ")";
    const double after = get_number(c, "after_s", 0.0);
    if (after > 0) t += ", from t = " + num(after) + " s";
    return t;
  }
  if (kind == "deadline") {
    std::string t = "\u2264 " + num(get_number(c, "limit")) + " misses";
    if (const auto ms = get_number(c, "max_latency_ms")) t += " over " + num(*ms) + " ms";
    return t;
  }
  std::string t = "\u2264 " + num(get_number(c, "limit")) + " " + unit;
  const double per = get_number(c, "per_distance", 0.0);
  if (per > 0) t += " + " + num(per * 100.0) + " % of distance";
  const double after = get_number(c, "after_s", 0.0);
  if (after > 0) t += ", from t = " + num(after) + " s";
  return t;
}

std::string checks(const RunFolder& f, const detail::RunPlots& plots) {
  const auto& list = get_array(f.summary, "checks");
  std::string h = "<section id=\"checks\"><h2>Checks</h2>\n";
  if (list.empty()) return h + "<p>The scenario has no checks.</p></section>\n";
  h += "<table class=\"checks\">\n" +
       detail::header_row({"check", "requirement", "figure", "limit", "verdict", "worst at", "plot"});
  for (const auto& c : list) {
    const bool judged = detail::get_bool(c, "judged").value_or(true);
    const bool passed = detail::get_bool(c, "passed").value_or(false);
    const std::string tag = !judged ? "SKIP" : passed ? "PASS" : "FAIL";
    std::string req = html_escape(get_string(c, "req", ""));
    if (const auto title = get_string(c, "title")) req += (req.empty() ? "" : "<br>") + html_escape(*title);
    const std::string name = get_string(c, "name", "");
    const auto anchor = plots.check_anchor.find(name);
    const std::string kind = get_string(c, "kind").value_or(name);
    std::string link = "\u2014";
    if (anchor != plots.check_anchor.end()) {
      link = "<a href=\"#" + html_escape(anchor->second) + "\">plot</a>";
    } else if (kind == "dut_alive" && !detail::of_peer(f.summary, c)) {
      link = "<a href=\"#dut-log\">DUT log</a>";  // the primary's (a peer's is dut-<name>.log)
    }
    const auto worst = get_number(c, "worst_t_s");
    h += "<tr class=\"" + std::string(!judged ? "skip" : passed ? "pass" : "fail") + "\">";
    h += "<td><code>" + html_escape(name) + "</code><div class=\"detail\">" + html_escape(get_string(c, "detail", "")) + "</div></td>";
    h += "<td>" + req + "</td>";
    const bool no_figure = !judged && kind == "consistency";  // nothing stated: no figure
    h += "<td class=\"n\">" +
         (no_figure ? std::string("\u2014")
                    : num(get_number(c, "value")) + " " + html_escape(get_string(c, "unit", ""))) +
         "</td>";
    h += "<td>" + html_escape(limit_text(c)) + "</td>";
    h += "<td class=\"tag\">" + tag + "</td>";
    h += "<td class=\"n\">" + (worst ? "t = " + fixed(*worst, 2) + " s" : std::string("\u2014")) + "</td>";
    h += "<td>" + link + "</td></tr>\n";
  }
  return h + "</table></section>\n";
}

std::string plot_sections(const detail::RunPlots& plots) {
  std::string h;
  for (const auto& s : plots.sections) {
    h += "<section id=\"" + html_escape(s.id) + "\"><h2>" + html_escape(s.title) + "</h2>\n";
    if (s.plots.empty()) {
      h += "<p class=\"note\">" + html_escape(s.empty_note) + "</p>";
    } else {
      h += std::string("<div class=\"") + (s.side_by_side ? "plots pair" : "plots") + "\">\n";
      for (const auto& p : s.plots) h += detail::figure_html(p);
      h += "</div>";
    }
    h += "</section>\n";
  }
  return h;
}

}  // namespace

// Tables (devices, links, vehicles, timing) and the log: run_tables_html.cpp.
namespace detail {
std::string run_tables_html(const RunFolder& f);
}

std::string run_report_html(const RunFolder& f) {
  const detail::RunPlots plots = detail::run_plots(f);
  json specs = json::array();
  for (const auto& s : plots.sections) {
    for (const auto& p : s.plots) specs.push_back(p);
  }
  std::string body = banner(f);
  body += "<nav class=\"toc\"><a href=\"#identity\">identity</a> <a href=\"#checks\">checks</a>";
  for (const auto& s : plots.sections) {
    body += " <a href=\"#" + html_escape(s.id) + "\">" + html_escape(s.id) + "</a>";
  }
  body += " <a href=\"#devices\">devices</a> <a href=\"#dut-log\">DUT log</a></nav>\n<main>\n";
  body += identity(f);
  body += checks(f, plots);
  body += plot_sections(plots);
  body += detail::run_tables_html(f);
  body += "</main>\n";
  const json& s = f.summary;
  return detail::render_page({"navbench " + get_string(member(s, "scenario"), "name", "?") + ": " +
                                  get_string(s, "verdict", "?"),
                              body, specs});
}

}  // namespace nav::reports
