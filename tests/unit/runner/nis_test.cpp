// SPDX-License-Identifier: MIT
// Innovation consistency (judge/consistency.hpp): NIS of a stated `$PNVBINN` by LDLᵀ against
// its definition for every dimension, a consistent synthetic filter's innovations (through
// the wire format) inside their χ² bounds about 95 % of the time and one predicting a quarter
// of its innovation covariance flagged, updates of several dimensions and the choice of one
// measurement, an S that is not positive definite reported, none stated not judged.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>
#include <random>

#include "judge/consistency.hpp"
#include "nav/protocols/navd_innovation.hpp"
#include "nav/protocols/navd_solution.hpp"

namespace nav::bench::detail {
namespace {

using protocols::navd::Innovation;
using Mat4 = Eigen::Matrix4d;

Mat4 spd() {
  Mat4 A;
  A << 1.0, 0.2, -0.3, 0.0, 0.5, 2.0, 0.1, 0.4, -0.2, 0.3, 0.7, 0.0, 0.1, 0.0, 0.2, 3.0;
  return A * A.transpose() + Mat4::Identity();
}

/// ν and S through the wire: encoded as the DUT would, then decoded as the bench reads it.
Innovation stated(const std::string& source, int m, const Eigen::Vector4d& nu, const Mat4& S) {
  protocols::navd::Matrix4 s{};
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) s[static_cast<std::size_t>(4 * i + j)] = S(i, j);
  }
  const auto in = protocols::navd::innovation_of(1, source, m, {nu(0), nu(1), nu(2), nu(3)}, s);
  const std::string line = protocols::navd::encode(in);
  const auto parsed = protocols::nmea::parse_with_limit(
      protocols::ByteSpan(reinterpret_cast<const std::uint8_t*>(line.data()), line.size()),
      protocols::navd::kMaxSentence);
  EXPECT_TRUE(parsed.message) << line;
  const auto back = protocols::navd::decode_innovation(*parsed.message);
  EXPECT_TRUE(back) << line;
  return *back;
}

TEST(Nis, IsTheQuadraticFormOfTheInverseInnovationCovarianceForEveryDimension) {
  const Mat4 S = spd();
  const Eigen::Vector4d nu(0.3, -1.2, 0.7, 2.0);
  for (int m = 1; m <= 4; ++m) {
    const auto i = stated("x", m, nu, S);
    const auto v = nis(i);
    ASSERT_TRUE(v) << m;
    const Eigen::MatrixXd Sm = S.topLeftCorner(m, m);
    const Eigen::VectorXd num = nu.head(m);
    // σ to six significant digits and ρ to four decimals on the wire.
    EXPECT_NEAR(*v, num.dot(Sm.llt().solve(num)), 2e-3 * *v) << m;
  }
  Innovation zero = stated("x", 2, nu, S);
  zero.sigma[1] = 0.0;
  EXPECT_FALSE(nis(zero));
  Innovation singular = stated("x", 2, nu, S);
  singular.rho[0] = 1.0;
  singular.sigma[1] = singular.sigma[0];
  EXPECT_FALSE(nis(singular));  // perfectly correlated: S is singular
  // An absurd innovation overflows to an infinite NIS, never to "not positive definite".
  Innovation absurd = stated("x", 2, nu, S);
  absurd.nu[0] = 1e300;
  absurd.nu[1] = -1e300;
  ASSERT_TRUE(nis(absurd));
  EXPECT_TRUE(std::isinf(*nis(absurd)));
}

/// K updates of one measurement of m dimensions, ν drawn from N(0, S_true), S_stated stated.
std::vector<reports::InnovationSample> updates(std::mt19937_64& rng, const std::string& source,
                                               int m, const Mat4& S_true, const Mat4& S_stated,
                                               int k) {
  const Mat4 L = S_true.llt().matrixL();
  std::normal_distribution<double> n01;
  std::vector<reports::InnovationSample> out;
  for (int i = 0; i < k; ++i) {
    Eigen::Vector4d w(n01(rng), n01(rng), n01(rng), n01(rng));
    Eigen::Vector4d nu = Eigen::Vector4d::Zero();
    // ν of the top-left m×m block: L's top-left block is the Cholesky factor of S's.
    nu.head(m) = L.topLeftCorner(m, m) * w.head(m);
    const auto v = nis(stated(source, m, nu, S_stated));
    out.push_back({static_cast<double>(i), source, m, v.value_or(std::nan(""))});
  }
  return out;
}

CheckSpec innovation_check(std::string source = {}) {
  CheckSpec c;
  c.kind = CheckSpec::Kind::kConsistency;
  c.of = "innovation";
  c.source = std::move(source);
  c.name = "innovation_consistency";
  return c;
}

