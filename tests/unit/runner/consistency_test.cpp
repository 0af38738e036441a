// SPDX-License-Identifier: MIT
// Filter consistency (judge/consistency.hpp): NEES by LDLᵀ against its definition, the χ²
// bounds against the tabulated [2.54, 3.50] for n = 3 and 100 samples, a consistent synthetic
// filter inside its bounds about 95 % of the time and one that states a quarter of its
// covariance flagged, a covariance that is not positive definite reported, none stated not
// judged.
#include "judge/consistency.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>

namespace nav::bench::detail {
namespace {

TEST(Nees, IsTheQuadraticFormOfTheInverseCovariance) {
  Mat3 P;
  P << 4.0, 1.0, 0.5, 1.0, 2.0, 0.3, 0.5, 0.3, 1.0;
  const Vec3 e(0.3, -1.2, 0.7);
  ASSERT_TRUE(nees(e, P));
  EXPECT_NEAR(*nees(e, P), e.dot(P.llt().solve(e)), 1e-12);
  Mat3 singular = P;
  singular.col(2) = singular.col(1);
  singular.row(2) = singular.row(1);
  EXPECT_FALSE(nees(e, singular));
  EXPECT_FALSE(nees(e, -P));
  Mat3 asymmetric = P;
  asymmetric(0, 1) += 0.5;
  EXPECT_FALSE(nees(e, asymmetric));
  Mat3 nan = P;
  nan(2, 2) = std::nan("");
  EXPECT_FALSE(nees(e, nan));
}

TEST(Nees, AttitudeErrorVectorIsTheRotationFromEstimateToTruth) {
  const Quat est = quat_from_euler(Euler{0.1, -0.2, 1.0});
  const Vec3 d(0.01, -0.02, 0.03);
  const Quat truth = Quat(Eigen::AngleAxisd(d.norm(), d.normalized())) * est;
  EXPECT_LT((attitude_error_vector(truth, est) - d).norm(), 1e-12);
  EXPECT_NEAR(attitude_error_vector(truth, est).norm(), attitude_error_angle(truth, est), 1e-12);
}

TEST(Nees, BoundsOfTheAverageAreTheTabulatedChiSquareQuantiles) {
  const auto [lo, hi] = average_nees_bounds(100, 3);
  EXPECT_NEAR(lo, 2.54, 0.005);  // χ²_300(0.025) / 100 = 2.5391
  EXPECT_NEAR(hi, 3.50, 0.005);  // χ²_300(0.975) / 100 = 3.4989
  const auto [lo1, hi1] = average_nees_bounds(1, 3);
  EXPECT_NEAR(lo1, 0.2158, 5e-4);
  EXPECT_NEAR(hi1, 9.3484, 5e-4);
}

/// K solutions of a filter whose errors are drawn from N(0, P_true) and which states P_stated.
std::vector<reports::AlignedSample> run(std::mt19937_64& rng, const Mat3& P_true,
                                        const Mat3& P_stated, int k) {
  const Mat3 L = P_true.llt().matrixL();
  std::normal_distribution<double> n01;
  std::vector<reports::AlignedSample> out;
  for (int i = 0; i < k; ++i) {
    reports::AlignedSample s;
    s.t_s = i;
    s.truth_p_n = Vec3(10.0, 20.0, 5.0);
    s.est_p_n = s.truth_p_n + L * Vec3(n01(rng), n01(rng), n01(rng));
    s.truth_q_nb = s.est_q_nb = Quat::Identity();
    s.cov_p_n = P_stated;
    out.push_back(s);
  }
  return out;
}

TEST(Consistency, AConsistentFilterPassesAbout95PercentOfRunsAQuarterCovarianceIsFlagged) {
  std::mt19937_64 rng(20261203);
  Mat3 P;
  P << 4.0, 1.0, 0.5, 1.0, 2.0, 0.3, 0.5, 0.3, 1.0;
  CheckSpec c;
  c.kind = CheckSpec::Kind::kConsistency;
  c.of = "position";
  c.name = "position_consistency";
  int inside = 0;
  const int runs = 1000;
  for (int r = 0; r < runs; ++r) {
    inside += judge_consistency(c, run(rng, P, P, 100), {}, std::nullopt).passed ? 1 : 0;
  }
  // Binomial(1000, 0.95): 95 % within ±1.4 %; ±3 % is ~4.4 sigma.
  EXPECT_GT(inside, 920);
  EXPECT_LT(inside, 980);
  int flagged = 0;
  for (int r = 0; r < 100; ++r) {
    const auto result = judge_consistency(c, run(rng, P, 0.25 * P, 100), {}, std::nullopt);
    flagged += result.passed ? 0 : 1;
    if (r == 0) {
      EXPECT_NEAR(result.value, 12.0, 1.5);  // 4 × 3
      EXPECT_NE(result.detail.find("too small"), std::string::npos) << result.detail;
    }
  }
  EXPECT_EQ(flagged, 100);
}

TEST(Consistency, NotPositiveDefiniteFailsNoneStatedIsNotJudged) {
  std::mt19937_64 rng(7);
  CheckSpec c;
  c.kind = CheckSpec::Kind::kConsistency;
  c.of = "position";
  c.name = "position_consistency";
  auto samples = run(rng, Mat3::Identity(), Mat3::Identity(), 10);
  samples[4].cov_p_n = Mat3::Zero();
  const auto bad = judge_consistency(c, samples, {}, std::nullopt);
  EXPECT_TRUE(bad.judged);
  EXPECT_FALSE(bad.passed);
  EXPECT_EQ(bad.detail, "the stated position covariance at t=4.00 s is not positive definite");
  for (auto& s : samples) s.cov_p_n.reset();
  const auto none = judge_consistency(c, samples, {}, std::nullopt);
  EXPECT_FALSE(none.judged);
  EXPECT_EQ(none.detail, "no covariance: the DUT stated none for its position");
  c.of = "attitude";
  c.name = "attitude_consistency";
  EXPECT_FALSE(judge_consistency(c, samples, {}, std::nullopt).judged);
}

}  // namespace
}  // namespace nav::bench::detail
