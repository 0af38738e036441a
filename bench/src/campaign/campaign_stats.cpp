// SPDX-License-Identifier: MIT
// Order-statistic and Clopper–Pearson verdicts (campaign_stats.hpp), on Boost.Math's binomial
// distribution and inverse incomplete beta function.
#include "nav/bench/campaign_stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/special_functions/beta.hpp>

namespace nav::bench {
namespace {

/// More runs than any campaign plan holds (kMaxPlanRuns): "needs more than this".
constexpr std::size_t kRunsCap = 100'000'000;

/// P(at least j + 1 of N values are above the q-quantile) = BinomCDF(N - j - 1; N, q): the
/// confidence of a statement that j of N runs broke (quantile) or failed (pass rate).
double confidence_with(std::size_t j, std::size_t n, double q) {
  if (j >= n) return 0.0;
  return binomial_cdf(static_cast<long long>(n - j) - 1, n, q);
}

/// The smallest N >= n with confidence_with(j, N, q) >= c, every further run within the
/// limit (the confidence grows with N); kRunsCap when even that is not enough.
std::size_t runs_needed(std::size_t j, std::size_t n, double q, double c) {
  if (confidence_with(j, n, q) >= c) return n;
  std::size_t lo = n, hi = std::max<std::size_t>(n, j + 1);
  while (confidence_with(j, hi, q) < c) {
    if (hi >= kRunsCap) return kRunsCap;
    lo = hi;
    hi = std::min(kRunsCap, hi * 2);
  }
  while (hi - lo > 1) {  // confidence_with(lo) < c <= confidence_with(hi)
    const std::size_t mid = lo + (hi - lo) / 2;
    (confidence_with(j, mid, q) >= c ? hi : lo) = mid;
  }
  return hi;
}

}  // namespace

double binomial_cdf(long long k, std::size_t n, double p) {
  if (k < 0) return 0.0;
  if (static_cast<std::size_t>(k) >= n) return 1.0;
  const boost::math::binomial_distribution<double> b(static_cast<double>(n), p);
  return boost::math::cdf(b, static_cast<double>(k));
}

Interval clopper_pearson(std::size_t x, std::size_t n, double level) {
  Interval i;
  if (n == 0) return i;
  const double alpha = 1.0 - level;
  const auto a = static_cast<double>(x);
  const auto b = static_cast<double>(n - x);
  if (x > 0) i.lower = boost::math::ibeta_inv(a, b + 1.0, alpha / 2.0);
  if (x < n) i.upper = boost::math::ibeta_inv(a + 1.0, b, 1.0 - alpha / 2.0);
  return i;
}

QuantileVerdict judge_quantile(std::vector<double> values, double q, double max, double c) {
  QuantileVerdict v;
  v.n = values.size();
  std::sort(values.begin(), values.end());
  v.above = static_cast<std::size_t>(
      values.end() - std::upper_bound(values.begin(), values.end(), max));
  v.confidence_reached = confidence_with(v.above, v.n, q);
  v.passed = v.n > 0 && v.confidence_reached >= c;
  for (std::size_t k = 1; k <= v.n; ++k) {
    if (binomial_cdf(static_cast<long long>(k) - 1, v.n, q) >= c) {
      v.upper_bound = values[k - 1];
      break;
    }
  }
  if (v.n == 0) {
    v.empirical = std::numeric_limits<double>::quiet_NaN();
  } else {
    const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.n)));
    v.empirical = values[std::clamp<std::size_t>(rank, 1, v.n) - 1];
  }
  v.runs_needed = runs_needed(v.above, v.n, q, c);
  return v;
}

PassRateVerdict judge_pass_rate(std::size_t passed, std::size_t n, double min_rate, double c) {
  PassRateVerdict v;
  v.n = n;
  v.passed_runs = std::min(passed, n);
  const std::size_t failed = n - v.passed_runs;
  v.confidence_reached = confidence_with(failed, n, min_rate);
  v.passed = n > 0 && v.confidence_reached >= c;
  if (v.passed_runs > 0) {
    v.lower_bound = boost::math::ibeta_inv(static_cast<double>(v.passed_runs),
                                           static_cast<double>(failed) + 1.0, 1.0 - c);
  }
  v.interval = clopper_pearson(v.passed_runs, n, c);
  v.runs_needed = runs_needed(failed, n, min_rate, c);
  return v;
}

