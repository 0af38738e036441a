// SPDX-License-Identifier: MIT
// The pure parts of `navbench campaign`: statistics, comparison rows, CSV and markdown.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <string_view>

#include "nav/bench/campaign.hpp"
#include "nav/bench/runner.hpp"

namespace nav::bench {
namespace {

/// "%.3f", or `undefined` for NaN.
std::string metres(double v, const std::string& undefined) {
  if (std::isnan(v)) return undefined;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3f", v);
  return buf;
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string o = "\"";
  for (const char c : s) {
    if (c == '"') o += '"';
    o += c;
  }
  return o + "\"";
}

std::string md_cell(const std::string& s) {
  std::string o;
  for (const char c : s) {
    if (c == '|' || c == '\\') o += '\\';
    o += c;
  }
  return o;
}

std::string label_value(const Labels& labels, const std::string& name) {
  for (const auto& [k, v] : labels) {
    if (k == name) return v;
  }
  return {};
}

int severity(int code) {
  switch (code) {
    case kExitPass: return 0;
    case kExitFail: return 1;
    case kExitDut: return 3;
    default: return 2;  // bench error, and anything unexpected
  }
}

}  // namespace

SampleStats sample_stats(const std::vector<double>& values) {
  SampleStats s;
  s.n = values.size();
  if (values.empty()) return s;
  double sum = 0.0;
  for (const double v : values) sum += v;
  s.mean = sum / static_cast<double>(s.n);
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  s.min = *lo;
  s.max = *hi;
  if (s.n >= 2) {
    double ss = 0.0;
    for (const double v : values) ss += (v - s.mean) * (v - s.mean);
    s.stddev = std::sqrt(ss / static_cast<double>(s.n - 1));
  }
  return s;
}

std::vector<ComparisonRow> comparison_rows(
    const std::vector<std::pair<std::string, Labels>>& scenarios,
    const std::vector<CampaignRun>& runs) {
  std::vector<ComparisonRow> rows;
  for (const auto& [name, labels] : scenarios) {
    ComparisonRow row;
    row.scenario = name;
    row.labels = labels;
    std::vector<double> values, horizontal, vertical, position, attitude;
    const auto add = [](std::vector<double>& to, const std::optional<double>& v) {
      if (v) to.push_back(*v);
    };
    for (const auto& r : runs) {
      if (r.scenario != name || !r.finished) continue;
      ++row.runs;
      if (r.exit_code == kExitPass) ++row.passed;
      // Runs that crashed, hung or were cut short did not reach the end: no endpoint.
      const bool reached_end = r.exit_code == kExitPass || r.exit_code == kExitFail;
      if (!reached_end) continue;
      add(values, r.endpoint_error_m);
      add(horizontal, r.figures.endpoint_horizontal_m);
      add(vertical, r.figures.endpoint_vertical_m);
      add(position, r.figures.mean_position_m);
      add(attitude, r.figures.mean_attitude_deg);
    }
    row.endpoint = sample_stats(values);
    row.endpoint_horizontal = sample_stats(horizontal);
    row.endpoint_vertical = sample_stats(vertical);
    row.mean_position = sample_stats(position);
    row.mean_attitude = sample_stats(attitude);
    rows.push_back(std::move(row));
  }
  return rows;
}

std::vector<std::string> label_columns(const std::vector<ComparisonRow>& rows) {
  std::vector<std::string> names;
  for (const auto& row : rows) {
    for (const auto& [k, v] : row.labels) {
      if (std::find(names.begin(), names.end(), k) == names.end()) names.push_back(k);
    }
  }
  return names;
}

std::string comparison_csv(const std::vector<ComparisonRow>& rows) {
  const auto labels = label_columns(rows);
  std::string o;
  for (const auto& l : labels) o += csv_field(l) + ",";
  o += "scenario,runs,passed,endpoint_error_mean_m,endpoint_error_std_m,endpoint_error_min_m,"
       "endpoint_error_max_m,endpoint_horizontal_mean_m,endpoint_horizontal_std_m,"
       "endpoint_vertical_mean_m,endpoint_vertical_std_m,mean_position_error_mean_m,"
       "mean_position_error_std_m,mean_attitude_error_mean_deg,mean_attitude_error_std_deg\n";
  for (const auto& row : rows) {
    for (const auto& l : labels) o += csv_field(label_value(row.labels, l)) + ",";
    const auto& e = row.endpoint;
    o += csv_field(row.scenario) + "," + std::to_string(row.runs) + "," +
         std::to_string(row.passed) + "," + metres(e.mean, "") + "," + metres(e.stddev, "") +
         "," + metres(e.min, "") + "," + metres(e.max, "");
    for (const SampleStats* f : {&row.endpoint_horizontal, &row.endpoint_vertical,
                                 &row.mean_position, &row.mean_attitude}) {
      o += "," + metres(f->mean, "") + "," + metres(f->stddev, "");
    }
    o += "\n";
  }
  return o;
}

std::string comparison_markdown(const std::vector<ComparisonRow>& rows) {
  static const std::string kNone = "\u2014";  // em dash
  const auto labels = label_columns(rows);
  std::string head = "|", rule = "|";
  for (const auto& l : labels) {
    head += " " + md_cell(l) + " |";
    rule += "---|";
  }
  head += " scenario | runs | passed | endpoint error [m] mean \u00b1 std | min [m] | max [m] |"
          " horizontal [m] | vertical [m] | mean position error [m] |"
          " mean attitude error [deg] |\n";
  rule += "---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  std::string o = head + rule;
  for (const auto& row : rows) {
    o += "|";
    for (const auto& l : labels) {
      const std::string v = label_value(row.labels, l);
      o += " " + (v.empty() ? kNone : md_cell(v)) + " |";
    }
    const auto mean_std = [](const SampleStats& s) {
      return s.n == 0 ? kNone : metres(s.mean, kNone) + " \u00b1 " + metres(s.stddev, kNone);
    };
    const auto& e = row.endpoint;
    o += " " + md_cell(row.scenario) + " | " + std::to_string(row.runs) + " | " +
         std::to_string(row.passed) + " | " + mean_std(e) + " | " + metres(e.min, kNone) +
         " | " + metres(e.max, kNone) + " | " + mean_std(row.endpoint_horizontal) + " | " +
         mean_std(row.endpoint_vertical) + " | " + mean_std(row.mean_position) + " | " +
         mean_std(row.mean_attitude) + " |\n";
  }
  return o;
}

std::vector<RunCheck> run_checks_from_summary(const nlohmann::json& summary) {
  std::vector<RunCheck> out;
  const auto checks = summary.find("checks");
  if (checks == summary.end() || !checks->is_array()) return out;
  for (const auto& c : *checks) {
    if (!c.is_object() || !c.value("judged", false)) continue;
    const auto name = c.find("name");
    if (name == c.end() || !name->is_string()) continue;
    RunCheck r{name->get<std::string>(), c.value("passed", false), {}, c.value("unit", std::string())};
    const auto value = c.find("value");
    const auto limit = c.find("limit");
    if (value != c.end() && value->is_number()) {
      // judge.cpp: a measured error passes exactly when it is within the limit; a check with
      // no solution to judge fails with value 0. So "failed, yet within the limit" means
      // nothing was measured.
      const double v = value->get<double>();
      if (r.passed || limit == c.end() || !limit->is_number() || v > limit->get<double>()) {
        r.value = v;
      }
    }
    out.push_back(std::move(r));
  }
  return out;
}

std::optional<double> endpoint_error_from_summary(const nlohmann::json& summary,
                                                  const std::string& check_name) {
  for (const auto& c : run_checks_from_summary(summary)) {
    if (c.name == check_name) return c.value;
  }
  return std::nullopt;
}

int campaign_exit_code(const std::vector<int>& run_exit_codes) {
  int worst = kExitPass;
  for (const int c : run_exit_codes) {
    const int code = severity(c) == 2 ? kExitBench : c;
    if (severity(code) > severity(worst)) worst = code;
  }
  return worst;
}

std::string exit_code_meaning(int code) {
  switch (code) {
    case kExitPass: return "pass";
    case kExitFail: return "a check failed";
    case kExitUsage: return "usage or scenario error";
    case kExitBench: return "bench error";
    case kExitDut: return "DUT crashed or hung";
    default: return "unexpected exit code";
  }
}

std::string command_line(const std::vector<std::string>& argv) {
  std::string o;
  for (const auto& a : argv) {
    if (!o.empty()) o += ' ';
    const bool plain = !a.empty() && std::all_of(a.begin(), a.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) ||
             std::string_view("_-./=:,+@%").find(c) != std::string_view::npos;
    });
    if (plain) {
      o += a;
      continue;
    }
    o += '\'';
    for (const char c : a) {
      if (c == '\'') o += "'\\''";
      else o += c;
    }
    o += '\'';
  }
  return o;
}

}  // namespace nav::bench
