// SPDX-License-Identifier: MIT
// DUT variants compared with the baseline pair by seed (campaign/campaign_pairs.hpp): a
// candidate made worse is flagged, an identical one is not, a better one is called better;
// crashes count as infinite errors, bench errors leave their pair out; differences below the
// printed resolution are ties.
#include "campaign/campaign_pairs.hpp"

#include <gtest/gtest.h>

#include "nav/bench/runner.hpp"

namespace nav::bench::detail {
namespace {

/// One scenario, variants base and cand, seeds 1..n: index 2k is base's seed k+1, 2k+1 cand's.
CampaignPlan two_variants(std::uint64_t n) {
  CampaignPlan plan;
  plan.seeds = n;
  plan.scenarios.resize(1);
  plan.scenarios[0].name = "alpha";
  plan.variants = {{"base", ""}, {"cand", ""}};
  return plan;
}

CampaignResult run(int exit_code, std::optional<double> endpoint) {
  CampaignResult r;
  r.exit_code = exit_code;
  if (exit_code == kExitPass || exit_code == kExitFail) {
    r.checks.push_back({"endpoint_error", true, endpoint, "m"});
    r.checks.push_back({"dut_alive", true, 0.0, ""});  // no unit: not a figure
  }
  return r;
}

std::vector<std::optional<CampaignResult>> results(const std::vector<double>& base,
                                                   const std::vector<double>& cand) {
  std::vector<std::optional<CampaignResult>> out;
  for (std::size_t k = 0; k < base.size(); ++k) {
    out.push_back(run(kExitPass, base[k]));
    out.push_back(run(kExitPass, cand[k]));
  }
  return out;
}

TEST(CompareVariants, ACandidateMadeWorseIsFlagged) {
  const std::vector<double> base{1.0, 1.2, 0.9, 1.1, 1.0, 1.3, 0.8, 1.05};
  std::vector<double> cand;
  for (std::size_t k = 0; k < base.size(); ++k) cand.push_back(base[k] + 0.1 + 0.01 * static_cast<double>(k));
  const auto c = compare_variants(two_variants(8), results(base, cand));
  ASSERT_EQ(c.size(), 1u);  // endpoint_error only
  EXPECT_EQ(c[0].figure, "endpoint_error");
  EXPECT_EQ(c[0].baseline, "base");
  EXPECT_EQ(c[0].candidate, "cand");
  EXPECT_TRUE(c[0].worse);
  EXPECT_EQ(c[0].finding, "worse");
  EXPECT_DOUBLE_EQ(c[0].test.p_greater, 1.0 / 256.0);
  EXPECT_NEAR(c[0].test.median_difference, 0.135, 1e-12);
  EXPECT_EQ(c[0].text,
            "cand against base, endpoint_error: worse at 95 % (Wilcoxon signed-rank, one-sided "
            "p = 0.0039; median paired difference +0.135 m over 8 pairs)");
  EXPECT_EQ(paired_json(c[0])["worse"], true);
}

TEST(CompareVariants, AnIdenticalCandidateIsNotFlaggedABetterOneIsCalledBetter) {
  const std::vector<double> base{1.0, 1.2, 0.9, 1.1, 1.0, 1.3};
  const auto same = compare_variants(two_variants(6), results(base, base));
  ASSERT_EQ(same.size(), 1u);
  EXPECT_FALSE(same[0].worse);
  EXPECT_EQ(same[0].finding, "no difference shown");
  std::vector<double> better;
  for (double b : base) better.push_back(b / 2);
  const auto b = compare_variants(two_variants(6), results(base, better));
  EXPECT_FALSE(b[0].worse);
  EXPECT_EQ(b[0].finding, "better");
}

TEST(CompareVariants, DifferencesThatPrintAsZeroAreTiesHoweverConsistentTheirSign) {
  const std::vector<double> base{1.0, 1.2, 0.9, 1.1, 1.0, 1.3, 0.8, 1.05};
  std::vector<double> hair, just_over;
  for (std::size_t k = 0; k < base.size(); ++k) {
    hair.push_back(base[k] + 3e-5 * static_cast<double>(k + 1));  // every seed worse, by < 0.5 mm
    just_over.push_back(base[k] + 6e-4);
  }
  const auto c = compare_variants(two_variants(8), results(base, hair));
  ASSERT_EQ(c.size(), 1u);
  EXPECT_FALSE(c[0].worse);
  EXPECT_EQ(c[0].finding, "no difference shown");
  EXPECT_EQ(c[0].test.n, 0u);  // all ties
  EXPECT_EQ(c[0].test.pairs, 8u);
  EXPECT_NEAR(c[0].test.median_difference, 1.35e-4, 1e-12);  // as measured
  const auto o = compare_variants(two_variants(8), results(base, just_over));
  EXPECT_TRUE(o[0].worse);
  EXPECT_EQ(o[0].test.n, 8u);
}

TEST(CompareVariants, CrashesCountAsInfiniteErrorsBenchErrorsLeaveThePairOut) {
  auto r = results({1, 1, 1, 1, 1, 1}, {1, 1, 1, 1, 1, 1});
  for (std::size_t k = 0; k < 5; ++k) r[2 * k + 1] = run(kExitDut, std::nullopt);  // cand crashed
  r[10] = run(kExitBench, std::nullopt);  // the bench failed base's seed 6
  const auto c = compare_variants(two_variants(6), r);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].left_out, 1u);
  EXPECT_EQ(c[0].test.pairs, 5u);
  EXPECT_TRUE(c[0].worse);
  // Without variants there is nothing to compare.
  CampaignPlan plain = two_variants(6);
  plain.variants.clear();
  EXPECT_TRUE(compare_variants(plain, r).empty());
}

}  // namespace
}  // namespace nav::bench::detail
