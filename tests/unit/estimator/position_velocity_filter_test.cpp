// SPDX-License-Identifier: MIT
#include "nav/estimator/position_velocity_filter.hpp"

#include <cmath>
#include <limits>
#include <random>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "test_support.hpp"

namespace nav::estimator {
namespace {

using pv::Covariance;
using pv::State;

TEST(PvModel, HandComputedPredictAndPositionUpdate) {
  // GIVEN x0 = 0, P0 = I, q = 1 m/s²/√Hz
  PositionVelocityFilter kf(State::Zero(), Covariance::Identity());
  // WHEN predicting 1 s with a_n = (1, 0, 0) m/s²
  ASSERT_EQ(kf.predict(Vec3(1.0, 0.0, 0.0), 1.0, 1.0), StepStatus::kApplied);
  // THEN p = ½ a dt² = 0.5, v = a dt = 1, and per axis
  //      P = F P Fᵀ + Q = [[2, 1], [1, 1]] + [[1/3, 1/2], [1/2, 1]] = [[7/3, 3/2], [3/2, 2]]
  EXPECT_DOUBLE_EQ(kf.p_n().x(), 0.5);
  EXPECT_DOUBLE_EQ(kf.v_n().x(), 1.0);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(kf.P()(a, a), 7.0 / 3.0, 1e-15);
    EXPECT_NEAR(kf.P()(a, 3 + a), 1.5, 1e-15);
    EXPECT_NEAR(kf.P()(3 + a, 3 + a), 2.0, 1e-15);
  }
  // WHEN fusing a position z = (1, 0, 0) m with σ = 1 m per axis
  const auto r = kf.update_position(Vec3(1.0, 0.0, 0.0), Vec3::Ones());
  // THEN y = 0.5, S = 7/3 + 1 = 10/3, K = [0.7, 0.45], NIS = 0.25 / (10/3) = 0.075,
  //      p = 0.5 + 0.7·0.5 = 0.85, v = 1 + 0.45·0.5 = 1.225,
  //      P = [[7/3 − 0.49·10/3, 1.5 − 0.315·10/3], [·, 2 − 0.2025·10/3]]
  //        = [[0.7, 0.45], [0.45, 1.325]]
  ASSERT_EQ(r.status, UpdateStatus::kFused);
  EXPECT_NEAR(r.y.x(), 0.5, 1e-15);
  EXPECT_NEAR(r.S(0, 0), 10.0 / 3.0, 1e-14);
  EXPECT_NEAR(r.nis, 0.075, 1e-14);
  EXPECT_NEAR(kf.p_n().x(), 0.85, 1e-14);
  EXPECT_NEAR(kf.v_n().x(), 1.225, 1e-14);
  EXPECT_NEAR(kf.P()(0, 0), 0.7, 1e-14);
  EXPECT_NEAR(kf.P()(0, 3), 0.45, 1e-14);
  EXPECT_NEAR(kf.P()(3, 3), 1.325, 1e-14);
  EXPECT_NEAR(kf.p_n().y(), 0.0, 1e-15);
}

TEST(PvModel, HandComputedDownPositionUpdate) {
  // GIVEN p_D = 1 m, v_D = 0.5 m/s, per axis P = [[4, 1], [1, 2]] (position, velocity)
  State x0 = State::Zero();
  x0(pv::kPos.idx + 2) = 1.0;
  x0(pv::kVel.idx + 2) = 0.5;
  Covariance P0 = Covariance::Identity();
  for (int a = 0; a < 3; ++a) {
    P0(a, a) = 4.0;
    P0(a, 3 + a) = P0(3 + a, a) = 1.0;
    P0(3 + a, 3 + a) = 2.0;
  }
  PositionVelocityFilter kf(x0, P0);
  // WHEN fusing p_D = 3 m with σ = 2 m (M9)
  const auto r = kf.update_down_position(3.0, 2.0);
  // THEN y = 2, S = 4 + 4 = 8, K = [4, 1] / 8 = [0.5, 0.125] on (p_D, v_D), NIS = 4 / 8,
  //      p_D = 1 + 0.5·2 = 2, v_D = 0.5 + 0.125·2 = 0.75,
  //      P = [[4 − 0.25·8, 1 − 0.0625·8], [·, 2 − 0.015625·8]] = [[2, 0.5], [0.5, 1.875]],
  //      North and East untouched
  ASSERT_EQ(r.status, UpdateStatus::kFused);
  EXPECT_NEAR(r.y(0), 2.0, 1e-15);
  EXPECT_NEAR(r.S(0, 0), 8.0, 1e-15);
  EXPECT_NEAR(r.nis, 0.5, 1e-15);
  EXPECT_NEAR(kf.p_n().z(), 2.0, 1e-15);
  EXPECT_NEAR(kf.v_n().z(), 0.75, 1e-15);
  EXPECT_NEAR(kf.P()(2, 2), 2.0, 1e-14);
  EXPECT_NEAR(kf.P()(2, 5), 0.5, 1e-14);
  EXPECT_NEAR(kf.P()(5, 5), 1.875, 1e-14);
  EXPECT_DOUBLE_EQ(kf.P()(0, 0), 4.0);
  EXPECT_DOUBLE_EQ(kf.P()(3, 3), 2.0);
  EXPECT_DOUBLE_EQ(kf.p_n().x(), 0.0);
  // A NaN depth or standard deviation leaves the filter alone.
  EXPECT_EQ(kf.update_down_position(std::numeric_limits<double>::quiet_NaN(), 1.0).status,
            UpdateStatus::kRejectedInvalid);
  EXPECT_EQ(kf.update_down_position(1.0, std::numeric_limits<double>::infinity()).status,
            UpdateStatus::kRejectedInvalid);
  EXPECT_NEAR(kf.p_n().z(), 2.0, 1e-15);
}

TEST(PvModel, HandComputedVelocityUpdate) {
  // GIVEN v = (1, 2, 0), P = I; WHEN fusing [v_N, v_E] = (1.5, 2) with σ = 1 m/s
  State x0 = State::Zero();
  x0.segment<3>(pv::kVel.idx) = Vec3(1.0, 2.0, 0.0);
  PositionVelocityFilter kf(x0, Covariance::Identity());
  const auto r = kf.update_horizontal_velocity(Vec<2>(1.5, 2.0), 1.0);
  // THEN S = 2 I, K = ½ on v_N and v_E, v_N = 1.25, P_vN = 0.5, NIS = 0.25 / 2
  ASSERT_EQ(r.status, UpdateStatus::kFused);
  EXPECT_NEAR(kf.v_n().x(), 1.25, 1e-15);
  EXPECT_NEAR(kf.v_n().y(), 2.0, 1e-15);
  EXPECT_NEAR(kf.P()(3, 3), 0.5, 1e-15);
  EXPECT_NEAR(kf.P()(5, 5), 1.0, 1e-15);  // v_D is not observed
  EXPECT_NEAR(r.nis, 0.125, 1e-15);
}

TEST(PvModel, SogCogToNorthEast) {
  const Vec<2> v = pv::velocity_from_sog_cog(2.0, std::numbers::pi / 2.0);  // due East
  EXPECT_NEAR(v.x(), 0.0, 1e-15);
  EXPECT_NEAR(v.y(), 2.0, 1e-15);
}

TEST(PvModel, NavAccelerationOfAStaticVehicleIsZero) {
  const Quat q = quat_from_euler({0.2, -0.1, 2.0});
  const double g = 9.79;
  const Vec3 f_b = q.conjugate() * Vec3(0.0, 0.0, -g);
  EXPECT_LT(pv::nav_acceleration(q, f_b, g).norm(), 1e-14);
}

TEST(PvModel, JacobiansMatchFiniteDifferences) {
  // F = ∂f/∂x and G = ∂f/∂a_n against central differences of the motion model.
  const double dt = 0.037;
  State x;
  x << 1.0, -2.0, 3.0, 0.4, -0.5, 0.6;
  const Vec3 a(0.3, -0.2, 0.1);
  const double h = 1e-6;
  Covariance F_num;
  for (int i = 0; i < pv::kStateSize; ++i) {
    State dx = State::Zero();
    dx(i) = h;
    F_num.col(i) = (pv::propagate(x + dx, a, dt) - pv::propagate(x - dx, a, dt)) / (2 * h);
  }
  EXPECT_LT((F_num - pv::transition_jacobian(dt)).cwiseAbs().maxCoeff(), 1e-9);
  Mat<pv::kStateSize, 3> G_num;
  for (int i = 0; i < 3; ++i) {
    Vec3 da = Vec3::Zero();
    da(i) = h;
    G_num.col(i) = (pv::propagate(x, a + da, dt) - pv::propagate(x, a - da, dt)) / (2 * h);
  }
  EXPECT_LT((G_num - pv::input_jacobian(dt)).cwiseAbs().maxCoeff(), 1e-9);
  // H of the measurements against differences of h(x) = p_n, h(x) = [v_N, v_E] and
  // h(x) = p_D.
  Mat<3, pv::kStateSize> Hp_num;
  Mat<2, pv::kStateSize> Hv_num;
  Mat<1, pv::kStateSize> Hd_num;
  for (int i = 0; i < pv::kStateSize; ++i) {
    State dx = State::Zero();
    dx(i) = h;
    Hp_num.col(i) = ((x + dx).segment<3>(0) - (x - dx).segment<3>(0)) / (2 * h);
    Hv_num.col(i) = ((x + dx).segment<2>(3) - (x - dx).segment<2>(3)) / (2 * h);
    Hd_num(0, i) = ((x + dx)(2) - (x - dx)(2)) / (2 * h);
  }
  EXPECT_LT((Hp_num - pv::position_jacobian()).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((Hv_num - pv::horizontal_velocity_jacobian()).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((Hd_num - pv::down_position_jacobian()).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(PvModel, ProcessNoiseIsPositiveDefinite) {
  const Covariance Q = pv::process_noise(0.2, 0.01);
  EXPECT_TRUE(Q.isApprox(Q.transpose()));
  EXPECT_EQ(Q.llt().info(), Eigen::Success);
  EXPECT_NEAR(Q(3, 3), 0.04 * 0.01, 1e-18);
}

/// Simulated vehicle at constant velocity, accel measured with white noise of density q,
/// GPS position (1 Hz) and velocity (1 Hz) with white noise; fixed seed.
struct Simulation {
  double q = 0.2;           // [m/s²/√Hz]
  double dt = 0.01;         // [s]
  double sigma_h = 2.0;     // [m]
  double sigma_v = 4.0;     // [m]
  double sigma_vel = 0.2;   // [m/s]
  Vec3 v_true{1.0, 0.5, 0.0};
};

TEST(PositionVelocityFilter, NoisyGpsConvergesAndStaysConsistent) {
  // GIVEN the simulation above over 600 s, seed 42
  const Simulation sim;
  std::mt19937_64 rng(42);
  std::normal_distribution<double> n01(0.0, 1.0);
  Covariance P0 = Covariance::Zero();
  P0.diagonal() << 100, 100, 100, 4, 4, 4;
  State x0 = State::Zero();
  x0.segment<3>(0) = Vec3(8.0, -6.0, 5.0);  // start 11.2 m off
  PositionVelocityFilter kf(x0, P0);
  Vec3 p_true = Vec3::Zero();
  int checks = 0, inside_3sigma = 0;
  double nees_sum = 0.0, nis_sum = 0.0;
  int nis_count = 0;
  const int steps_per_s = static_cast<int>(std::lround(1.0 / sim.dt));
  for (int k = 1; k <= 600 * steps_per_s; ++k) {
    p_true += sim.v_true * sim.dt;
    const double a_std = sim.q / std::sqrt(sim.dt);  // white accel noise of density q
    const Vec3 a_meas(a_std * n01(rng), a_std * n01(rng), a_std * n01(rng));
    kf.predict(a_meas, sim.dt, sim.q);
    if (k % steps_per_s != 0) continue;
    // WHEN GPS fixes arrive at 1 Hz
    const Vec3 z_p = p_true + Vec3(sim.sigma_h * n01(rng), sim.sigma_h * n01(rng),
                                   sim.sigma_v * n01(rng));
    const auto rp = kf.update_position(z_p, Vec3(sim.sigma_h, sim.sigma_h, sim.sigma_v));
    ASSERT_EQ(rp.status, UpdateStatus::kFused);
    const Vec<2> z_v = sim.v_true.head<2>() + Vec<2>(sim.sigma_vel * n01(rng),
                                                     sim.sigma_vel * n01(rng));
    ASSERT_EQ(kf.update_horizontal_velocity(z_v, sim.sigma_vel).status, UpdateStatus::kFused);
    if (k < 30 * steps_per_s) continue;  // judge after 30 s of convergence
    // THEN the error stays within a few sigma of the filter's own covariance
    State x_true;
    x_true << p_true, sim.v_true;
    const State err = kf.x() - x_true;
    for (int i = 0; i < 3; ++i) {
      ++checks;
      inside_3sigma += std::abs(err(i)) <= 3.0 * std::sqrt(kf.P()(i, i)) ? 1 : 0;
    }
    nees_sum += err.dot(kf.P().ldlt().solve(err));
    nis_sum += rp.nis;
    ++nis_count;
  }
  EXPECT_GE(static_cast<double>(inside_3sigma) / checks, 0.98);
  const double nees = nees_sum / nis_count;  // expected 6 (state dimension)
  const double nis = nis_sum / nis_count;    // expected 3 (position measurement dimension)
  EXPECT_GT(nees, 4.0);
  EXPECT_LT(nees, 8.0);
  EXPECT_GT(nis, 2.5);
  EXPECT_LT(nis, 3.5);
  EXPECT_LT((kf.p_n() - p_true).head<2>().norm(), 3.0 * sim.sigma_h);
}

TEST(PositionVelocityFilter, CovarianceStaysSymmetricPositiveDefinite) {
  // GIVEN random intervals, accelerations and measurements over 20000 steps, seed 7
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.001, 0.05);
  std::normal_distribution<double> n01(0.0, 1.0);
  PositionVelocityFilter kf(State::Zero(), Covariance::Identity() * 10.0);
  for (int k = 0; k < 20000; ++k) {
    kf.predict(Vec3(n01(rng), n01(rng), n01(rng)), u(rng), 0.3);
    if (k % 7 == 0) kf.update_position(Vec3(n01(rng), n01(rng), n01(rng)), Vec3(0.01, 0.01, 0.02));
    if (k % 11 == 0) kf.update_horizontal_velocity(Vec<2>(n01(rng), n01(rng)), 0.001);
  }
  // THEN P is exactly symmetric and its eigenvalues are positive
  const Covariance& P = kf.P();
  EXPECT_EQ((P - P.transpose()).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(P.llt().info(), Eigen::Success);
  const Eigen::SelfAdjointEigenSolver<Covariance> eig(P);
  EXPECT_GT(eig.eigenvalues().minCoeff(), 0.0);
  EXPECT_TRUE(kf.x().allFinite());
}

TEST(PositionVelocityFilter, NanAndInfAreRejectedWithoutChangingTheState) {
  PositionVelocityFilter kf(State::Zero(), Covariance::Identity());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(kf.update_position(Vec3(nan, 0, 0), Vec3::Ones()).status,
            UpdateStatus::kRejectedInvalid);
  EXPECT_EQ(kf.update_position(Vec3::Zero(), Vec3(1, inf, 1)).status,
            UpdateStatus::kRejectedInvalid);
  EXPECT_EQ(kf.update_horizontal_velocity(Vec<2>(0, nan), 1.0).status,
            UpdateStatus::kRejectedInvalid);
  EXPECT_EQ(kf.predict(Vec3(0, inf, 0), 0.01, 0.2), StepStatus::kRejectedInvalid);
  EXPECT_EQ(kf.x(), State::Zero());
  EXPECT_EQ(kf.P(), Covariance::Identity());
}

TEST(PositionVelocityFilter, IndefiniteInnovationCovarianceIsANumericalFault) {
  // GIVEN R = −100 I (not a covariance) so S = H P Hᵀ + R is negative definite
  State x = State::Zero();
  Covariance P = Covariance::Identity();
  const auto r = linear_update<pv::kStateSize, 3>(x, P, Vec3(1, 2, 3), pv::position_jacobian(),
                                                  Mat3::Identity() * -100.0);
  // THEN the update reports a numerical fault and leaves x and P untouched
  EXPECT_EQ(r.status, UpdateStatus::kNumericalFault);
  EXPECT_EQ(x, State::Zero());
  EXPECT_EQ(P, Covariance::Identity());
}

TEST(PositionVelocityFilter, GateRejectsAnOutlier) {
  PositionVelocityFilter kf(State::Zero(), Covariance::Identity());
  // 100 m jump against S = 2 I: NIS = 5000 > 11.34 (chi² 3 dof, 99 %)
  const auto r = kf.update_position(Vec3(100, 0, 0), Vec3::Ones(), 11.34);
  EXPECT_EQ(r.status, UpdateStatus::kRejectedGate);
  EXPECT_NEAR(r.nis, 5000.0, 1e-9);
  EXPECT_EQ(kf.x(), State::Zero());
  EXPECT_STREQ(to_string(r.status), "rejected_gate");
}

TEST(PositionVelocityFilter, NonPositiveDtIsAContractViolation) {
  PositionVelocityFilter kf(State::Zero(), Covariance::Identity());
  EXPECT_THROW(kf.predict(Vec3::Zero(), 0.0, 0.2), std::logic_error);
}

}  // namespace
}  // namespace nav::estimator
