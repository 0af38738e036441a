// SPDX-License-Identifier: MIT
// A campaign's statistics (campaign_stats.hpp) against tabulated values: binomial
// probabilities counted by hand, Wilks' numbers of runs for one-sided tolerance statements
// (Wilks 1941; the "59 runs for 95/95" of nuclear safety analyses), and Clopper–Pearson
// intervals as published (Clopper & Pearson 1934; e.g. 0 of 10: [0, 0.3085]), and Wilcoxon's
// signed-rank test against its table of critical values.
#include "nav/bench/campaign_stats.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <vector>

namespace nav::bench {
namespace {

std::vector<double> ramp(std::size_t n) {  // 1, 2, ..., n
  std::vector<double> v(n);
  std::iota(v.begin(), v.end(), 1.0);
  return v;
}

TEST(BinomialCdf, CountedByHand) {
  EXPECT_NEAR(binomial_cdf(2, 10, 0.5), 56.0 / 1024.0, 1e-15);
  EXPECT_NEAR(binomial_cdf(0, 3, 0.2), 0.512, 1e-15);
  EXPECT_EQ(binomial_cdf(-1, 5, 0.5), 0.0);
  EXPECT_EQ(binomial_cdf(5, 5, 0.5), 1.0);
}

// Wilks' table: runs needed for "the q-quantile is below the j+1-th largest value" at
// confidence c.
TEST(JudgeQuantile, RunsNeededAreWilksNumbers) {
  struct Row { double q, c; std::size_t above, runs; };
  for (const Row& r : {Row{0.95, 0.95, 0, 59}, Row{0.95, 0.95, 1, 93}, Row{0.95, 0.95, 2, 124},
                       Row{0.95, 0.95, 3, 153}, Row{0.90, 0.90, 0, 22}, Row{0.99, 0.95, 0, 299},
                       Row{0.95, 0.99, 0, 90}, Row{0.90, 0.95, 0, 29}}) {
    std::vector<double> values(r.above, 10.0);  // above the limit 5
    values.push_back(1.0);
    const auto v = judge_quantile(values, r.q, 5.0, r.c);
    EXPECT_EQ(v.above, r.above);
    EXPECT_EQ(v.runs_needed, r.runs) << r.q << "/" << r.c << " with " << r.above << " above";
    EXPECT_FALSE(v.passed);
  }
}

TEST(JudgeQuantile, FiftyNineRunsWithinTheLimitProve95Over95AndFiftyEightDoNot) {
  const auto yes = judge_quantile(ramp(59), 0.95, 59.0, 0.95);
  EXPECT_TRUE(yes.passed);
  EXPECT_EQ(yes.above, 0u);
  EXPECT_NEAR(yes.confidence_reached, 1.0 - std::pow(0.95, 59), 1e-12);  // 0.9515
  EXPECT_EQ(yes.runs_needed, 59u);
  ASSERT_TRUE(yes.upper_bound);
  EXPECT_EQ(*yes.upper_bound, 59.0);  // the largest value: first order
  EXPECT_EQ(yes.empirical, 57.0);     // nearest rank: ceil(0.95 * 59) = 57

  const auto no = judge_quantile(ramp(58), 0.95, 100.0, 0.95);
  EXPECT_FALSE(no.passed);
  EXPECT_NEAR(no.confidence_reached, 1.0 - std::pow(0.95, 58), 1e-12);  // 0.9490
  EXPECT_FALSE(no.upper_bound);  // too few runs for any bound
  EXPECT_EQ(no.runs_needed, 59u);
}

TEST(JudgeQuantile, RunsAboveTheLimitLowerTheConfidenceOrderByOrder) {
  // 93 runs, one above: the second largest bounds the 95th percentile at 95 %.
  std::vector<double> values = ramp(93);
  const auto v = judge_quantile(values, 0.95, 92.5, 0.95);
  EXPECT_EQ(v.above, 1u);
  EXPECT_TRUE(v.passed);
  EXPECT_NEAR(v.confidence_reached, binomial_cdf(91, 93, 0.95), 1e-15);
  ASSERT_TRUE(v.upper_bound);
  EXPECT_EQ(*v.upper_bound, 92.0);
  // Every run above: the statement has no support at all.
  const auto none = judge_quantile({3.0, 4.0}, 0.5, 1.0, 0.5);
  EXPECT_EQ(none.confidence_reached, 0.0);
  EXPECT_FALSE(none.passed);
  // No runs: undecided, failed.
  const auto empty = judge_quantile({}, 0.95, 1.0, 0.9);
  EXPECT_FALSE(empty.passed);
  EXPECT_TRUE(std::isnan(empty.empirical));
  EXPECT_EQ(empty.runs_needed, 45u);  // ln 0.1 / ln 0.95 = 44.9
}

TEST(ClopperPearson, PublishedIntervals) {
  const auto zero = clopper_pearson(0, 10, 0.95);
  EXPECT_EQ(zero.lower, 0.0);
  EXPECT_NEAR(zero.upper, 0.30850, 5e-6);
  const auto one = clopper_pearson(1, 10, 0.95);
  EXPECT_NEAR(one.lower, 0.00253, 5e-6);
  EXPECT_NEAR(one.upper, 0.44502, 5e-6);
  const auto half = clopper_pearson(5, 10, 0.95);
  EXPECT_NEAR(half.lower, 0.18709, 5e-6);
  EXPECT_NEAR(half.upper, 0.81291, 5e-6);
  const auto all = clopper_pearson(10, 10, 0.95);
  EXPECT_NEAR(all.lower, 0.69150, 5e-6);
  EXPECT_EQ(all.upper, 1.0);
  // The exact lower bound of n of n at level 1 - 2a is a^(1/n).
  EXPECT_NEAR(clopper_pearson(20, 20, 0.90).lower, std::pow(0.05, 1.0 / 20.0), 1e-12);
}

TEST(JudgePassRate, LowerBoundAndConfidenceAgreeWithTheBinomial) {
  const auto all = judge_pass_rate(59, 59, 0.95, 0.95);
  EXPECT_TRUE(all.passed);
  EXPECT_NEAR(all.lower_bound, std::pow(0.05, 1.0 / 59.0), 1e-12);  // 0.9505
  EXPECT_NEAR(all.confidence_reached, 1.0 - std::pow(0.95, 59), 1e-12);
  const auto one_failed = judge_pass_rate(58, 59, 0.95, 0.95);
  EXPECT_FALSE(one_failed.passed);
  EXPECT_LT(one_failed.lower_bound, 0.95);
  EXPECT_EQ(one_failed.runs_needed, 93u);  // as Wilks' second order
  // 95 of 100 at 90 %: the lower bound (the 10 % quantile of Beta(95, 6)) is above 0.9.
  const auto some = judge_pass_rate(95, 100, 0.9, 0.9);
  EXPECT_TRUE(some.passed);
  EXPECT_NEAR(some.confidence_reached, binomial_cdf(94, 100, 0.9), 1e-15);
  EXPECT_GE(some.lower_bound, 0.9);
  // The lower bound sits where the confidence reached equals the level asked.
  EXPECT_NEAR(binomial_cdf(94, 100, some.lower_bound), 0.9, 1e-9);
  const auto none = judge_pass_rate(0, 5, 0.5, 0.9);
  EXPECT_EQ(none.lower_bound, 0.0);
  EXPECT_FALSE(none.passed);
}

// The one-tailed 5 % critical values of Wilcoxon's T (the smaller rank sum) for n = 5..20,
// as every table prints them: P(T <= crit) <= 0.05 < P(T <= crit + 1).
TEST(SignedRank, ExactDistributionMatchesTheTableOfCriticalValues) {
  const int crit[] = {0, 2, 3, 5, 8, 10, 13, 17, 21, 25, 30, 35, 41, 47, 53, 60};
  for (std::size_t n = 5; n <= 20; ++n) {
    const double c = crit[n - 5];
    EXPECT_LE(signed_rank_cdf(c, n), 0.05) << n;
    EXPECT_GT(signed_rank_cdf(c + 1, n), 0.05) << n;
  }
  EXPECT_DOUBLE_EQ(signed_rank_cdf(0, 5), 1.0 / 32.0);
  EXPECT_NEAR(signed_rank_cdf(10, 10), 0.0420, 5e-5);  // 43 of 1024
  EXPECT_DOUBLE_EQ(signed_rank_cdf(55, 10), 1.0);
}

TEST(SignedRank, ACandidateMadeWorseIsFlaggedAnIdenticalOneIsNot) {
  // Ten pairs, the candidate worse in every one: W+ = 55, p = 1/1024.
  std::vector<double> worse;
  for (int i = 1; i <= 10; ++i) worse.push_back(0.1 * i);
  const auto w = signed_rank_test(worse);
  EXPECT_TRUE(w.exact);
  EXPECT_EQ(w.n, 10u);
  EXPECT_EQ(w.w_plus, 55.0);
  EXPECT_DOUBLE_EQ(w.p_greater, 1.0 / 1024.0);
  EXPECT_DOUBLE_EQ(w.p_less, 1.0);
  EXPECT_NEAR(w.median_difference, 0.55, 1e-12);
  // Identical: every difference zero, nothing ranked, no evidence.
  const auto same = signed_rank_test(std::vector<double>(10, 0.0));
  EXPECT_EQ(same.n, 0u);
  EXPECT_EQ(same.p_greater, 1.0);
  EXPECT_EQ(same.median_difference, 0.0);
  // Better in every pair: evidence the other way only.
  std::vector<double> better;
  for (double d : worse) better.push_back(-d);
  const auto b = signed_rank_test(better);
  EXPECT_DOUBLE_EQ(b.p_greater, 1.0);
  EXPECT_DOUBLE_EQ(b.p_less, 1.0 / 1024.0);
}

TEST(SignedRank, TiesAndLargeSamplesUseTheNormalApproximation) {
  // d = 1, 2, -3, 4, 5, 6, 7, 8, 9, 10 (no ties): T- = 3, P(T <= 3 | n = 10) = 0.0049.
  std::vector<double> d{1, 2, -3, 4, 5, 6, 7, 8, 9, 10};
  const auto exact = signed_rank_test(d);
  EXPECT_TRUE(exact.exact);
  EXPECT_EQ(exact.w_plus, 52.0);
  EXPECT_NEAR(exact.p_greater, signed_rank_cdf(3, 10), 1e-15);
  EXPECT_NEAR(exact.p_greater, 5.0 / 1024.0, 1e-15);
  // Tied |d|: average ranks (1.5, 1.5, 3), then the normal approximation.
  const auto tied = signed_rank_test({0.5, -0.5, 2.0, 0.0});
  EXPECT_FALSE(tied.exact);
  EXPECT_EQ(tied.n, 3u);
  EXPECT_EQ(tied.w_plus, 4.5);
  // 60 untied pairs: the approximation is within 0.005 of the exact distribution.
  std::vector<double> many;
  for (int i = 1; i <= 60; ++i) many.push_back(i % 3 == 0 ? -i : i);
  const auto approx = signed_rank_test(many);
  EXPECT_FALSE(approx.exact);
  const double w_minus = 60.0 * 61.0 / 2.0 - approx.w_plus;
  EXPECT_NEAR(approx.p_greater, signed_rank_cdf(w_minus, 60), 0.005);
}

}  // namespace
}  // namespace nav::bench