TEST(InnovationConsistency, AConsistentFilterPassesAbout95PercentOfRunsAQuarterSIsFlagged) {
  std::mt19937_64 rng(20261203);
  const Mat4 S = spd();
  const CheckSpec c = innovation_check();
  int inside = 0;
  const int runs = 400;
  for (int r = 0; r < runs; ++r) {
    inside += judge_consistency(c, {}, updates(rng, "euler", 3, S, S, 100), std::nullopt).passed;
  }
  // Binomial(400, 0.95): sd 1.1 %; 95 % ± 4.5 % is over 4 sigma.
  EXPECT_GT(inside, 362);
  EXPECT_LT(inside, 398);
  int flagged = 0;
  for (int r = 0; r < 50; ++r) {
    const auto result =
        judge_consistency(c, {}, updates(rng, "euler", 3, S, 0.25 * S, 100), std::nullopt);
    flagged += result.passed ? 0 : 1;
    if (r == 0) {
      EXPECT_NEAR(result.value, 12.0, 1.5);  // 4 × 3
      EXPECT_NE(result.detail.find("too small"), std::string::npos) << result.detail;
    }
  }
  EXPECT_EQ(flagged, 50);
  // Four times S: the NIS a quarter of m, flagged as too large.
  const auto cautious =
      judge_consistency(c, {}, updates(rng, "euler", 3, S, 4.0 * S, 100), std::nullopt);
  EXPECT_FALSE(cautious.passed);
  EXPECT_NE(cautious.detail.find("too large"), std::string::npos) << cautious.detail;
}

TEST(InnovationConsistency, SeveralMeasurementsTogetherOrOneByName) {
  std::mt19937_64 rng(11);
  const Mat4 S = spd();
  // A GPS-like mix: 1 Hz positions (3 dof) consistent, depths (1 dof) overconfident ×100.
  auto all = updates(rng, "gps-position", 3, S, S, 300);
  const auto depth = updates(rng, "depth", 1, S, 0.01 * S, 300);
  all.insert(all.end(), depth.begin(), depth.end());
  const auto gps = judge_consistency(innovation_check("gps-position"), {}, all, std::nullopt);
  EXPECT_TRUE(gps.judged);
  EXPECT_NEAR(gps.value, 3.0, 0.5);
  EXPECT_NE(gps.detail.find("over 300 updates of gps-position (3 dof on average)"),
            std::string::npos)
      << gps.detail;
  const auto d = judge_consistency(innovation_check("depth"), {}, all, std::nullopt);
  EXPECT_FALSE(d.passed);
  EXPECT_NEAR(d.value, 100.0, 30.0);
  // Together: Σ NIS over Σ m = 1200 degrees of freedom, the average ≈ (3 + 100) / 2.
  const auto together = judge_consistency(innovation_check(), {}, all, std::nullopt);
  EXPECT_FALSE(together.passed);
  EXPECT_NE(together.detail.find("of any measurement (2 dof on average)"), std::string::npos)
      << together.detail;
  const auto [lo, hi] = average_chi2_bounds(600, 1200.0);
  EXPECT_NEAR(together.limit, hi, 1e-12);
  EXPECT_NEAR(lo, 1.842, 0.01);  // χ²_1200(0.025)/600 = 1.8421
}

TEST(InnovationConsistency, NotPositiveDefiniteFailsNoneStatedIsNotJudged) {
  std::mt19937_64 rng(7);
  auto samples = updates(rng, "mag", 3, spd(), spd(), 10);
  samples[4].nis = std::nan("");
  const auto bad = judge_consistency(innovation_check(), {}, samples, std::nullopt);
  EXPECT_TRUE(bad.judged);
  EXPECT_FALSE(bad.passed);
  EXPECT_EQ(bad.detail,
            "the stated innovation covariance of mag at t=4.00 s is not positive definite");
  // An innovation too large for its S (ν = 1e300): an infinite NIS fails, as too small an S.
  samples[4].nis = std::numeric_limits<double>::infinity();
  const auto huge = judge_consistency(innovation_check(), {}, samples, std::nullopt);
  EXPECT_FALSE(huge.passed);
  EXPECT_NE(huge.detail.find("too small"), std::string::npos) << huge.detail;
  const auto other = judge_consistency(innovation_check("euler"), {}, samples, std::nullopt);
  EXPECT_FALSE(other.judged);
  EXPECT_EQ(other.detail, "no innovations: the DUT stated none for euler");
  CheckSpec late = innovation_check();
  late.after = from_seconds(20.0);
  const auto stopped = judge_consistency(late, {}, samples, 9.5);
  EXPECT_FALSE(stopped.judged);
  EXPECT_EQ(stopped.detail,
            "not judged: the run was stopped at t=9.50 s, before its 'after' (20.00 s)");
}

}  // namespace
}  // namespace nav::bench::detail