double signed_rank_cdf(double t, std::size_t n) {
  // P(T = k): each rank r in 1..n is in T with probability 1/2, independently.
  const std::size_t max = n * (n + 1) / 2;
  if (t < 0.0) return 0.0;
  if (t >= static_cast<double>(max)) return 1.0;
  std::vector<double> p(max + 1, 0.0);
  p[0] = 1.0;
  std::size_t top = 0;
  for (std::size_t r = 1; r <= n; ++r) {
    top += r;
    for (std::size_t k = top; k >= r; --k) p[k] = 0.5 * (p[k] + p[k - r]);
    for (std::size_t k = std::min(r, top + 1); k-- > 0;) p[k] *= 0.5;
  }
  double cdf = 0.0;
  for (std::size_t k = 0; k <= static_cast<std::size_t>(std::floor(t + 1e-9)); ++k) cdf += p[k];
  return std::min(cdf, 1.0);
}

SignedRankTest signed_rank_test(const std::vector<double>& differences) {
  SignedRankTest t;
  t.pairs = differences.size();
  std::vector<double> all = differences;
  std::sort(all.begin(), all.end());
  if (all.empty()) {
    t.median_difference = std::numeric_limits<double>::quiet_NaN();
  } else {
    const std::size_t m = all.size() / 2;
    t.median_difference = all.size() % 2 ? all[m] : 0.5 * (all[m - 1] + all[m]);
  }
  std::vector<double> d;
  for (const double x : differences) {
    if (x != 0.0 && !std::isnan(x)) d.push_back(x);
  }
  t.n = d.size();
  if (t.n == 0) return t;  // nothing to rank: no evidence either way
  std::sort(d.begin(), d.end(), [](double a, double b) { return std::abs(a) < std::abs(b); });
  double tie_term = 0.0;  // sum of (t^3 - t) over groups of tied |d|
  bool ties = false;
  for (std::size_t i = 0; i < t.n;) {
    std::size_t j = i;
    while (j + 1 < t.n && std::abs(d[j + 1]) == std::abs(d[i])) ++j;
    const double rank = 0.5 * static_cast<double>(i + j) + 1.0;  // average of ranks i+1..j+1
    const auto size = static_cast<double>(j - i + 1);
    if (j > i) {
      ties = true;
      tie_term += size * size * size - size;
    }
    for (std::size_t k = i; k <= j; ++k) {
      if (d[k] > 0.0) t.w_plus += rank;
    }
    i = j + 1;
  }
  const auto n = static_cast<double>(t.n);
  const double max = n * (n + 1.0) / 2.0;
  t.exact = !ties && t.n <= 50;
  if (t.exact) {
    // W+ and W- = max - W+ have the same null distribution.
    t.p_greater = signed_rank_cdf(max - t.w_plus, t.n);
    t.p_less = signed_rank_cdf(t.w_plus, t.n);
  } else {
    const double mean = max / 2.0;
    const double sd = std::sqrt(n * (n + 1.0) * (2.0 * n + 1.0) / 24.0 - tie_term / 48.0);
    const boost::math::normal_distribution<double> z01;
    t.p_greater = sd > 0.0 ? boost::math::cdf(boost::math::complement(
                                 z01, (t.w_plus - mean - 0.5) / sd))
                           : 1.0;
    t.p_less = sd > 0.0 ? boost::math::cdf(z01, (t.w_plus - mean + 0.5) / sd) : 1.0;
  }
  t.p_greater = std::clamp(t.p_greater, 0.0, 1.0);
  t.p_less = std::clamp(t.p_less, 0.0, 1.0);
  return t;
}

}  // namespace nav::bench
