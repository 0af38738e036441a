// SPDX-License-Identifier: MIT
// The statistics of a campaign's verdicts: statements over one value per run (the runs of a
// campaign are independent, each with its own seed), decided without assuming a distribution.
//
// Quantile statement "the q-quantile of X is <= max, with confidence c": with n runs and j of
// them above max, the (n - j)-th smallest value x_(n-j) is <= max, and
//     P(x_(k) >= x_q) = P(fewer than k of n values below x_q) = BinomCDF(k - 1; n, q)
// (order statistics of a continuous distribution; Wilks 1941). So the statement holds with
// confidence BinomCDF(n - j - 1; n, q), 0 when every run is above. It is decided true when
// that reaches c. With no run above max, n >= ln(1 - c) / ln(q) runs are needed: 59 for
// q = c = 0.95, the classic "95/95" (Wilks' table).
//
// Pass-rate statement "the pass rate is >= r, with confidence c": x passes of n runs; the
// one-sided Clopper–Pearson lower bound at c is the (1 - c)-quantile of Beta(x, n - x + 1),
// and it is >= r exactly when P(X >= x | p = r) <= 1 - c, so the confidence reached is
// BinomCDF(x - 1; n, r).
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

namespace nav::bench {

/// P(X <= k) for X ~ Binomial(n, p); 0 for k < 0.
double binomial_cdf(long long k, std::size_t n, double p);

/// A two-sided Clopper–Pearson interval for a proportion (x successes of n), at level
/// (e.g. 0.95): [0, 1] when n is 0.
struct Interval {
  double lower = 0.0;
  double upper = 1.0;
};
Interval clopper_pearson(std::size_t x, std::size_t n, double level);

/// The decision of "the q-quantile of the values is <= max, with confidence c".
struct QuantileVerdict {
  std::size_t n = 0;                 ///< values
  std::size_t above = 0;             ///< values above max
  double confidence_reached = 0.0;   ///< with which the statement holds
  bool passed = false;               ///< confidence_reached >= c
  /// The distribution-free upper bound on the q-quantile at confidence c: the smallest order
  /// statistic x_(k) with BinomCDF(k - 1; n, q) >= c; none when n is too small.
  std::optional<double> upper_bound;
  double empirical = 0.0;            ///< the sample q-quantile (nearest rank); NaN when n is 0
  /// Runs that would reach c if every further run stayed within max (n itself when passed).
  std::size_t runs_needed = 0;
};
QuantileVerdict judge_quantile(std::vector<double> values, double q, double max, double c);

/// The decision of "the pass rate is >= min_rate, with confidence c".
struct PassRateVerdict {
  std::size_t n = 0;
  std::size_t passed_runs = 0;
  double confidence_reached = 0.0;
  bool passed = false;
  double lower_bound = 0.0;          ///< one-sided Clopper–Pearson lower bound at c
  Interval interval;                 ///< two-sided Clopper–Pearson at level c
  /// Runs that would reach c if every further run passed (n itself when passed).
  std::size_t runs_needed = 0;
};
PassRateVerdict judge_pass_rate(std::size_t passed, std::size_t n, double min_rate, double c);

/// Wilcoxon's signed-rank test of paired differences d_i = candidate_i - baseline_i for the
/// one-sided alternative "the candidate's values are larger" (worse, for an error). Zero
/// differences are dropped (Wilcoxon's own treatment); tied |d| share their average rank.
/// W+ is the sum of the ranks of the positive differences. Exact null distribution when at
/// most 50 differences remain and none are tied; otherwise the normal approximation with the
/// tie correction of the variance and a continuity correction.
struct SignedRankTest {
  std::size_t pairs = 0;        ///< pairs given
  std::size_t n = 0;            ///< non-zero differences ranked
  double w_plus = 0.0;          ///< rank sum of positive differences
  double p_greater = 1.0;       ///< P(W+ >= observed) under "no difference"
  double p_less = 1.0;          ///< P(W+ <= observed): evidence the candidate is better
  double median_difference = 0.0;  ///< median of all d_i (zeros kept); NaN when none
  bool exact = true;            ///< exact distribution (false: normal approximation)
};
SignedRankTest signed_rank_test(const std::vector<double>& differences);

/// P(T <= t) for Wilcoxon's signed-rank statistic T over n untied non-zero differences under
/// "no difference" (each rank's sign a fair coin): the exact distribution (n <= 1000).
double signed_rank_cdf(double t, std::size_t n);

}  // namespace nav::bench
