// SPDX-License-Identifier: MIT
// Paper P4's planar beacon UKF (p4_beacon_ukf.hpp): the paper's UT weights for several κ, the
// process model by hand, one predict against the linear KF (F P Fᵀ + Q with F and Q written out
// here) and one GPS update against the KF by hand, the compass innovation wrapped across 0/2π,
// ψ continuous through ±π, a simulated beacon driving a circle (position RMS, gyro bias,
// final error within 3σ of P), dead reckoning without GPS, and every refusal. Fixed seeds.
#include "nav/estimator/p4_beacon_ukf.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include "test_support.hpp"

namespace nav::estimator {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = std::numbers::pi;
constexpr int kN = P4Idx::kDim;

/// A fixed symmetric positive definite P with O(1) entries and correlations everywhere.
P4Mat correlated_covariance(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  P4Mat A;
  for (int r = 0; r < kN; ++r) {
    for (int c = 0; c < kN; ++c) A(r, c) = 0.5 * normal(rng);
  }
  return A * A.transpose() + 0.1 * P4Mat::Identity();
}

TEST(P4Weights, SumToOneAndAreThePapersForSeveralKappa) {
  for (const double kappa : {0.0, 1.0, 0.5, 2.0, 3.0, -2.0, -3.0}) {
    SCOPED_TRACE("kappa=" + std::to_string(kappa));
    P4UkfParams p;
    p.kappa = kappa;
    const P4BeaconUkf f(p);
    const UnscentedWeights<kN>& w = f.weights();
    EXPECT_NEAR(w.mean.sum(), 1.0, 1e-15);
    EXPECT_NEAR(w.mean(0), kappa / (kN + kappa), 1e-15);           // W₁ = κ/(n+κ)
    for (int j = 1; j < UnscentedWeights<kN>::kPoints; ++j) {
      EXPECT_NEAR(w.mean(j), 1.0 / (2.0 * (kN + kappa)), 1e-15);   // W_{i>1} = 1/(2(n+κ))
    }
    // β = 0, α = 1: the covariance weights are the same (W₀⁽ᶜ⁾ = W₀⁽ᵐ⁾ + 1 − α² + β, rounded).
    EXPECT_LT((w.cov - w.mean).cwiseAbs().maxCoeff(), 1e-15);
    EXPECT_NEAR(w.gamma * w.gamma, kN + kappa, 1e-13);             // Uᵀ U = (n + κ) P
  }
  // The default κ = 0: no negative weight, the centre point unweighted.
  const P4BeaconUkf f(P4UkfParams{});
  EXPECT_EQ(f.weights().mean(0), 0.0);
  EXPECT_GE(f.weights().cov.minCoeff(), 0.0);
}

TEST(P4Process, ModelByHandHeadingEast) {
  // ψ = 90°: body x points East, body y (starboard) South.
  P4Vec x;
  x << 1.0, 2.0, 0.3, -0.4, kPi / 2, 0.01;
  const P4Input u{0.2, 0.1, 0.05};
  const double dt = 0.5;
  const P4Vec y = p4_process(x, u, dt);
  const double a_N = -0.1, a_E = 0.2;  // B1, B2 by hand
  EXPECT_NEAR(y(P4Idx::kN), 1.0 + 0.3 * dt + 0.5 * a_N * dt * dt, 1e-15);
  EXPECT_NEAR(y(P4Idx::kE), 2.0 - 0.4 * dt + 0.5 * a_E * dt * dt, 1e-15);
  EXPECT_NEAR(y(P4Idx::kVn), 0.3 + a_N * dt, 1e-15);
  EXPECT_NEAR(y(P4Idx::kVe), -0.4 + a_E * dt, 1e-15);
  EXPECT_NEAR(y(P4Idx::kPsi), kPi / 2 + (0.05 - 0.01) * dt, 1e-15);
  EXPECT_EQ(y(P4Idx::kBgz), 0.01);
}

// With f = 0 the model is linear in x (the acceleration, the only place ψ enters nonlinearly,
// vanishes), so the UKF must reproduce the KF exactly; ψ = 0 and ω_z = b as in a level,
// non-turning beacon. (With f ≠ 0 and a heading spread in P it is not linear.)
TEST(P4Predict, LinearCaseEqualsTheKalmanFilterByHand) {
  for (const double kappa : {0.0, 1.0}) {
    SCOPED_TRACE("kappa=" + std::to_string(kappa));
    P4UkfParams p;
    p.kappa = kappa;
    p.accel_noise_density_mps2_rthz = 0.3;
    p.gyro_noise_density_radps_rthz = 0.02;
    p.gyro_bias_walk_radps_rtsec = 0.01;
    P4BeaconUkf f(p);
    P4Vec x0;
    x0 << 10.0, -5.0, 1.5, -0.7, 0.0, 0.003;
    const P4Mat P0 = correlated_covariance(11);
    ASSERT_EQ(f.reset(x0, P0), StepStatus::kApplied);
    const double dt = 0.1;
    ASSERT_EQ(f.predict(P4Input{0.0, 0.0, 0.003}, dt), StepStatus::kApplied);

    P4Mat F = P4Mat::Identity();  // rows N, E, v_N, v_E, ψ, b
    F(0, 2) = dt;
    F(1, 3) = dt;
    F(4, 5) = -dt;
    const double qa2 = 0.3 * 0.3, qg2 = 0.02 * 0.02, qb2 = 0.01 * 0.01;
    P4Mat Q = P4Mat::Zero();
    Q(0, 0) = Q(1, 1) = qa2 * dt * dt * dt / 3.0;
    Q(0, 2) = Q(2, 0) = Q(1, 3) = Q(3, 1) = qa2 * dt * dt / 2.0;
    Q(2, 2) = Q(3, 3) = qa2 * dt;
    Q(4, 4) = qg2 * dt + qb2 * dt * dt * dt / 3.0;
    Q(4, 5) = Q(5, 4) = -qb2 * dt * dt / 2.0;
    Q(5, 5) = qb2 * dt;
    P4Vec x_expected = F * x0;
    x_expected(4) += 0.003 * dt;  // + ω_z dt
    const P4Mat P_expected = F * P0 * F.transpose() + Q;
    EXPECT_LT((f.x() - x_expected).cwiseAbs().maxCoeff(), 1e-12) << f.x().transpose();
    EXPECT_LT((f.P() - P_expected).cwiseAbs().maxCoeff(), 1e-12) << "\n" << f.P();
    EXPECT_LT((p4_process_noise(p, dt) - Q).cwiseAbs().maxCoeff(), 1e-18);
  }
}

TEST(P4Update, GpsPositionEqualsTheKalmanFilterByHand) {
  P4UkfParams p;
  p.gps_position_std_m = 0.8;
  P4BeaconUkf f(p);
  P4Vec x0;
  x0 << 3.0, 4.0, 0.5, 0.2, 1.0, -0.002;
  const P4Mat P0 = correlated_covariance(12);
  ASSERT_EQ(f.reset(x0, P0), StepStatus::kApplied);
  const Eigen::Vector2d z(3.9, 3.1);
  const UpdateReport<2> r = f.update_gps_position(z);
  ASSERT_EQ(r.status, UpdateStatus::kFused);

  Mat<2, kN> H = Mat<2, kN>::Zero();
  H(0, 0) = H(1, 1) = 1.0;
  const Eigen::Matrix2d R = 0.64 * Eigen::Matrix2d::Identity();
  const Eigen::Vector2d y = z - H * x0;
  const Eigen::Matrix2d S = H * P0 * H.transpose() + R;
  const Eigen::LDLT<Eigen::Matrix2d> S_ldlt(S);
  const Mat<kN, 2> K = S_ldlt.solve(H * P0).transpose();  // K = P Hᵀ S⁻¹
  const P4Vec x_expected = x0 + K * y;
  const P4Mat P_expected = (P4Mat::Identity() - K * H) * P0;
  EXPECT_LT((r.y - y).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((r.S - S).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(r.nis, y.dot(S_ldlt.solve(y)), 1e-12);
  EXPECT_LT((f.x() - x_expected).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((f.P() - P_expected).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(P4Compass, InnovationWrapsAcrossNorth) {
  P4BeaconUkf f(P4UkfParams{});
  P4Vec x0 = P4Vec::Zero();
  x0(P4Idx::kPsi) = 0.01;
  const P4Mat P0 = P4Vec(1.0, 1.0, 0.1, 0.1, 0.01, 1e-4).asDiagonal();
  ASSERT_EQ(f.reset(x0, P0), StepStatus::kApplied);
  const UpdateReport<1> r = f.update_compass(2.0 * kPi - 0.01);
  ASSERT_EQ(r.status, UpdateStatus::kFused);
  EXPECT_NEAR(r.y(0), -0.02, 1e-12);  // not ≈ 2π
  EXPECT_LT(f.x()(P4Idx::kPsi), 0.01);
  EXPECT_GT(f.x()(P4Idx::kPsi), -0.02);
  EXPECT_LT(r.nis, 1.0);

  // A continuous ψ three turns up, just below π; measured just past π (in [0, 2π)).
  x0(P4Idx::kPsi) = 6.0 * kPi + kPi - 0.01;
  ASSERT_EQ(f.reset(x0, P0), StepStatus::kApplied);
  const UpdateReport<1> r2 = f.update_compass(kPi + 0.01);
  ASSERT_EQ(r2.status, UpdateStatus::kFused);
  EXPECT_NEAR(r2.y(0), 0.02, 1e-12);
  EXPECT_GT(f.x()(P4Idx::kPsi), 7.0 * kPi - 0.01);  // stays on its turn
  EXPECT_GE(f.heading(), 0.0);
  EXPECT_LT(f.heading(), 2.0 * kPi);
  EXPECT_NEAR(f.heading(), wrap_two_pi(f.x()(P4Idx::kPsi)), 1e-12);
}

TEST(P4Heading, StaysContinuousThroughPiAndOutputIsWrapped) {
  P4BeaconUkf f(P4UkfParams{});
  P4Vec x0 = P4Vec::Zero();
  x0(P4Idx::kPsi) = kPi - 0.05;
  ASSERT_EQ(f.reset(x0, 0.01 * P4Mat::Identity()), StepStatus::kApplied);
  for (int k = 0; k < 10; ++k) {
    ASSERT_EQ(f.predict(P4Input{0.0, 0.0, 1.0}, 0.01), StepStatus::kApplied);
  }
  EXPECT_NEAR(f.x()(P4Idx::kPsi), kPi + 0.05, 1e-12);  // not wrapped inside the state
  EXPECT_NEAR(f.heading(), kPi + 0.05, 1e-12);
  EXPECT_EQ(wrap_two_pi(-1e-18), 0.0);
  EXPECT_NEAR(wrap_two_pi(-0.5 * kPi), 1.5 * kPi, 1e-15);
  EXPECT_NEAR(wrap_two_pi(9.0 * kPi), kPi, 1e-14);
}

TEST(P4Velocity, RmcSpeedAndCourseAsNedVelocity) {
  const Eigen::Vector2d v = rmc_velocity_ne(2.0, kPi / 2);  // 2 m/s due East
  EXPECT_NEAR(v(0), 0.0, 1e-15);
  EXPECT_NEAR(v(1), 2.0, 1e-15);
  P4BeaconUkf f(P4UkfParams{});
  ASSERT_EQ(f.initialise(Eigen::Vector2d(1.0, 2.0), 1.0), StepStatus::kApplied);
  const UpdateReport<2> r = f.update_gps_velocity(v);
  ASSERT_EQ(r.status, UpdateStatus::kFused);
  // P₀ diagonal: v_E pulled by σ_v0²/(σ_v0² + σ_v²) of the innovation, v_N stays.
  const double k = 1.0 / (1.0 + 0.04);
  EXPECT_NEAR(f.velocity_ne()(1), 2.0 * k, 1e-12);
  EXPECT_NEAR(f.velocity_ne()(0), 0.0, 1e-12);
}

/// A beacon driving a circle at 50 Hz with seeded sensor noise, GPS and compass at 1 Hz.
struct CircleRun {
  double rms_m = 0.0;           ///< horizontal error RMS over t >= 30 s [m]
  double mean_nees = 0.0;       ///< mean position NEES at the GPS epochs, t >= 30 s [-]
  double final_nees = 0.0;      ///< final position NEES [-]
  double bias_error = 0.0;      ///< b̂ − b at the end [rad/s]
  double bias_std = 0.0;        ///< √P_bb at the end [rad/s]
  double heading_error = 0.0;   ///< ψ̂ − ψ at the end, wrapped [rad]
  double heading_std = 0.0;     ///< √P_ψψ [rad]
};

CircleRun run_circle(bool use_rmc_velocity) {
  constexpr double kDt = 0.02, kDuration = 300.0, kSpeed = 2.0;
  constexpr double kOmega = 2.0 * kPi / 120.0, kBias = 0.01, kPsi0 = 0.3;
  constexpr double kAccelDensity = 0.02, kGyroDensity = 1e-3;  // simulated sensors
  const Eigen::Vector2d p0(100.0, -50.0);
  std::mt19937_64 rng(20130301);
  std::normal_distribution<double> normal(0.0, 1.0);
  const auto truth_psi = [&](double t) { return kPsi0 + kOmega * t; };
  const auto truth_pos = [&](double t) {
    const double r = kSpeed / kOmega;
    return Eigen::Vector2d(p0(0) + r * (std::sin(truth_psi(t)) - std::sin(kPsi0)),
                           p0(1) - r * (std::cos(truth_psi(t)) - std::cos(kPsi0)));
  };
  P4UkfParams p;
  p.accel_noise_density_mps2_rthz = 0.05;
  p.gyro_noise_density_radps_rthz = 2e-3;
  p.gyro_bias_walk_radps_rtsec = 1e-5;
  p.gps_position_std_m = 1.0;
  p.compass_std_rad = 2.0 * kPi / 180.0;
  p.gps_velocity_std_mps = 0.1;
  p.initial_position_std_m = 1.0;
  p.initial_velocity_std_mps = 2.0;
  p.initial_heading_std_rad = 2.0 * kPi / 180.0;
  P4BeaconUkf f(p);
  const auto gps = [&](double t) {
    return Eigen::Vector2d(truth_pos(t) + Eigen::Vector2d(normal(rng), normal(rng)));
  };
  const auto compass = [&](double t) {
    return wrap_two_pi(truth_psi(t) + p.compass_std_rad * normal(rng));
  };
  EXPECT_EQ(f.initialise(gps(0.0), compass(0.0)), StepStatus::kApplied);
  CircleRun out;
  double sum_sq = 0.0, sum_nees = 0.0;
  int n_err = 0, n_nees = 0;
  const int steps = static_cast<int>(std::lround(kDuration / kDt));
  const double sa = kAccelDensity / std::sqrt(kDt), sg = kGyroDensity / std::sqrt(kDt);
  for (int k = 0; k < steps; ++k) {
    // Centripetal acceleration V ω to starboard (f_y); the gyro reads ω + b + noise.
    const P4Input u{sa * normal(rng), kSpeed * kOmega + sa * normal(rng),
                    kOmega + kBias + sg * normal(rng)};
    EXPECT_EQ(f.predict(u, kDt), StepStatus::kApplied);
    const double t = (k + 1) * kDt;
    if ((k + 1) % 50 != 0) continue;  // 1 Hz aiding
    EXPECT_EQ(f.update_gps_position(gps(t)).status, UpdateStatus::kFused);
    EXPECT_EQ(f.update_compass(compass(t)).status, UpdateStatus::kFused);
    if (use_rmc_velocity) {
      // RMC speed and course of the true velocity, with 0.1 m/s per axis of noise.
      const Eigen::Vector2d v = rmc_velocity_ne(kSpeed, truth_psi(t)) +
                                0.1 * Eigen::Vector2d(normal(rng), normal(rng));
      EXPECT_EQ(f.update_gps_velocity(v).status, UpdateStatus::kFused);
    }
    const Eigen::Vector2d e = f.position_ne() - truth_pos(t);
    const double nees = e.dot(f.position_covariance_ne().ldlt().solve(e));
    if (t >= 30.0) {
      sum_sq += e.squaredNorm();
      ++n_err;
      sum_nees += nees;
      ++n_nees;
    }
    out.final_nees = nees;
  }
  out.rms_m = std::sqrt(sum_sq / n_err);
  out.mean_nees = sum_nees / n_nees;
  out.bias_error = f.gyro_bias() - kBias;
  out.bias_std = std::sqrt(f.P()(P4Idx::kBgz, P4Idx::kBgz));
  out.heading_error = wrap_pi(f.x()(P4Idx::kPsi) - truth_psi(kDuration));
  out.heading_std = std::sqrt(f.P()(P4Idx::kPsi, P4Idx::kPsi));
  EXPECT_EQ(f.numerical_faults(), 0);
  return out;
}

class P4Circle : public ::testing::TestWithParam<bool> {};

TEST_P(P4Circle, TracksTheCircleAndEstimatesTheGyroBias) {
  const CircleRun r = run_circle(GetParam());
  RecordProperty("rms_m", std::to_string(r.rms_m));
  std::printf("rms %.3f m, mean NEES %.2f, final NEES %.2f, bias error %.2e (σ %.2e) rad/s, "
              "heading error %.2e (σ %.2e) rad\n",
              r.rms_m, r.mean_nees, r.final_nees, r.bias_error, r.bias_std, r.heading_error,
              r.heading_std);
  EXPECT_LT(r.rms_m, 1.0);                    // GPS alone: σ √2 ≈ 1.41 m per fix
  EXPECT_LT(std::abs(r.bias_error), 1.0e-3);  // 10 % of the 0.01 rad/s bias
  EXPECT_LT(std::abs(r.bias_error), 3.0 * r.bias_std);
  EXPECT_LT(std::abs(r.heading_error), 3.0 * r.heading_std);
  EXPECT_LT(r.final_nees, 11.8);  // chi² 2 dof at 99.73 % ("3σ")
  EXPECT_LT(r.mean_nees, 4.0);    // not overconfident (2 if consistent; the filter's noise
  EXPECT_GT(r.mean_nees, 0.3);    // densities are above the simulated ones)
}

INSTANTIATE_TEST_SUITE_P(PositionAndCompass, P4Circle, ::testing::Values(false));
INSTANTIATE_TEST_SUITE_P(WithRmcVelocity, P4Circle, ::testing::Values(true));

TEST(P4DeadReckoning, DriftsButStaysFinite) {
  P4BeaconUkf f(P4UkfParams{});
  ASSERT_EQ(f.initialise(Eigen::Vector2d(0.0, 0.0), 0.5), StepStatus::kApplied);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  double last_var = f.position_covariance_ne().trace();
  for (int k = 0; k < 600 * 50; ++k) {
    const P4Input u{0.05 + 0.1 * normal(rng), 0.1 * normal(rng), 0.02 + 0.01 * normal(rng)};
    ASSERT_EQ(f.predict(u, 0.02), StepStatus::kApplied) << k;
    if (k % 500 == 0) {
      const double var = f.position_covariance_ne().trace();
      EXPECT_GT(var, last_var) << k;  // drifts: the position uncertainty only grows
      last_var = var;
    }
  }
  EXPECT_TRUE(f.x().allFinite());
  EXPECT_TRUE(f.P().allFinite());
  EXPECT_EQ(Eigen::LLT<P4Mat>(f.P()).info(), Eigen::Success);
  EXPECT_GT(std::sqrt(last_var), 100.0);  // 10 min of q_a = 0.1 m/s²/√Hz: ~1 km
  EXPECT_EQ(f.numerical_faults(), 0);
}

TEST(P4Refusals, InvalidInputsLeaveTheStateUntouched) {
  P4BeaconUkf f(P4UkfParams{});
  // Before initialisation everything is refused.
  EXPECT_EQ(f.predict(P4Input{}, 0.02), StepStatus::kRejectedInvalid);
  EXPECT_EQ(f.update_gps_position(Eigen::Vector2d(1.0, 2.0)).status,
            UpdateStatus::kRejectedInvalid);
  EXPECT_EQ(f.update_compass(1.0).status, UpdateStatus::kRejectedInvalid);
  EXPECT_EQ(f.update_gps_velocity(Eigen::Vector2d(1.0, 2.0)).status,
            UpdateStatus::kRejectedInvalid);
  EXPECT_FALSE(f.initialised());
  EXPECT_EQ(f.initialise(Eigen::Vector2d(kNaN, 0.0), 1.0), StepStatus::kRejectedInvalid);
  EXPECT_EQ(f.initialise(Eigen::Vector2d(0.0, 0.0), kInf), StepStatus::kRejectedInvalid);
  EXPECT_FALSE(f.initialised());

  ASSERT_EQ(f.initialise(Eigen::Vector2d(10.0, 20.0), 6.0), StepStatus::kApplied);
  EXPECT_NEAR(f.x()(P4Idx::kPsi), 6.0 - 2.0 * kPi, 1e-15);  // wrapped once, at B11
  ASSERT_EQ(f.predict(P4Input{0.1, 0.0, 0.01}, 0.02), StepStatus::kApplied);
  const P4Vec x = f.x();
  const P4Mat P = f.P();
  const auto untouched = [&] { return f.x() == x && f.P() == P; };
  for (const P4Input& u : {P4Input{kNaN, 0.0, 0.0}, P4Input{0.0, kInf, 0.0},
                           P4Input{0.0, 0.0, kNaN}}) {
    EXPECT_EQ(f.predict(u, 0.02), StepStatus::kRejectedInvalid);
    EXPECT_TRUE(untouched());
  }
  for (const double dt : {0.0, -0.02, 10.5, kNaN, kInf}) {
    EXPECT_EQ(f.predict(P4Input{}, dt), StepStatus::kRejectedInvalid) << dt;
    EXPECT_TRUE(untouched());
  }
  EXPECT_EQ(f.update_gps_position(Eigen::Vector2d(kNaN, 1.0)).status,
            UpdateStatus::kRejectedInvalid);
  EXPECT_EQ(f.update_compass(kInf).status, UpdateStatus::kRejectedInvalid);
  EXPECT_EQ(f.update_compass(kNaN).status, UpdateStatus::kRejectedInvalid);
  EXPECT_EQ(f.update_gps_velocity(Eigen::Vector2d(0.0, -kInf)).status,
            UpdateStatus::kRejectedInvalid);
  EXPECT_TRUE(untouched());
  EXPECT_EQ(f.reset(x, -P), StepStatus::kRejectedInvalid);  // not positive definite
  EXPECT_EQ(f.reset(P4Vec::Constant(kNaN), P), StepStatus::kRejectedInvalid);
  EXPECT_TRUE(untouched());
  // An input so large that the transform overflows: a numerical fault, counted, refused.
  EXPECT_EQ(f.predict(P4Input{1e300, 0.0, 0.0}, 1.0), StepStatus::kRejectedInvalid);
  EXPECT_EQ(f.numerical_faults(), 1);
  EXPECT_EQ(f.last_predict_status(), UnscentedStatus::kNonFinite);
  EXPECT_TRUE(untouched());
  // A gate refuses an outlier and reports its NIS.
  P4UkfParams gated;
  gated.gps_position_gate_nis = 13.8;
  P4BeaconUkf g(gated);
  ASSERT_EQ(g.initialise(Eigen::Vector2d(0.0, 0.0), 0.0), StepStatus::kApplied);
  const UpdateReport<2> r = g.update_gps_position(Eigen::Vector2d(100.0, 0.0));
  EXPECT_EQ(r.status, UpdateStatus::kRejectedGate);
  EXPECT_NEAR(r.nis, 100.0 * 100.0 / 18.0, 1e-9);  // S = σ_p0² + σ_p² = 18 m²
  EXPECT_EQ(g.x()(P4Idx::kN), 0.0);
}

TEST(P4Params, DefaultsPassAndBadFieldsAreNamed) {
  EXPECT_TRUE(validate(P4UkfParams{}).has_value());
  struct Case {
    const char* name;
    double P4UkfParams::*member;
    double bad;
  };
  const Case cases[] = {
      {"kappa", &P4UkfParams::kappa, -6.0},
      {"kappa", &P4UkfParams::kappa, kNaN},
      {"accel_noise_density_mps2_rthz", &P4UkfParams::accel_noise_density_mps2_rthz, 0.0},
      {"gyro_noise_density_radps_rthz", &P4UkfParams::gyro_noise_density_radps_rthz, -1.0},
      {"gyro_bias_walk_radps_rtsec", &P4UkfParams::gyro_bias_walk_radps_rtsec, kInf},
      {"gps_position_std_m", &P4UkfParams::gps_position_std_m, 0.0},
      {"compass_std_rad", &P4UkfParams::compass_std_rad, kNaN},
      {"gps_velocity_std_mps", &P4UkfParams::gps_velocity_std_mps, -0.1},
      {"gps_position_gate_nis", &P4UkfParams::gps_position_gate_nis, -1.0},
      {"compass_gate_nis", &P4UkfParams::compass_gate_nis, kNaN},
      {"gps_velocity_gate_nis", &P4UkfParams::gps_velocity_gate_nis, -0.5},
      {"initial_position_std_m", &P4UkfParams::initial_position_std_m, 0.0},
      {"initial_velocity_std_mps", &P4UkfParams::initial_velocity_std_mps, -2.0},
      {"initial_heading_std_rad", &P4UkfParams::initial_heading_std_rad, kInf},
      {"initial_gyro_bias_std_radps", &P4UkfParams::initial_gyro_bias_std_radps, 0.0},
      {"max_dt_s", &P4UkfParams::max_dt_s, 0.0},
  };
  for (const Case& c : cases) {
    P4UkfParams p;
    p.*(c.member) = c.bad;
    const Result<void> r = validate(p);
    ASSERT_FALSE(r.has_value()) << c.name << " = " << c.bad;
    EXPECT_NE(r.error().detail.find(c.name), std::string::npos) << r.error().detail;
    EXPECT_THROW(P4BeaconUkf{p}, std::logic_error) << c.name;  // contract (test_support.hpp)
  }
  P4UkfParams ok;
  ok.kappa = -5.5;  // n + κ > 0: accepted
  ok.compass_gate_nis = 0.0;
  EXPECT_TRUE(validate(ok).has_value());
}

}  // namespace
}  // namespace nav::estimator
