// SPDX-License-Identifier: MIT
// A campaign's checks (scenario `campaign.checks`) decided over the finished runs of their
// scenario (campaign_stats.hpp), and what they say in campaign.json, comparison.md and on
// stdout. Private to nav_bench's campaign/.
//
// Which runs count: a run that reached the end of its scenario (exit 0 or 1) counts with what
// its check measured, or as above every limit when it measured nothing (no solution to judge);
// a run whose DUT crashed or hung (exit 4) counts as above every limit and as failed; a run the
// bench could not make (exit 3) does not count, and the verdict says how many were left out.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "nav/bench/campaign_plan.hpp"
#include "nav/bench/campaign_result.hpp"
#include "nav/bench/campaign_stats.hpp"

namespace nav::bench::detail {

struct CampaignCheckVerdict {
  std::string scenario;
  CampaignCheckSpec spec;
  std::size_t left_out = 0;  ///< finished runs that do not count (bench errors)
  std::optional<QuantileVerdict> quantile;
  std::optional<PassRateVerdict> pass_rate;
  bool passed = false;
  std::string statement;  ///< what is claimed: "the 95th percentile of endpoint_error is <= ..."
  std::string finding;    ///< what the runs show: "holds with 95.2 % confidence: ..."
};

/// Every campaign check of every scenario of the plan, over results[i] of each index i.
std::vector<CampaignCheckVerdict> judge_campaign_checks(
    const CampaignPlan& plan, const std::vector<std::optional<CampaignResult>>& results);

/// A verdict as campaign.json writes it.
nlohmann::ordered_json verdict_json(const CampaignCheckVerdict& v);

/// "95th percentile", "99.9th percentile", "median": a quantile q in words.
std::string percentile_name(double q);

/// The exit code of a run once its scenario's campaign checks decide: 1 (a check of that one
/// run failed) becomes 0 when the scenario has campaign checks; others stay.
int run_code_under_campaign_checks(int exit_code, const PlanScenario& scenario);

}  // namespace nav::bench::detail
