// SPDX-License-Identifier: MIT
// Paper P3's crawler EKF (p3_crawler_ekf.hpp): the odometry of eq 3 on hand-computed moves,
// the Jacobians A and W (eq 7 with its ΔT) against central differences, an update by hand,
// and the gate: no x correction, x's variance kept, P symmetric positive definite (Joseph).
#include "nav/estimator/p3_crawler_ekf.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include <Eigen/Cholesky>

namespace nav::estimator {
namespace {

constexpr double kB = 0.3;  // wheel base [m]

TEST(P3Odometry, StraightTurnInPlaceAndAnArcByHand) {
  // Both wheels 0.1 m heading 30° down the wall: 0.1 m along that direction.
  const P3Vec x0(1.0, 2.0, std::numbers::pi / 6);
  const P3Vec s = p3_motion(x0, P3Input(0.1, 0.1), kB);
  EXPECT_NEAR(s(0), 1.0 + 0.1 * std::cos(std::numbers::pi / 6), 1e-15);
  EXPECT_NEAR(s(1), 2.0 + 0.1 * std::sin(std::numbers::pi / 6), 1e-15);
  EXPECT_DOUBLE_EQ(s(2), x0(2));
  // Opposite travel: a turn in place by 2d/b, the position unchanged; the left wheel ahead
  // turns the robot to its right, towards y′ (θ grows).
  const P3Vec t = p3_motion(x0, P3Input(-0.03, 0.03), kB);
  EXPECT_NEAR(t(2), x0(2) + 0.2, 1e-15);
  EXPECT_NEAR((t.head<2>() - x0.head<2>()).norm(), 0.0, 1e-15);
  // An arc: the chord at the mean heading (RK2), Δs = 0.1, Δθ = 0.1.
  const P3Vec a = p3_motion(P3Vec::Zero(), P3Input(0.085, 0.115), kB);
  EXPECT_NEAR(a(2), 0.1, 1e-15);
  EXPECT_NEAR(a(0), 0.1 * std::cos(0.05), 1e-15);
  EXPECT_NEAR(a(1), 0.1 * std::sin(0.05), 1e-15);
}

TEST(P3Odometry, JacobiansMatchCentralDifferences) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> pos(-5.0, 5.0), ang(-3.0, 3.0), d(-0.05, 0.05);
  const double h = 1e-6;
  for (int n = 0; n < 300; ++n) {
    const P3Vec x(pos(rng), pos(rng), ang(rng));
    const P3Input u(d(rng), d(rng));
    const P3Mat A = p3_state_jacobian(x, u, kB);
    const P3InputJacobian W = p3_input_jacobian(x, u, kB);
    for (int j = 0; j < 3; ++j) {
      P3Vec e = P3Vec::Zero();
      e(j) = h;
      const P3Vec col = (p3_motion(x + e, u, kB) - p3_motion(x - e, u, kB)) / (2 * h);
      EXPECT_LT((A.col(j) - col).norm(), 1e-8) << n << " A col " << j;
    }
    for (int j = 0; j < 2; ++j) {
      P3Input e = P3Input::Zero();
      e(j) = h;
      const P3Vec col = (p3_motion(x, u + e, kB) - p3_motion(x, u - e, kB)) / (2 * h);
      EXPECT_LT((W.col(j) - col).norm(), 1e-8) << n << " W col " << j;
    }
  }
}

TEST(P3CrawlerEkf, AnUpdateByHand) {
  P3Params p;
  p.sigma_x_m = 1.0;
  p.sigma_y_m = 1.0;
  p.sigma_theta_rad = 1.0;
  P3CrawlerEkf f(p, P3Vec::Zero(), P3Mat::Identity());
  // P = I, R = I: K = I/2, half of each innovation, P halves.
  const auto r = f.update(P3Vec(2.0, -4.0, 0.5), true);
  ASSERT_EQ(r.status, UpdateStatus::kFused);
  EXPECT_TRUE(f.state().isApprox(P3Vec(1.0, -2.0, 0.25), 1e-12));
  EXPECT_TRUE(f.covariance().isApprox(0.5 * P3Mat::Identity(), 1e-12));
  EXPECT_NEAR(r.nis, (4.0 + 16.0 + 0.25) / 2.0, 1e-12);
}

TEST(P3CrawlerEkf, TheGateLeavesXAloneAndKeepsPSymmetricPositiveDefinite) {
  P3Params p;
  P3CrawlerEkf f(p, P3Vec(0.0, 0.0, 0.3), P3Mat::Identity() * 0.04);
  // Correlate x with θ and y: drive an arc first.
  for (int k = 0; k < 50; ++k) ASSERT_EQ(f.predict(P3Input(0.012, 0.008)), StepStatus::kApplied);
  const P3Vec before = f.state();
  const P3Mat P_before = f.covariance();
  ASSERT_GT(std::abs(P_before(0, 2)), 1e-6);  // x and θ correlated
  const auto r = f.update(before + P3Vec(0.5, 0.2, 0.01), false);
  ASSERT_EQ(r.status, UpdateStatus::kFused);
  EXPECT_DOUBLE_EQ(f.state()(0), before(0));              // no x correction
  EXPECT_DOUBLE_EQ(f.covariance()(0, 0), P_before(0, 0));  // nor any on its variance
  EXPECT_GT(f.state()(1), before(1));                       // y and θ are corrected
  const P3Mat& P = f.covariance();
  EXPECT_EQ(P, P.transpose());
  const Eigen::LDLT<P3Mat> ldlt(P);
  EXPECT_TRUE((ldlt.vectorD().array() > 0.0).all());
}

TEST(P3CrawlerEkf, HeadingInnovationWrapsAndBadInputIsRefused) {
  P3Params p;
  P3CrawlerEkf f(p, P3Vec(0.0, 0.0, 3.1), P3Mat::Identity() * 0.01);
  const auto r = f.update(P3Vec(0.0, 0.0, -3.1), true);
  ASSERT_EQ(r.status, UpdateStatus::kFused);
  EXPECT_NEAR(r.y(2), 2 * std::numbers::pi - 6.2, 1e-12);  // across ±π, not −6.2
  EXPECT_GT(std::abs(f.state()(2)), 3.1);
  const P3Vec x = f.state();
  EXPECT_EQ(f.predict(P3Input(NAN, 0.0)), StepStatus::kRejectedInvalid);
  EXPECT_EQ(f.update(P3Vec(0.0, INFINITY, 0.0), true).status, UpdateStatus::kRejectedInvalid);
  EXPECT_EQ(f.state(), x);
}

}  // namespace
}  // namespace nav::estimator
