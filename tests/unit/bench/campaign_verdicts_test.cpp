// SPDX-License-Identifier: MIT
// A campaign's checks decided over its runs (campaign/campaign_verdicts.hpp): which runs
// count and how, the statements and findings in words, and the exit code they give.
#include "campaign/campaign_verdicts.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "nav/bench/runner.hpp"

namespace nav::bench::detail {
namespace {

CampaignCheckSpec quantile(double q, double max, double c) {
  CampaignCheckSpec s;
  s.kind = CampaignCheckSpec::Kind::kQuantile;
  s.name = "endpoint_error_p";
  s.of = "endpoint_error";
  s.quantile = q;
  s.limit = max;
  s.unit = "m";
  s.confidence = c;
  return s;
}

CampaignCheckSpec pass_rate(const std::string& of, double min, double c) {
  CampaignCheckSpec s;
  s.kind = CampaignCheckSpec::Kind::kPassRate;
  s.name = "rate";
  s.of = of;
  s.min_rate = min;
  s.confidence = c;
  return s;
}

/// One scenario ("alpha") with the given campaign checks, seeds 1..n.
CampaignPlan plan_of(std::vector<CampaignCheckSpec> checks, std::uint64_t n) {
  CampaignPlan plan;
  plan.seeds = n;
  PlanScenario s;
  s.name = "alpha";
  s.campaign_checks = std::move(checks);
  plan.scenarios.push_back(s);
  return plan;
}

CampaignResult run(int exit_code, std::optional<double> endpoint, bool endpoint_passed = true) {
  CampaignResult r;
  r.exit_code = exit_code;
  if (exit_code == kExitPass || exit_code == kExitFail) {
    r.checks.push_back({"endpoint_error", endpoint_passed, endpoint, "m"});
  }
  return r;
}

TEST(CampaignVerdicts, TwentyTwoRunsWithinTheLimitShowThe90thPercentileAt90Percent) {
  std::vector<std::optional<CampaignResult>> results;
  for (int i = 0; i < 22; ++i) results.push_back(run(kExitPass, 1.0 + 0.01 * i));
  const auto v = judge_campaign_checks(plan_of({quantile(0.9, 2.0, 0.9)}, 22), results);
  ASSERT_EQ(v.size(), 1u);
  EXPECT_TRUE(v[0].passed);
  EXPECT_EQ(v[0].scenario, "alpha");
  EXPECT_EQ(v[0].statement,
            "the 90th percentile of endpoint_error is \u2264 2.000 m, with 90 % confidence");
  EXPECT_EQ(v[0].finding,
            "shown with 90.2 % confidence: 0 of 22 runs above 2.000 m; at 90 % the 90th "
            "percentile is \u2264 1.210 m");
  EXPECT_EQ(verdict_json(v[0])["runs_needed"], 22);
}

TEST(CampaignVerdicts, RunsThatMeasuredNothingOrCrashedCountAboveBenchErrorsAreLeftOut) {
  std::vector<std::optional<CampaignResult>> results;
  for (int i = 0; i < 20; ++i) results.push_back(run(kExitPass, 1.0));
  results.push_back(run(kExitFail, std::nullopt, false));  // no solution to judge
  results.push_back(run(kExitDut, std::nullopt));          // crashed
  results.push_back(run(kExitBench, std::nullopt));        // the bench failed
  results.push_back(std::nullopt);                         // not run (yet)
  const auto v = judge_campaign_checks(plan_of({quantile(0.9, 2.0, 0.9)}, 24), results);
  ASSERT_EQ(v.size(), 1u);
  ASSERT_TRUE(v[0].quantile);
  EXPECT_EQ(v[0].quantile->n, 22u);
  EXPECT_EQ(v[0].quantile->above, 2u);
  EXPECT_EQ(v[0].left_out, 1u);
  EXPECT_FALSE(v[0].passed);
  EXPECT_NE(v[0].finding.find("not shown: 2 of 22 runs above 2.000 m"), std::string::npos)
      << v[0].finding;
  EXPECT_NE(v[0].finding.find("(1 run in bench error left out)"), std::string::npos);
  // Wilks' third order for 90/90: 52 runs, two of them above.
  EXPECT_NE(v[0].finding.find("52 runs (30 more, none of them above) would show it"),
            std::string::npos)
      << v[0].finding;
}

TEST(CampaignVerdicts, PassRateOfTheRunsVerdictOrOfOneCheck) {
  std::vector<std::optional<CampaignResult>> results;
  for (int i = 0; i < 9; ++i) results.push_back(run(kExitPass, 1.0));
  results.push_back(run(kExitFail, 3.0, /*endpoint_passed=*/true));  // another check failed
  const auto plan = plan_of({pass_rate("", 0.5, 0.9), pass_rate("endpoint_error", 0.7, 0.9)}, 10);
  const auto v = judge_campaign_checks(plan, results);
  ASSERT_EQ(v.size(), 2u);
  ASSERT_TRUE(v[0].pass_rate);
  EXPECT_EQ(v[0].pass_rate->passed_runs, 9u);
  EXPECT_EQ(v[0].statement, "the rate of runs that pass every check is \u2265 50 %, with 90 % confidence");
  EXPECT_TRUE(v[0].passed);
  EXPECT_EQ(v[1].pass_rate->passed_runs, 10u);
  EXPECT_NEAR(v[1].pass_rate->confidence_reached, 1.0 - std::pow(0.7, 10), 1e-12);
  EXPECT_TRUE(v[1].passed);
}

TEST(CampaignVerdicts, AFailedRunIsJudgedByTheCampaignChecksWhereThereAreAny) {
  PlanScenario with, without;
  with.campaign_checks.push_back(pass_rate("", 0.5, 0.5));
  EXPECT_EQ(run_code_under_campaign_checks(kExitFail, with), kExitPass);
  EXPECT_EQ(run_code_under_campaign_checks(kExitDut, with), kExitDut);
  EXPECT_EQ(run_code_under_campaign_checks(kExitBench, with), kExitBench);
  EXPECT_EQ(run_code_under_campaign_checks(kExitFail, without), kExitFail);
}

TEST(PercentileName, OrdinalsAndTheMedian) {
  EXPECT_EQ(percentile_name(0.95), "95th percentile");
  EXPECT_EQ(percentile_name(0.91), "91st percentile");
  EXPECT_EQ(percentile_name(0.92), "92nd percentile");
  EXPECT_EQ(percentile_name(0.83), "83rd percentile");
  EXPECT_EQ(percentile_name(0.11), "11th percentile");
  EXPECT_EQ(percentile_name(0.999), "99.9th percentile");
  EXPECT_EQ(percentile_name(0.5), "median");
}

}  // namespace
}  // namespace nav::bench::detail
