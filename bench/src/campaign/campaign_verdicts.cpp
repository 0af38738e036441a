// SPDX-License-Identifier: MIT
// A campaign's checks decided over its runs (campaign_verdicts.hpp).
#include "campaign/campaign_verdicts.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

#include "nav/bench/runner.hpp"

namespace nav::bench::detail {
namespace {

using json = nlohmann::ordered_json;

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

std::string percent(double p) { return fmt("%.1f", 100.0 * p) + " %"; }
std::string short_percent(double p) { return fmt("%g", std::round(p * 1e6) / 1e4) + " %"; }

std::string count(std::size_t n) { return std::to_string(n); }

/// "45 runs (25 more)": how many runs would show the statement.
std::string runs_needed_text(std::size_t needed, std::size_t n, const std::string& unless) {
  if (needed >= 100'000'000) return "no practical number of further runs " + unless + " would show it";
  return count(needed) + " runs (" + count(needed - n) + " more, none of them " + unless +
         ") would show it";
}

/// The run check of a result named name, or null.
const RunCheck* check_of(const CampaignResult& r, const std::string& name) {
  for (const auto& c : r.checks) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

CampaignCheckVerdict judge(const std::string& cell, const CampaignCheckSpec& spec,
                           const std::vector<const CampaignResult*>& runs) {
  CampaignCheckVerdict v;
  v.scenario = cell;
  v.spec = spec;
  std::vector<double> values;
  std::size_t passed = 0, counted = 0;
  for (const CampaignResult* r : runs) {
    const bool ended = r->exit_code == kExitPass || r->exit_code == kExitFail;
    if (!ended && r->exit_code != kExitDut) {
      ++v.left_out;
      continue;
    }
    ++counted;
    const RunCheck* c = ended && !spec.of.empty() ? check_of(*r, spec.of) : nullptr;
    if (spec.kind == CampaignCheckSpec::Kind::kQuantile) {
      values.push_back(c && c->value ? *c->value : std::numeric_limits<double>::infinity());
    } else if (spec.of.empty() ? r->exit_code == kExitPass : (c && c->passed)) {
      ++passed;
    }
  }
  const std::string u = " " + spec.unit;
  if (spec.kind == CampaignCheckSpec::Kind::kQuantile) {
    const auto q = judge_quantile(values, spec.quantile, spec.limit, spec.confidence);
    v.passed = q.passed;
    v.statement = "the " + percentile_name(spec.quantile) + " of " + spec.of +
                  " is \u2264 " + fmt("%.3f", spec.limit) + u + ", with " +
                  short_percent(spec.confidence) + " confidence";
    const std::string above = count(q.above) + " of " + count(q.n) + " runs above " +
                              fmt("%.3f", spec.limit) + u;
    if (q.passed) {
      v.finding = "shown with " + percent(q.confidence_reached) + " confidence: " + above;
      if (q.upper_bound) {
        v.finding += "; at " + short_percent(spec.confidence) + " the " +
                     percentile_name(spec.quantile) + " is \u2264 " +
                     fmt("%.3f", *q.upper_bound) + u;
      }
    } else {
      v.finding = "not shown: " + above + ", confidence " + percent(q.confidence_reached) + "; " +
                  runs_needed_text(q.runs_needed, q.n, "above");
    }
    v.quantile = q;
  } else {
    const auto p = judge_pass_rate(passed, counted, spec.min_rate, spec.confidence);
    v.passed = p.passed;
    v.statement = (spec.of.empty() ? std::string("the rate of runs that pass every check")
                                   : "the rate of runs that pass " + spec.of) +
                  " is \u2265 " + short_percent(spec.min_rate) + ", with " +
                  short_percent(spec.confidence) + " confidence";
    const std::string tally = count(p.passed_runs) + " of " + count(p.n) + " runs passed";
    const std::string bound = "lower bound " + percent(p.lower_bound) + " at " +
                              short_percent(spec.confidence) + " (Clopper\u2013Pearson)";
    if (p.passed) {
      v.finding = "shown with " + percent(p.confidence_reached) + " confidence: " + tally + "; " +
                  bound;
    } else {
      v.finding = "not shown: " + tally + ", confidence " + percent(p.confidence_reached) + ", " +
                  bound + "; " + runs_needed_text(p.runs_needed, p.n, "failing");
    }
    v.pass_rate = p;
  }
  if (v.left_out > 0) {
    v.finding += " (" + count(v.left_out) + " run" + (v.left_out == 1 ? "" : "s") +
                 " in bench error left out)";
  }
  return v;
}

json number_or_null(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

}  // namespace

std::string percentile_name(double q) {
  const double pct = std::round(q * 1e6) / 1e4;
  const double whole = std::round(pct);
  std::string suffix = "th";
  if (std::abs(pct - whole) < 1e-9) {
    const auto n = static_cast<long long>(whole);
    if (n % 100 < 11 || n % 100 > 13) {
      if (n % 10 == 1) suffix = "st";
      else if (n % 10 == 2) suffix = "nd";
      else if (n % 10 == 3) suffix = "rd";
    }
  }
  if (std::abs(pct - 50.0) < 1e-9) return "median";
  return fmt("%g", pct) + suffix + " percentile";
}

std::vector<CampaignCheckVerdict> judge_campaign_checks(
    const CampaignPlan& plan, const std::vector<std::optional<CampaignResult>>& results) {
  std::vector<CampaignCheckVerdict> out;
  for (std::size_t c = 0; c < plan.cells(); ++c) {  // each variant of a scenario on its own
    const PlanScenario& sc = plan.scenarios[plan.scenario_of(c)];
    if (sc.campaign_checks.empty()) continue;
    std::vector<const CampaignResult*> runs;
    for (std::size_t i = c; i < results.size(); i += plan.cells()) {
      if (results[i]) runs.push_back(&*results[i]);
    }
    for (const auto& spec : sc.campaign_checks) {
      out.push_back(judge(plan.cell_name(c), spec, runs));
    }
  }
  return out;
}

json verdict_json(const CampaignCheckVerdict& v) {
  json j;
  j["scenario"] = v.scenario;
  j["check"] = campaign_check_json(v.spec);
  j["passed"] = v.passed;
  j["statement"] = v.statement;
  j["finding"] = v.finding;
  j["runs_left_out"] = v.left_out;
  if (v.quantile) {
    const auto& q = *v.quantile;
    j["runs"] = q.n;
    j["runs_above"] = q.above;
    j["confidence_reached"] = q.confidence_reached;
    j["upper_bound"] = q.upper_bound ? number_or_null(*q.upper_bound) : json(nullptr);
    j["empirical_quantile"] = number_or_null(q.empirical);
    j["runs_needed"] = q.runs_needed;
  } else if (v.pass_rate) {
    const auto& p = *v.pass_rate;
    j["runs"] = p.n;
    j["runs_passed"] = p.passed_runs;
    j["confidence_reached"] = p.confidence_reached;
    j["lower_bound"] = p.lower_bound;
    j["interval"] = {p.interval.lower, p.interval.upper};
    j["runs_needed"] = p.runs_needed;
  }
  return j;
}

int run_code_under_campaign_checks(int exit_code, const PlanScenario& scenario) {
  return exit_code == kExitFail && !scenario.campaign_checks.empty() ? kExitPass : exit_code;
}

}  // namespace nav::bench::detail
