// SPDX-License-Identifier: MIT
// The MFINS attitude EKF (p1_attitude_ekf.hpp, A1..A8): at rest it levels from δgⁿ and finds
// the heading from δmⁿ from a wrong start, and estimates the gyro bias; on the stadium it holds
// the attitude when given the motion acceleration and not when told "zero" (the paper's
// undefined â_motion); its acceleration output A8; invalid input refused. Fixed seeds.
#include "nav/estimator/p1_attitude_ekf.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>

#include "nav/common/units.hpp"
#include "nav/estimator/complementary_attitude.hpp"
#include "p1_test_support.hpp"
#include "test_support.hpp"

namespace nav::estimator {
namespace {

using testing::attitude_error_n;
using testing::Normal;
using testing::SensorErrors;
using testing::Stadium;
using testing::Truth;
constexpr double kDeg = units::kDegToRad;
constexpr double kDt = 0.01;  ///< IMU period [s]

P1Params params_with_start(const Quat& q0) {
  P1Params p;
  p.initial_q_nb = q0;
  p.initial_tilt_std_rad = 0.1;
  p.initial_heading_std_rad = 0.6;
  return p;
}

SensorErrors sensor_errors(const P1Params& p) {
  SensorErrors e;
  e.gyro_bias_b_radps = Vec3(2e-3, -3e-3, 4e-3);
  e.accel_bias_b_mps2 = Vec3(0.01, -0.01, 0.04);
  e.gyro_noise_radps_rthz = p.gyro_noise_radps_rthz;
  e.accel_noise_mps2_rthz = p.accel_noise_mps2_rthz;
  e.mag_std_tesla = p.mag_std_tesla;
  return e;
}

/// Tilt (ε_N, ε_E) and heading (ε_D) parts of the NED attitude error [rad].
double tilt_of(const Vec3& rho) { return rho.head<2>().norm(); }

TEST(P1AttitudeEkf, LevelsAndFindsHeadingAtRest) {
  const Quat q_true = quat_from_euler({3.0 * kDeg, -2.0 * kDeg, 40.0 * kDeg});
  // Start 5° off in roll and 4° in pitch (about NED) and 25° in heading.
  const Vec3 rho0(5.0 * kDeg, -4.0 * kDeg, 25.0 * kDeg);
  P1Params p = params_with_start((quat_exp(-rho0) * q_true).normalized());
  // At rest a horizontal accel bias reads as a tilt, and through the inclined field (mⁿ =
  // (20, 0, 40) µT) the tilt about North as twice that heading: the rotation about mⁿ plus
  // the bias that hides it is unobservable and stays at its prior, σ ≈ σ_ba0 / g. A prior of
  // 0.01 m/s² bounds it to ≈ 0.06° of tilt and 0.12° of heading (with 0.05 m/s² it would be
  // 0.3° and 0.6°, and the filter would say so).
  p.initial_accel_bias_std_mps2 = 0.01;
  SensorErrors e = sensor_errors(p);
  e.accel_bias_b_mps2 = Vec3(0.006, -0.004, 0.02);
  P1AttitudeEkf ekf(p);
  Normal n(5);
  ImuSample perfect;
  perfect.dt_s = kDt;
  perfect.f_b_mps2 = q_true.conjugate() * (-p.gravity_n());
  Vec3 rho_at_10s = Vec3::Zero();
  for (int k = 1; k <= 6000; ++k) {
    const ImuSample s = testing::noisy_imu(perfect, q_true, p.mag_field_n_tesla, e, n);
    ASSERT_EQ(ekf.step(s, Vec3::Zero()), StepStatus::kApplied);
    if (k == 1000) rho_at_10s = attitude_error_n(q_true, ekf.q_nb());
  }
  const Vec3 rho = attitude_error_n(q_true, ekf.q_nb());
  // Within 10 s the 25° heading and 6° tilt errors are gone to well under a degree.
  EXPECT_LT(tilt_of(rho_at_10s), 0.5 * kDeg);
  EXPECT_LT(std::abs(rho_at_10s.z()), 1.0 * kDeg);
  // After 60 s: what is left is that unobservable combination, and the filter knows it.
  EXPECT_LT(tilt_of(rho), 0.1 * kDeg);
  EXPECT_LT(std::abs(rho.z()), 0.25 * kDeg);
  const Mat3 P_rho = ekf.attitude_covariance_n();
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(std::abs(rho(i)), 3.0 * std::sqrt(P_rho(i, i))) << "axis " << i;
  }
  // The gyro bias is estimated (at rest all three axes: the attitude is pinned).
  EXPECT_LT((ekf.gyro_bias_b() - e.gyro_bias_b_radps).norm(), 2e-4);
  // The accel bias along gravity (body z, level) is observable at rest.
  EXPECT_NEAR(ekf.accel_bias_b().z(), e.accel_bias_b_mps2.z(), 5e-3);
  EXPECT_EQ(ekf.stats().mag_fused, 6000u);
  EXPECT_EQ(ekf.stats().gravity_fused, 6000u);
  EXPECT_EQ(ekf.stats().numerical_faults, 0u);
  const P1AttitudeEkf::MatN& P = ekf.covariance();
  EXPECT_TRUE((P - P.transpose()).isZero(0.0));
  using Mat9 = Mat<9, 9>;
  EXPECT_EQ(Eigen::LLT<Mat9>(P).info(), Eigen::Success);
}

/// Worst tilt and heading errors on the stadium after 20 s, with the motion acceleration
/// given as the truth or as zero.
struct StadiumResult {
  double worst_tilt = 0.0;
  double worst_heading = 0.0;
  double worst_accel = 0.0;  ///< |â_ins − a_n| [m/s²]
};

StadiumResult run_stadium(bool give_motion_acceleration) {
  const Stadium stadium(0.5);
  const Quat q0 = stadium.at(0.0).q_nb();
  const P1Params p = params_with_start((quat_exp(Vec3(0.02, -0.02, 0.1)) * q0).normalized());
  const SensorErrors e = sensor_errors(p);
  P1AttitudeEkf ekf(p);
  Normal n(9);
  StadiumResult r;
  for (int k = 0; k < 6000; ++k) {
    const double t1 = (k + 1) * kDt;
    const Truth x = stadium.at(t1);
    const ImuSample s = testing::noisy_imu(stadium.perfect_imu(k * kDt, t1, p.gravity_mps2),
                                           x.q_nb(), p.mag_field_n_tesla, e, n);
    const Vec3 a_motion = give_motion_acceleration ? x.a_n : Vec3::Zero();
    ekf.step(s, a_motion);
    if (t1 < 20.0) continue;
    const Vec3 rho = attitude_error_n(x.q_nb(), ekf.q_nb());
    r.worst_tilt = std::max(r.worst_tilt, tilt_of(rho));
    r.worst_heading = std::max(r.worst_heading, std::abs(rho.z()));
    r.worst_accel =
        std::max(r.worst_accel, (ekf.acceleration_error().a_ins_n_mps2 - x.a_n).norm());
  }
  return r;
}

TEST(P1AttitudeEkf, HoldsTheAttitudeOnTheStadiumGivenTheMotionAcceleration) {
  const StadiumResult given = run_stadium(true);
  EXPECT_LT(given.worst_tilt, 0.25 * kDeg);
  EXPECT_LT(given.worst_heading, 0.5 * kDeg);
  // The INS acceleration handed on (A8) is the true one up to the accelerometer's white noise
  // at 100 Hz (σ_a/√dt = 0.02 m/s² per axis) and the residual bias.
  EXPECT_LT(given.worst_accel, 0.15);
  // With â_motion = 0 the 0.125 m/s² centripetal acceleration of the turns reads as a tilt of
  // about 0.125/g = 0.73°: the undefined motion acceleration matters (papers.md, P1 trap).
  const StadiumResult zero = run_stadium(false);
  EXPECT_GT(zero.worst_tilt, 0.4 * kDeg);
  EXPECT_GT(zero.worst_tilt, 2.0 * given.worst_tilt);
}

TEST(P1AttitudeEkf, AccelerationOutputStatesWhatTheUpdatesRemoved) {
  const Quat q_true = quat_from_euler({0.0, 0.0, 10.0 * kDeg});
  P1Params p = params_with_start(q_true);
  P1AttitudeEkf ekf(p);
  ImuSample s;
  s.dt_s = kDt;
  s.f_b_mps2 = q_true.conjugate() * (-p.gravity_n()) + Vec3(0.05, 0.0, 0.0);  // 0.05 m/s² off
  // No update (no field, no motion acceleration): nothing removed, a_ins = R̂ f̂ + g.
  ASSERT_EQ(ekf.step(s, std::nullopt), StepStatus::kApplied);
  const P1AccelerationError& a = ekf.acceleration_error();
  EXPECT_EQ(a.delta_a_n_mps2, Vec3::Zero());
  EXPECT_LT((a.a_ins_n_mps2 - q_true * Vec3(0.05, 0.0, 0.0)).norm(), 1e-12);
  EXPECT_EQ(ekf.last_gravity_status(), UpdateStatus::kRejectedInvalid);
  EXPECT_TRUE(ekf.innovations().empty());
  // A gravity update with the true (zero) motion acceleration removes part of that 0.05 m/s²
  // (as tilt and accel bias): δâ points against it, and a_ins moves towards zero.
  ASSERT_EQ(ekf.step(s, Vec3::Zero()), StepStatus::kApplied);
  const Vec3 err_n = q_true * Vec3(0.05, 0.0, 0.0);
  EXPECT_LT(a.delta_a_n_mps2.dot(err_n), 0.0);
  EXPECT_LT(a.a_ins_n_mps2.norm(), err_n.norm());
  EXPECT_STREQ(ekf.innovations().back().source, "gravity");
  // Σ_δa is symmetric, positive definite and at least the white noise of one sample.
  EXPECT_TRUE((a.P_delta_a_n - a.P_delta_a_n.transpose()).isZero(1e-18));
  const double white = p.accel_noise_mps2_rthz * p.accel_noise_mps2_rthz / kDt;
  EXPECT_GE(a.P_delta_a_n.diagonal().minCoeff(), white);
  EXPECT_EQ(Eigen::LLT<Mat3>(a.P_delta_a_n).info(), Eigen::Success);
  // It is J P Jᵀ + (σ_a²/dt) I at the state after the update (A8).
  const Mat<3, P1AttitudeEkf::kN> J = P1AttitudeEkf::gravity_jacobian(
      ekf.q_nb().toRotationMatrix(), s.f_b_mps2 - ekf.accel_bias_b());
  const Mat3 expected = J * ekf.covariance() * J.transpose() + white * Mat3::Identity();
  EXPECT_LT((a.P_delta_a_n - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.norm());
}

TEST(P1AttitudeEkf, RefusesNanAndInf) {
  P1AttitudeEkf ekf(P1Params{});
  ImuSample s;
  s.dt_s = kDt;
  s.f_b_mps2 = Vec3(0.0, 0.0, -9.8);
  s.m_b_tesla = Vec3(2e-5, 0.0, 4e-5);
  ASSERT_EQ(ekf.step(s, Vec3::Zero()), StepStatus::kApplied);
  const Quat q = ekf.q_nb();
  const P1AttitudeEkf::MatN P = ekf.covariance();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  ImuSample bad = s;
  bad.omega_b_radps.z() = nan;
  EXPECT_EQ(ekf.step(bad, Vec3::Zero()), StepStatus::kRejectedInvalid);
  EXPECT_EQ(ekf.step(s, Vec3(0.0, std::numeric_limits<double>::infinity(), 0.0)),
            StepStatus::kRejectedInvalid);
  bad = s;
  bad.dt_s = 0.0;
  EXPECT_EQ(ekf.step(bad, std::nullopt), StepStatus::kRejectedInvalid);
  EXPECT_EQ(ekf.q_nb().coeffs(), q.coeffs());
  EXPECT_EQ(ekf.covariance(), P);
  EXPECT_TRUE(ekf.innovations().empty());
  EXPECT_EQ(ekf.stats().imu_rejected_invalid, 3u);
  EXPECT_EQ(ekf.stats().imu_samples, 4u);
}

}  // namespace
}  // namespace nav::estimator
