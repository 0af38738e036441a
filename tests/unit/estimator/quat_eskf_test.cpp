// SPDX-License-Identifier: MIT
// QuatEskf (quat_eskf.hpp, E1..E14): the model's Jacobians (transition, accelerometer, the
// 3-D magnetometer with its heading projector Π) against finite differences, one step against
// an independent numpy script, gyro-bias convergence at rest, hard-iron convergence during a
// turn, magnetometer gates (with their hard-iron widening) and a hard iron with an unknown
// Earth field, DVL compensation of the accelerometer, pitch through ±90°, invalid input and
// covariance health. Every random sequence has a fixed seed.
#include "nav/estimator/quat_eskf.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "nav/estimator/complementary_attitude.hpp"
#include "test_support.hpp"

namespace nav::estimator {
namespace {

using testing::earth_field_n;
using testing::field_b;
using testing::static_specific_force_b;
using MatN = Mat<QuatEskf::kN, QuatEskf::kN>;
using VecN = Vec<QuatEskf::kN>;

constexpr double kDeg = units::kDegToRad;
constexpr double kG0 = units::kStandardGravity;
/// The P0 pool's Earth field, NED [T] (scenarios/p0-pool-*.yaml).
const Vec3 kPoolField(30e-6, 0.0, 40e-6);
/// The P0 rig's hard iron, body [T].
const Vec3 kPoolHardIron(2e-6, -1.5e-6, 1e-6);

/// Log of SO(3) for a unit quaternion [rad], on the short path.
Vec3 quat_log(const Quat& q_in) {
  const Quat q = q_in.w() < 0.0 ? Quat(-q_in.coeffs()) : q_in;
  const double s = q.vec().norm();
  if (s < 1e-15) {
    return 2.0 * q.vec();
  }
  return 2.0 * std::atan2(s, q.w()) * q.vec() / s;
}

/// Local error δθ with q = q_ref ⊗ Exp(δθ) [rad].
Vec3 local_error(const Quat& q_ref, const Quat& q) { return quat_log(q_ref.conjugate() * q); }

Quat euler_deg(double roll, double pitch, double yaw) {
  return quat_from_euler({roll * kDeg, pitch * kDeg, yaw * kDeg});
}

/// Yaw of q_nb [rad].
double yaw_of(const Quat& q) { return euler_from_quat(q).yaw; }

/// Angle between the estimated and the true "down" direction in the body frame [rad].
double tilt_error(const Quat& q_est, const Quat& q_true) {
  const Vec3 d_est = q_est.conjugate() * Vec3::UnitZ();
  const Vec3 d_true = q_true.conjugate() * Vec3::UnitZ();
  return std::atan2(d_est.cross(d_true).norm(), d_est.dot(d_true));
}

bool is_symmetric_pd(const MatN& P) {
  if (!P.allFinite() || !(P - P.transpose()).isZero(0.0)) {
    return false;
  }
  const Eigen::LLT<MatN> llt(P);
  return llt.info() == Eigen::Success;
}

/// P is exactly symmetric and finite; positive definite when h is estimated, else its
/// (δθ, δb_g) block is and the δh rows and columns are exactly 0 (h held at 0).
bool covariance_healthy(const QuatEskf& f) {
  const MatN& P = f.covariance();
  if (f.estimates_hard_iron()) {
    return is_symmetric_pd(P);
  }
  if (!P.allFinite() || !(P - P.transpose()).isZero(0.0) ||
      !P.bottomRows<3>().isZero(0.0)) {
    return false;
  }
  const Eigen::LLT<Mat<6, 6>> llt(P.topLeftCorner<6, 6>());
  return llt.info() == Eigen::Success;
}

AttitudeInput static_input(const Quat& q_true, double dt = 0.05) {
  AttitudeInput in;
  in.f_b_mps2 = static_specific_force_b(q_true);
  in.m_b_tesla = field_b(q_true, earth_field_n());
  in.dt_s = dt;
  return in;
}

/// Three independent N(0, σ²) samples.
Vec3 noise3(std::mt19937_64& rng, double sigma) {
  std::normal_distribution<double> n(0.0, sigma);
  const double x = n(rng);
  const double y = n(rng);
  const double z = n(rng);
  return Vec3(x, y, z);
}

/// Default parameters with a known Earth field `m_n` (hard iron estimated).
EskfParams known_field_params(const Vec3& m_n) {
  EskfParams p;
  p.mag_field_n_tesla = m_n;
  return p;
}

// ----------------------------------------------------------------------------------------
// 1. Jacobians against finite differences.

// GIVEN a nominal (q, b_g, h_b) and a perturbed one q ⊗ Exp(δθ), b_g + δb, h_b + δh
// WHEN both are propagated with the same gyro reading (E1, E2)
// THEN the error after the step is F δx to first order (E3), F from central differences.
TEST(QuatEskfJacobians, TransitionMatchesFiniteDifferencesOfTheErrorPropagation) {
  const Quat q0 = euler_deg(20.0, -35.0, 150.0);
  const Vec3 b0(0.01, -0.02, 0.005);
  const Vec3 h0(2e-6, -1e-6, 3e-6);
  const std::vector<Vec3> rates = {Vec3::Zero(), Vec3(0.1, -0.05, 0.2), Vec3(1.0, -2.0, 3.0),
                                   Vec3(0.0, 6.0, 0.0)};
  const std::vector<double> dts = {0.001, 0.05, 0.2};
  const double eps = 1e-6;
  for (const Vec3& omega : rates) {
    for (const double dt : dts) {
      const Vec3 omega_m = omega + b0;
      const Quat q1 = q0 * quat_exp((omega_m - b0) * dt);
      auto propagated_error = [&](const VecN& dx0) {
        const Quat q0_p = q0 * quat_exp(dx0.head<3>());
        const Vec3 b_p = b0 + dx0.segment<3>(3);
        const Vec3 h_p = h0 + dx0.tail<3>();
        const Quat q1_p = q0_p * quat_exp((omega_m - b_p) * dt);
        VecN dx1;
        dx1 << local_error(q1, q1_p), b_p - b0, h_p - h0;  // b and h are constant (E2)
        return dx1;
      };
      MatN F_num;
      for (int i = 0; i < QuatEskf::kN; ++i) {
        const VecN e = eps * VecN::Unit(i);
        F_num.col(i) = (propagated_error(e) - propagated_error(-e)) / (2.0 * eps);
      }
      const MatN F = QuatEskf::transition(omega, dt);
      EXPECT_LE((F - F_num).cwiseAbs().maxCoeff(), 1e-8)
          << "omega " << omega.transpose() << " dt " << dt << "\nF\n"
          << F << "\nnumeric\n"
          << F_num;
    }
  }
}

std::vector<Quat> jacobian_attitudes() {
  return {euler_deg(0.0, 0.0, 0.0),      euler_deg(10.0, -20.0, 30.0),
          euler_deg(-170.0, 45.0, 179.9), euler_deg(30.0, 80.0, -179.9),
          euler_deg(5.0, -80.0, 179.99),  euler_deg(-60.0, 10.0, -179.99),
          euler_deg(120.0, -70.0, 90.0),  euler_deg(0.0, 80.0, 180.0),
          euler_deg(0.0, 90.0, 30.0),     euler_deg(40.0, -90.0, -60.0)};
}

// GIVEN attitudes including pitch ±80° and ±90° and yaw near ±180°
// WHEN q is perturbed locally, q ⊗ Exp(±ε e_i)
// THEN the central differences of h_a (E7) match the analytic [R_nbᵀ g_n]×.
TEST(QuatEskfJacobians, AccelJacobianMatchesCentralDifferences) {
  const double eps = 1e-6;
  for (const Quat& q : jacobian_attitudes()) {
    Mat3 J_a_num;
    for (int i = 0; i < 3; ++i) {
      const Quat q_plus = q * quat_exp(eps * Vec3::Unit(i));
      const Quat q_minus = q * quat_exp(-eps * Vec3::Unit(i));
      J_a_num.col(i) =
          (QuatEskf::accel_model(q_plus) - QuatEskf::accel_model(q_minus)) / (2.0 * eps);
    }
    const Euler e = euler_from_quat(q);
    EXPECT_LE((QuatEskf::accel_jacobian(q) - J_a_num).cwiseAbs().maxCoeff(), 1e-7)
        << "roll " << e.roll << " pitch " << e.pitch << " yaw " << e.yaw;
  }
}

/// Π of E11 from the Euler form of R_nb's third row, u = (−sin θ, sin φ cos θ, cos φ cos θ):
/// independent of the filter's quaternion form. Not used at pitch ±90° (roll undefined).
Mat3 heading_projector_from_euler(const Quat& q) {
  const Euler e = euler_from_quat(q);
  const Vec3 u(-std::sin(e.pitch), std::sin(e.roll) * std::cos(e.pitch),
               std::cos(e.roll) * std::cos(e.pitch));
  return u * u.transpose();
}

// GIVEN attitudes including pitch ±80° and ±90°, Earth fields with and without an East
//       component, a hard iron
// WHEN q is perturbed locally by Exp(±ε e_i), by Exp(±ε Π e_i) (the projected error of E11),
//      and h by ±ε e_i
// THEN the central differences of h_m (E9) give J_m = [R_nbᵀ m_n]× (E10), the projected
//      ones give H_m's attitude block J_m Π (E12), the hard-iron ones I, and the gyro-bias
//      block is 0.
TEST(QuatEskfJacobians, MagJacobianWithHeadingProjectorMatchesCentralDifferences) {
  const double eps = 1e-6;
  const Vec3 h_b(2e-6, -1.5e-6, 1e-6);
  const std::vector<Vec3> fields = {kPoolField, Vec3(18e-6, -4e-6, -45e-6),
                                    Vec3(25e-6, 6e-6, 0.0)};
  for (const Vec3& m_n : fields) {
    for (const Quat& q : jacobian_attitudes()) {
      const Mat3 Pi = QuatEskf::heading_projector(q);
      Mat3 J_num;
      Mat3 H_theta_num;
      Mat3 H_h_num;
      for (int i = 0; i < 3; ++i) {
        const Vec3 d = eps * Vec3::Unit(i);
        J_num.col(i) = (QuatEskf::mag_model(q * quat_exp(d), m_n, h_b) -
                        QuatEskf::mag_model(q * quat_exp(-d), m_n, h_b)) /
                       (2.0 * eps);
        H_theta_num.col(i) = (QuatEskf::mag_model(q * quat_exp(Pi * d), m_n, h_b) -
                              QuatEskf::mag_model(q * quat_exp(-(Pi * d)), m_n, h_b)) /
                             (2.0 * eps);
        H_h_num.col(i) = (QuatEskf::mag_model(q, m_n, h_b + 1e-6 * Vec3::Unit(i)) -
                          QuatEskf::mag_model(q, m_n, h_b - 1e-6 * Vec3::Unit(i))) /
                         2e-6;
      }
      const Mat<3, QuatEskf::kN> H = QuatEskf::mag_jacobian(q, m_n);
      const Euler e = euler_from_quat(q);
      // Fields are ~5e-5 T: 1e-13 T absolute is a relative 2e-9.
      EXPECT_LE((skew(q.conjugate() * m_n) - J_num).cwiseAbs().maxCoeff(), 1e-13)
          << "roll " << e.roll << " pitch " << e.pitch << " yaw " << e.yaw;
      EXPECT_LE((H.leftCols<3>() - H_theta_num).cwiseAbs().maxCoeff(), 1e-13)
          << "roll " << e.roll << " pitch " << e.pitch << " yaw " << e.yaw << "\n"
          << H.leftCols<3>() << "\n" << H_theta_num;
      EXPECT_LE((H.leftCols<3>() - J_num * Pi).cwiseAbs().maxCoeff(), 1e-13);
      EXPECT_TRUE(H.middleCols<3>(3).isZero(0.0));
      EXPECT_LE((H.rightCols<3>() - H_h_num).cwiseAbs().maxCoeff(), 1e-9);
      EXPECT_TRUE(H.rightCols<3>().isIdentity(0.0));
      if (std::abs(std::cos(e.pitch)) > 1e-3) {
        EXPECT_LE((Pi - heading_projector_from_euler(q)).cwiseAbs().maxCoeff(), 1e-12);
      }
    }
  }
}

// GIVEN attitudes including pitch ±90°
// WHEN the local error is a rotation α about u = R_nbᵀ e_z (the range of Π, E11)
// THEN Π is a rank-1 orthogonal projector, q ⊗ Exp(α u) = Exp(α e_z) ⊗ q (a pure change of
//      heading: the body's down direction is unchanged), and Π removes any rotation about a
//      horizontal axis.
TEST(QuatEskfJacobians, HeadingProjectorKeepsOnlyRotationsAboutTheVertical) {
  const double alpha = 0.3;
  for (const Quat& q : jacobian_attitudes()) {
    const Mat3 Pi = QuatEskf::heading_projector(q);
    const Vec3 u = q.conjugate() * Vec3::UnitZ();
    EXPECT_LE((Pi * Pi - Pi).cwiseAbs().maxCoeff(), 1e-15);
    EXPECT_LE((Pi - Pi.transpose()).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_NEAR(Pi.trace(), 1.0, 1e-15);
    EXPECT_LE((Pi * u - u).cwiseAbs().maxCoeff(), 1e-15);
    const Quat turned = q * quat_exp(alpha * u);
    const Quat expected = Quat(Eigen::AngleAxisd(alpha, Vec3::UnitZ())) * q;
    EXPECT_LT(attitude_error_angle(turned, expected), 1e-12);
    EXPECT_LT(tilt_error(turned, q), 1e-12);
    // A rotation about a horizontal NED axis, seen locally, is in Π's null space.
    const Vec3 tilt_b = q.conjugate() * Vec3(std::cos(0.4), std::sin(0.4), 0.0);
    EXPECT_LE((Pi * tilt_b).cwiseAbs().maxCoeff(), 1e-15);
  }
}

// ----------------------------------------------------------------------------------------
// 2. One step against numbers computed independently.

// GIVEN the ESKF with a known Earth field, initialised (roll 10°, pitch −5°, yaw 40°) from
//       readings with a hard iron h = (2, −1.5, 1) µT, so the initial yaw is off by it
// WHEN one step with ω_m = (0.02, −0.01, 0.05) rad/s, dt = 0.05 s, and readings of the attitude
//      q_init ⊗ Exp((0.01, −0.02, 0.03)) (both gates off, so accel and mag are fused)
// THEN q, b_g, h_b, P and the gate quantities are those of an independent numpy
//      implementation of E1..E14.
TEST(QuatEskfStep, SingleStepMatchesHandComputation) {
  EskfParams params;  // the values the script uses, spelled out so retuning keeps this test
  params.gyro_noise_radps_rthz = 5.0e-4;
  params.gyro_bias_walk_radps2_rthz = 2.0e-6;
  params.initial_tilt_std_rad = 0.05;
  params.initial_yaw_std_rad = 0.1;
  params.initial_gyro_bias_std_radps = 0.005;
  params.gyro_bias_limit_radps = 0.05;
  params.accel_std_mps2 = 0.2;
  params.accel_gate_mps2 = 2.0;
  params.mag_field_n_tesla = earth_field_n();
  params.initial_hard_iron_std_tesla = 3.0e-6;
  params.hard_iron_walk_tesla_rts = 1.0e-9;
  params.mag_std_tesla = 1.0e-6;
  params.mag_norm_gate = 0.0;
  params.mag_inclination_gate_rad = 0.0;
  params.mag_gate_nis = 0.0;
  params.declination_rad = 0.3;  // ignored: the known field's declination (0) is used
  const Vec3 h_true(2e-6, -1.5e-6, 1e-6);
  QuatEskf f(params);
  const Quat q_init = euler_deg(10.0, -5.0, 40.0);
  ASSERT_TRUE(f.initialise(static_specific_force_b(q_init),
                           field_b(q_init, earth_field_n()) + h_true));
  ASSERT_TRUE(f.estimates_hard_iron());

  AttitudeInput in = static_input(q_init * quat_exp(Vec3(0.01, -0.02, 0.03)));
  in.m_b_tesla += h_true;
  in.omega_b_radps = Vec3(0.02, -0.01, 0.05);
  in.dt_s = 0.05;
  ASSERT_EQ(f.step(in), AttitudeStatus::kOk);
  EXPECT_EQ(f.last_step().accel, UpdateStatus::kFused);
  EXPECT_EQ(f.last_step().mag, UpdateStatus::kFused);

  // Expected values: printed by tests/unit/estimator/reference/eskf_single_step.py, which
  // re-implements E1..E14 from the header's equations with its own quaternion and rotation
  // code, Euler-angle levelling, an Euler form of Π and np.linalg.inv for S. Run it with
  //   python3 tests/unit/estimator/reference/eskf_single_step.py
  // (python3 + numpy, e.g. Debian's /usr/bin/python3 with python3-numpy; here Python 3.11,
  // numpy 1.24) and paste its output here after any change to E1..E14 or to these params.
  EXPECT_NEAR(f.last_step().mag_norm_ratio, 1.0447082259138127, 1e-12);
  EXPECT_NEAR(f.last_step().mag_inclination_rad, 1.0657335708574749, 1e-12);
  const Quat q_expected(0.93133292963229819, 0.1033811635968058, -0.019621893154241055,
                        0.34863489570743617);
  const Vec3 b_expected(-2.8773728100217755e-06, 1.008436281855735e-05,
                        -2.219316780490917e-06);
  const Vec3 h_expected(1.709356119141261e-06, -1.559762587379022e-06,
                        9.1230848823370784e-07);
  VecN P_diag_expected;
  P_diag_expected << 0.00042209137092514355, 0.00056759845872885221, 0.0068672758743931542,
      2.4999468123408847e-05, 2.4999479122021983e-05, 2.4999937040112606e-05,
      1.8515024778583995e-12, 2.1641456905479551e-12, 9.9865666951966935e-13;
  const Quat q = f.q_nb().w() < 0.0 ? Quat(-f.q_nb().coeffs()) : f.q_nb();
  EXPECT_LE((q.coeffs() - q_expected.coeffs()).cwiseAbs().maxCoeff(), 1e-12)
      << q.coeffs().transpose();
  EXPECT_LE((f.gyro_bias_b() - b_expected).cwiseAbs().maxCoeff(), 1e-14)
      << f.gyro_bias_b().transpose();
  EXPECT_LE((f.hard_iron_b() - h_expected).cwiseAbs().maxCoeff(), 1e-17)
      << f.hard_iron_b().transpose();
  const MatN& P = f.covariance();
  for (int i = 0; i < QuatEskf::kN; ++i) {
    EXPECT_NEAR(P(i, i), P_diag_expected(i), 1e-9 * P_diag_expected(i)) << i;
  }
  EXPECT_NEAR(P(0, 1), 0.000117522416759287, 1e-13);
  EXPECT_NEAR(P(2, 5), -8.6493241730578496e-07, 1e-15);
  EXPECT_NEAR(P(2, 7), 9.3067105441566487e-08, 1e-16);
  EXPECT_NEAR(P(6, 8), -3.063854842843292e-13, 1e-21);
}

// GIVEN a filter with a known field initialised from exact readings (no tilt–heading
//       covariance yet)
// WHEN a sample comes whose field is turned 0.3 rad in heading (exact accelerometer, zero rate)
// THEN the 3-D update (E12) moves the heading and leaves the tilt exactly where it was.
TEST(QuatEskfStep, MagnetometerUpdateTurnsTheHeadingButNeverTilts) {
  const Quat q_true = euler_deg(12.0, -25.0, 70.0);
  EskfParams p = known_field_params(earth_field_n());
  p.mag_norm_gate = 0.0;
  p.mag_inclination_gate_rad = 0.0;
  QuatEskf f(p);
  ASSERT_TRUE(f.initialise(static_specific_force_b(q_true), field_b(q_true, earth_field_n())));
  const Quat q_before = f.q_nb();
  AttitudeInput in = static_input(q_true);
  in.m_b_tesla = field_b(q_true, Eigen::AngleAxisd(0.3, Vec3::UnitZ()) * earth_field_n());
  ASSERT_EQ(f.step(in), AttitudeStatus::kOk);
  ASSERT_EQ(f.last_step().mag, UpdateStatus::kFused);
  EXPECT_GT(std::abs(wrap_pi(yaw_of(f.q_nb()) - yaw_of(q_before))), 0.01);
  EXPECT_LT(tilt_error(f.q_nb(), q_before), 1e-12);
}

// ----------------------------------------------------------------------------------------
// 3. Gyro bias at rest.

// GIVEN a GX3-25-like AHRS at rest (gyro noise 0.03 °/s/√Hz, bias (0.2, −0.15, 0.25) °/s,
//       accel 0.6 mg, mag 0.05 µT per sample), seeds 1..10
// WHEN the ESKF runs 60 s at 20 Hz (default parameters: Earth field unknown)
// THEN yaw never strays 0.5° from truth, and the bias estimate is within 0.01 °/s.
// The 0.01 °/s is a statistical bound: with angle random walk N the best possible bias
// estimate over T has σ = N/√T = 0.03/√60 = 0.0039 °/s per axis, so 0.01 °/s is 2.6σ (1 %
// of axes outside). The test therefore asserts the RMS over 10 seeds × 3 axes (≤ 0.0055 °/s,
// 1.4× the limit) and at most 2 of the 30 axis errors above 0.01 °/s (0.3 expected).
TEST(QuatEskfBias, ConvergesAtRestToTheAngleRandomWalkLimit) {
  const double dt = 0.05;
  const Vec3 bias = Vec3(0.2, -0.15, 0.25) * kDeg;
  const double gyro_sigma = 0.03 * kDeg / std::sqrt(dt);  // per sample
  const double accel_sigma = 0.6e-3 * kG0;                // 0.6 mg per sample
  const double mag_sigma = 0.05e-6;                       // 0.05 µT per sample
  const Quat q_true = euler_deg(2.0, -3.0, 60.0);
  double sum_sq = 0.0;
  int above = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    std::mt19937_64 rng(seed);
    auto reading = [&]() {
      AttitudeInput in = static_input(q_true, dt);
      in.omega_b_radps = bias + noise3(rng, gyro_sigma);
      in.f_b_mps2 += noise3(rng, accel_sigma);
      in.m_b_tesla += noise3(rng, mag_sigma);
      return in;
    };
    QuatEskf f{EskfParams{}};
    const AttitudeInput first = reading();
    ASSERT_TRUE(f.initialise(first.f_b_mps2, first.m_b_tesla));
    double max_yaw_error = 0.0;
    for (int k = 0; k < 1200; ++k) {
      ASSERT_EQ(f.step(reading()), AttitudeStatus::kOk) << k;
      max_yaw_error =
          std::max(max_yaw_error, std::abs(wrap_pi(yaw_of(f.q_nb()) - yaw_of(q_true))));
    }
    EXPECT_LE(max_yaw_error, 0.5 * kDeg) << "seed " << seed << ": " << max_yaw_error / kDeg;
    const Vec3 bias_error = f.gyro_bias_b() - bias;
    sum_sq += bias_error.squaredNorm();
    above += static_cast<int>((bias_error.array().abs() > 0.01 * kDeg).count());
  }
  const double rms = std::sqrt(sum_sq / 30.0);
  EXPECT_LE(rms, 0.0055 * kDeg) << rms / kDeg << " deg/s";
  EXPECT_LE(above, 2);
}

// ----------------------------------------------------------------------------------------
// 4. Hard iron.

/// Outcome of turn_with_hard_iron().
struct TurnResult {
  Vec3 h_b;                     ///< ĥ at the end [T]
  double max_heading_end = 0.0;  ///< largest |heading error| over the last 60 s [rad]
  bool h_always_zero = true;     ///< ĥ was exactly 0 after every step
  bool healthy = true;           ///< covariance_healthy() after every step
};

/// The pool rig (GX3-25 errors of scenarios/p0-pool-*.yaml: gyro bias 0.25 °/s per axis,
/// white 0.1 °/s per sample; accel bias 2 mg, white 0.6 mg; mag white 0.2 µT) with the hard
/// iron `h_b` and the pool's field: 30 s at rest facing North, then a 360° turn to starboard
/// at 2 °/s (180 s), the ESKF told the field.
TurnResult turn_with_hard_iron(const EskfParams& params, const Vec3& h_b, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const double dt = 0.05;
  const Vec3 gyro_bias = Vec3::Constant(0.25 * kDeg);
  const Vec3 accel_bias = Vec3::Constant(2e-3 * kG0);
  Quat q_true = euler_deg(0.0, 0.0, 0.0);
  auto reading = [&](const Vec3& omega) {
    AttitudeInput in;
    in.dt_s = dt;
    in.omega_b_radps = omega + gyro_bias + noise3(rng, 0.1 * kDeg);
    in.f_b_mps2 = static_specific_force_b(q_true) + accel_bias + noise3(rng, 0.6e-3 * kG0);
    in.m_b_tesla = field_b(q_true, kPoolField) + h_b + noise3(rng, 0.2e-6);
    return in;
  };
  QuatEskf f(params);
  const AttitudeInput first = reading(Vec3::Zero());
  NAV_ENSURE(f.initialise(first.f_b_mps2, first.m_b_tesla), "initialisation must succeed");
  const int n_rest = 600;
  const int n_turn = 3600;
  const Vec3 turn_rate(0.0, 0.0, 2.0 * kDeg);
  TurnResult r;
  for (int k = 0; k < n_rest + n_turn; ++k) {
    const Vec3 omega = k >= n_rest ? turn_rate : Vec3::Zero();
    q_true = (q_true * quat_exp(omega * dt)).normalized();
    if (f.step(reading(omega)) != AttitudeStatus::kOk) {
      r.healthy = false;
    }
    r.h_always_zero = r.h_always_zero && (f.hard_iron_b().array() == 0.0).all();
    r.healthy = r.healthy && covariance_healthy(f);
    if (k >= n_rest + n_turn - 1200) {
      r.max_heading_end = std::max(r.max_heading_end,
                                   std::abs(wrap_pi(yaw_of(f.q_nb()) - yaw_of(q_true))));
    }
  }
  r.h_b = f.hard_iron_b();
  return r;
}

// GIVEN the pool rig with its hard iron h = (2, −1.5, 1) µT, the ESKF told the pool's field
//       (default parameters otherwise), seeds 1..3
// WHEN it rests 30 s and turns 360° at 2 °/s
// THEN ĥ is within 0.3 µT of h per axis at the end and the heading error stays below 1° over
//      the last 60 s. (The accelerometer bias tilts the estimate by ~0.1°, which moves ĥ by
//      ~0.1 µT: the bound leaves room for it.)
TEST(QuatEskfHardIron, ConvergesDuringAFullTurnWithAKnownField) {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const TurnResult r = turn_with_hard_iron(known_field_params(kPoolField), kPoolHardIron, seed);
    EXPECT_TRUE(r.healthy) << seed;
    EXPECT_LE((r.h_b - kPoolHardIron).cwiseAbs().maxCoeff(), 0.3e-6)
        << "seed " << seed << ": " << r.h_b.transpose() * 1e6 << " uT";
    EXPECT_LT(r.max_heading_end, 1.0 * kDeg) << "seed " << seed << ": " << r.max_heading_end / kDeg;
  }
}

// GIVEN the same rig and turn, the ESKF told the field but with σ_h0 = 0
// WHEN it runs
// THEN h_b stays exactly 0 (its covariance too), and the heading keeps a hard-iron error of
//      several degrees over the last 60 s (8.7° with seed 1): the unmodelled h biases the
//      heading by up to asin(2.5 / 30) ≈ 4.8°, and moves |m_b| off |m_n| by −1.4 % .. +4.6 %
//      with the heading, so the 1 % magnitude gate refuses most samples.
TEST(QuatEskfHardIron, WithZeroInitialStdTheHardIronStaysZero) {
  EskfParams p = known_field_params(kPoolField);
  p.initial_hard_iron_std_tesla = 0.0;
  {
    QuatEskf f(p);
    ASSERT_TRUE(f.initialise(static_specific_force_b(Quat::Identity()), kPoolField));
    EXPECT_FALSE(f.estimates_hard_iron());
  }
  const TurnResult r = turn_with_hard_iron(p, kPoolHardIron, 1);
  EXPECT_TRUE(r.healthy);
  EXPECT_TRUE(r.h_always_zero);
  EXPECT_GT(r.max_heading_end, 3.0 * kDeg) << r.max_heading_end / kDeg;
}

// GIVEN the default parameters (Earth field unknown) and readings with a hard iron
// WHEN the filter initialises and runs through part of a turn
// THEN m_n is the first field rotated by the initial attitude, the gate references are its
//      magnitude and inclination, and h_b stays exactly 0 with zero covariance (E12 is then a
//      heading update whose reference is the first sample).
TEST(QuatEskfHardIron, UnknownFieldIsTakenAtInitialiseAndTheHardIronHeldAtZero) {
  const Quat q_true = euler_deg(4.0, -6.0, 35.0);
  const Vec3 m_b0 = field_b(q_true, earth_field_n()) + kPoolHardIron;
  QuatEskf f{EskfParams{}};
  ASSERT_TRUE(f.initialise(static_specific_force_b(q_true), m_b0));
  EXPECT_FALSE(f.estimates_hard_iron());
  const Vec3 m_n = f.q_nb() * m_b0;
  EXPECT_LE((f.mag_field_n() - m_n).cwiseAbs().maxCoeff(), 1e-18);
  EXPECT_NEAR(f.mag_field_n().y(), 0.0, 1e-18);  // yaw from the field: no East component
  EXPECT_NEAR(f.mag_reference_norm(), m_b0.norm(), 1e-18);
  EXPECT_NEAR(f.mag_reference_inclination(), std::asin(m_n.z() / m_n.norm()), 1e-12);
  const TurnResult r = turn_with_hard_iron(EskfParams{}, kPoolHardIron, 2);
  EXPECT_TRUE(r.healthy);
  EXPECT_TRUE(r.h_always_zero);
}

// ----------------------------------------------------------------------------------------
// 5. Magnetometer gates.

EskfParams gate_params() {
  EskfParams p;
  p.mag_norm_gate = 0.03;
  p.mag_inclination_gate_rad = 0.05;
  return p;
}

/// A filter initialised at `q_true` from exact readings.
QuatEskf initialised_at(const Quat& q_true, const EskfParams& params) {
  QuatEskf f(params);
  NAV_ENSURE(f.initialise(static_specific_force_b(q_true), field_b(q_true, earth_field_n())),
             "test initialisation must succeed");
  return f;
}

// GIVEN a filter initialised from exact readings (m_ref = |m_n|)
// WHEN a sample comes whose field is 10 % stronger and turned 0.3 rad in heading
// THEN the magnitude gate refuses it, counts it, and the heading is left alone.
TEST(QuatEskfMagGates, FieldTenPercentOffIsGatedAndHeadingUnchanged) {
  const Quat q_true = euler_deg(3.0, -4.0, 25.0);
  QuatEskf f = initialised_at(q_true, gate_params());
  const double yaw_before = yaw_of(f.q_nb());
  AttitudeInput in = static_input(q_true);
  in.m_b_tesla = 1.1 * field_b(q_true, Eigen::AngleAxisd(0.3, Vec3::UnitZ()) * earth_field_n());
  ASSERT_EQ(f.step(in), AttitudeStatus::kOk);
  EXPECT_EQ(f.last_step().mag, UpdateStatus::kRejectedGate);
  EXPECT_NEAR(f.last_step().mag_norm_ratio, 1.1, 1e-9);
  EXPECT_EQ(f.stats().mag_rejected, 1u);
  // Exact accelerometer, zero rate: nothing else may move the heading.
  EXPECT_NEAR(yaw_of(f.q_nb()), yaw_before, 1e-9);
}

// GIVEN a filter initialised from exact readings
// WHEN the field keeps its magnitude but its inclination is 0.1 rad off the reference
// THEN the inclination gate refuses it.
TEST(QuatEskfMagGates, InclinationOffByATenthOfARadianIsGated) {
  const Quat q_true = euler_deg(-5.0, 2.0, -100.0);
  QuatEskf f = initialised_at(q_true, gate_params());
  const double yaw_before = yaw_of(f.q_nb());
  // Tilting the NED field about East by 0.1 rad changes its inclination by 0.1 rad.
  const Vec3 m_n = Eigen::AngleAxisd(0.1, Vec3::UnitY()) * earth_field_n();
  AttitudeInput in = static_input(q_true);
  in.m_b_tesla = field_b(q_true, m_n);
  ASSERT_EQ(f.step(in), AttitudeStatus::kOk);
  EXPECT_EQ(f.last_step().mag, UpdateStatus::kRejectedGate);
  EXPECT_NEAR(f.last_step().mag_norm_ratio, 1.0, 1e-9);
  EXPECT_NEAR(std::abs(f.last_step().mag_inclination_rad - f.mag_reference_inclination()), 0.1,
              1e-6);
  EXPECT_EQ(f.stats().mag_rejected, 1u);
  EXPECT_NEAR(yaw_of(f.q_nb()), yaw_before, 1e-9);
}

// GIVEN both gates off
// WHEN the two disturbed samples above come
// THEN both are fused and move the heading.
TEST(QuatEskfMagGates, WithGatesOffDisturbedSamplesAreFused) {
  EskfParams p;
  p.mag_norm_gate = 0.0;
  p.mag_inclination_gate_rad = 0.0;
  const Quat q_true = euler_deg(3.0, -4.0, 25.0);
  QuatEskf f = initialised_at(q_true, p);
  double yaw = yaw_of(f.q_nb());
  AttitudeInput in = static_input(q_true);
  in.m_b_tesla = 1.1 * field_b(q_true, Eigen::AngleAxisd(0.3, Vec3::UnitZ()) * earth_field_n());
  ASSERT_EQ(f.step(in), AttitudeStatus::kOk);
  EXPECT_EQ(f.last_step().mag, UpdateStatus::kFused);
  EXPECT_GT(std::abs(wrap_pi(yaw_of(f.q_nb()) - yaw)), 0.01);
  yaw = yaw_of(f.q_nb());
  in.m_b_tesla =
      field_b(q_true, Eigen::AngleAxisd(0.2, Vec3::UnitZ()) *
                          (Eigen::AngleAxisd(0.1, Vec3::UnitY()) * earth_field_n()));
  ASSERT_EQ(f.step(in), AttitudeStatus::kOk);
  EXPECT_EQ(f.last_step().mag, UpdateStatus::kFused);
  EXPECT_GT(std::abs(wrap_pi(yaw_of(f.q_nb()) - yaw)), 0.001);
  EXPECT_EQ(f.stats().mag_rejected, 0u);
}

// GIVEN a known field (hard iron not estimated, σ_h0 = 0): the references are |m_n| and
//       I(m_n), not the first sample's
// WHEN the filter initialises from a field 2 % weaker than m_n and gets a sample of m_n itself,
//      then one 5 % stronger than m_n
// THEN the first is fused (it matches m_n) and the second refused.
TEST(QuatEskfMagGates, KnownFieldIsTheGateReference) {
  EskfParams p = gate_params();
  p.mag_field_n_tesla = earth_field_n();
  p.initial_hard_iron_std_tesla = 0.0;
  const Quat q_true = euler_deg(2.0, 6.0, -40.0);
  QuatEskf f(p);
  ASSERT_TRUE(f.initialise(static_specific_force_b(q_true),
                           0.98 * field_b(q_true, earth_field_n())));
  EXPECT_NEAR(f.mag_reference_norm(), earth_field_n().norm(), 1e-18);
  EXPECT_NEAR(f.mag_reference_inclination(), std::atan2(4.0, 2.0), 1e-12);
  AttitudeInput in = static_input(q_true);
  ASSERT_EQ(f.step(in), AttitudeStatus::kOk);
  EXPECT_EQ(f.last_step().mag, UpdateStatus::kFused);
  in.m_b_tesla = 1.05 * field_b(q_true, earth_field_n());
  ASSERT_EQ(f.step(in), AttitudeStatus::kOk);
  EXPECT_EQ(f.last_step().mag, UpdateStatus::kRejectedGate);
  EXPECT_NEAR(f.last_step().mag_norm_ratio, 1.05, 1e-3);
}

// GIVEN a known field and a sample whose field is 2 µT (4.5 % of |m_n|) stronger along the
//       field, as a hard iron along it would make it, with a 3 % magnitude gate
// WHEN the filter has just initialised with σ_h0 = 3 µT, or with σ_h0 = 0
// THEN with σ_h0 = 3 µT the gate is widened by 3 σ_n / |m_n| = 20 % (E8a) and the sample is
//      fused; with σ_h0 = 0 it is refused.
TEST(QuatEskfMagGates, GatesWidenWithTheHardIronUncertainty) {
  const Quat q_true = euler_deg(-3.0, 4.0, 120.0);
  const Vec3 m_b = field_b(q_true, earth_field_n());
  for (const double sigma_h0 : {3e-6, 0.0}) {
    EskfParams p = gate_params();
    p.mag_field_n_tesla = earth_field_n();
    p.initial_hard_iron_std_tesla = sigma_h0;
    QuatEskf f(p);
    ASSERT_TRUE(f.initialise(static_specific_force_b(q_true), m_b));
    AttitudeInput in = static_input(q_true);
    in.m_b_tesla = m_b + 2e-6 * m_b.normalized();
    ASSERT_EQ(f.step(in), AttitudeStatus::kOk);
    EXPECT_NEAR(f.last_step().mag_norm_ratio, 1.0 + 2e-6 / earth_field_n().norm(), 1e-9);
    EXPECT_EQ(f.last_step().mag,
              sigma_h0 > 0.0 ? UpdateStatus::kFused : UpdateStatus::kRejectedGate)
        << sigma_h0;
  }
}

// GIVEN the NIS gate set to the 99.9 % point of χ²(3) = 16.27, the other gates off, a known
//       field, a filter that has rested 30 s (ĥ and the heading settled)
// WHEN a sample comes with 10 µT added across the field
// THEN the NIS gate refuses it and counts it; the next clean sample is fused.
TEST(QuatEskfMagGates, NisGateRefusesAFieldFarFromThePrediction) {
  EskfParams p = known_field_params(earth_field_n());
  p.mag_norm_gate = 0.0;
  p.mag_inclination_gate_rad = 0.0;
  p.mag_gate_nis = 16.27;
  const Quat q_true = euler_deg(1.0, 2.0, 10.0);
  QuatEskf f = initialised_at(q_true, p);
  std::mt19937_64 rng(3);
  AttitudeInput in = static_input(q_true);
  for (int k = 0; k < 600; ++k) {
    in.m_b_tesla = field_b(q_true, earth_field_n()) + noise3(rng, 0.2e-6);
    ASSERT_EQ(f.step(in), AttitudeStatus::kOk);
  }
  EXPECT_EQ(f.stats().mag_rejected, 0u);
  in.m_b_tesla = field_b(q_true, earth_field_n() + Vec3(0.0, 10e-6, 0.0));
  ASSERT_EQ(f.step(in), AttitudeStatus::kOk);
  EXPECT_EQ(f.last_step().mag, UpdateStatus::kRejectedGate);
  EXPECT_GT(f.last_step().mag_nis, 16.27);
  EXPECT_EQ(f.stats().mag_rejected, 1u);
  in.m_b_tesla = field_b(q_true, earth_field_n());
  ASSERT_EQ(f.step(in), AttitudeStatus::kOk);
  EXPECT_EQ(f.last_step().mag, UpdateStatus::kFused);
}

// GIVEN a 5 µT hard iron along body x (the vehicle starts facing North, so at the start it
//       lies along the horizontal field), a GX3-25-like gyro with bias, 30 s at rest
// WHEN the vehicle turns 360° at 6 °/s and rests 10 s (default parameters, seed 11)
// THEN the ESKF's heading error stays well below the raw magnetic heading error (P0 eqs 1-4
//      on the same readings), which sweeps ±14.5°.
// This is the Earth-field-unknown mode (default parameters), where h is not estimated and
// the gates are all that protects the heading. The magnitude and inclination of m_b + h
// depend on the heading only through cos(heading − heading at the start) (level vehicle), so
// the gates cannot refuse samples near the starting heading nor at its mirror image; along
// body x the mirror is the start itself. With the hard iron across the field the mirror
// heading passes the gates with the opposite heading error and pulls the estimate: give the
// filter the Earth field and it estimates h instead (QuatEskfHardIron tests).
TEST(QuatEskfMagGates, HardIronDuringATurnHeadingErrorStaysBelowRawMagnetometer) {
  std::mt19937_64 rng(11);
  const double dt = 0.05;
  const Vec3 hard_iron_b(5e-6, 0.0, 0.0);
  const Vec3 bias = Vec3(0.1, -0.2, 0.25) * kDeg;
  const double gyro_sigma = 0.03 * kDeg / std::sqrt(dt);
  Quat q_true = euler_deg(0.0, 0.0, 0.0);
  auto reading = [&](const Vec3& omega) {
    AttitudeInput in = static_input(q_true, dt);
    in.omega_b_radps = omega + bias + noise3(rng, gyro_sigma);
    in.f_b_mps2 += noise3(rng, 0.6e-3 * kG0);
    in.m_b_tesla += hard_iron_b + noise3(rng, 0.05e-6);
    return in;
  };
  QuatEskf f{EskfParams{}};
  const AttitudeInput first = reading(Vec3::Zero());
  ASSERT_TRUE(f.initialise(first.f_b_mps2, first.m_b_tesla));
  const int n_rest = 600;
  const int n_turn = 1200;
  const int n_end = 200;
  const Vec3 turn_rate(0.0, 0.0, 2.0 * std::numbers::pi / (n_turn * dt));
  double max_eskf = 0.0;
  double max_raw = 0.0;
  for (int k = 0; k < n_rest + n_turn + n_end; ++k) {
    const Vec3 omega = (k >= n_rest && k < n_rest + n_turn) ? turn_rate : Vec3::Zero();
    q_true = (q_true * quat_exp(omega * dt)).normalized();
    const AttitudeInput in = reading(omega);
    ASSERT_EQ(f.step(in), AttitudeStatus::kOk) << k;
    const std::optional<Quat> raw = ComplementaryAttitude::align(in.f_b_mps2, in.m_b_tesla, 0.0);
    ASSERT_TRUE(raw.has_value());
    max_raw = std::max(max_raw, std::abs(wrap_pi(yaw_of(*raw) - yaw_of(q_true))));
    max_eskf = std::max(max_eskf, std::abs(wrap_pi(yaw_of(f.q_nb()) - yaw_of(q_true))));
  }
  EXPECT_GT(max_raw, 14.0 * kDeg);  // asin(5/20) = 14.5°: the disturbance is really there
  EXPECT_LT(max_eskf, 0.6 * max_raw) << "eskf " << max_eskf / kDeg << " raw " << max_raw / kDeg;
  EXPECT_LT(max_eskf, 9.0 * kDeg) << max_eskf / kDeg;
  EXPECT_GT(f.stats().mag_rejected, static_cast<std::uint64_t>(n_turn / 2));
}

// ----------------------------------------------------------------------------------------
// 6. DVL compensation of the accelerometer.

/// Max tilt error over the last 60 s of a 90 s circle (1 m/s, 0.2 rad/s, level) [rad].
double circle_tilt_error(bool with_dvl) {
  std::mt19937_64 rng(5);
  const double dt = 0.05;
  const Vec3 v_b(1.0, 0.0, 0.0);
  const Vec3 omega(0.0, 0.0, 0.2);
  Quat q_true = euler_deg(0.0, 0.0, 10.0);
  QuatEskf f{EskfParams{}};
  EXPECT_TRUE(f.initialise(static_specific_force_b(q_true), field_b(q_true, earth_field_n())));
  double max_tilt = 0.0;
  for (int k = 0; k < 1800; ++k) {
    q_true = (q_true * quat_exp(omega * dt)).normalized();
    AttitudeInput in = static_input(q_true, dt);
    in.omega_b_radps = omega + noise3(rng, 0.03 * kDeg / std::sqrt(dt));
    in.f_b_mps2 += omega.cross(v_b) + noise3(rng, 0.6e-3 * kG0);  // centripetal 0.2 m/s²
    if (with_dvl) {
      in.v_b_mps = v_b;
      in.dv_b_mps2 = Vec3::Zero();
    }
    EXPECT_EQ(f.step(in), AttitudeStatus::kOk);
    EXPECT_EQ(f.last_step().accel, UpdateStatus::kFused);
    if (k >= 600) {
      max_tilt = std::max(max_tilt, tilt_error(f.q_nb(), q_true));
    }
  }
  return max_tilt;
}

// GIVEN a constant-speed circle, so the accelerometer sees a centripetal 0.2 m/s²
// WHEN the filter runs with and without the DVL velocity
// THEN with v_b (E6) the tilt is right; without it the tilt leans into the turn (~1.2°).
TEST(QuatEskfDvl, CentripetalCompensationReducesTiltError) {
  const double with_dvl = circle_tilt_error(true);
  const double without = circle_tilt_error(false);
  // asin(0.2 / g0) = 1.17° without; with, only the gyro noise's tilt wander is left.
  EXPECT_LT(with_dvl, 0.3 * kDeg) << with_dvl / kDeg;
  EXPECT_GT(without, 0.8 * kDeg) << without / kDeg;
  EXPECT_LT(with_dvl, 0.25 * without) << with_dvl / kDeg << " vs " << without / kDeg;
}

// ----------------------------------------------------------------------------------------
// 7. No singularity.

/// Runs `n` gyro-only steps at body rate `omega` from q0 (accelerometer |f| = 0 and a field
/// 10× too strong, so neither is fused) and checks the attitude against q0 ⊗ Exp(ω t)
/// [rad]; returns the largest sin(pitch) of the truth.
double gyro_only_run(const Quat& q0, const Vec3& omega, double dt, int n) {
  QuatEskf f = initialised_at(q0, EskfParams{});
  double max_sin_pitch = -1.0;
  for (int k = 1; k <= n; ++k) {
    AttitudeInput in;
    in.omega_b_radps = omega;
    in.f_b_mps2 = Vec3::Zero();
    in.m_b_tesla = 10.0 * earth_field_n();
    in.dt_s = dt;
    EXPECT_EQ(f.step(in), AttitudeStatus::kOk) << k;
    EXPECT_EQ(f.last_step().accel, UpdateStatus::kRejectedGate) << k;
    EXPECT_NE(f.last_step().mag, UpdateStatus::kFused) << k;
    const Quat q_true = q0 * quat_exp(omega * (k * dt));
    EXPECT_LT(attitude_error_angle(f.q_nb(), q_true), 1e-6) << k;
    EXPECT_TRUE(covariance_healthy(f)) << k;
    max_sin_pitch = std::max(max_sin_pitch, -(q_true * Vec3::UnitX()).z());
  }
  EXPECT_EQ(f.stats().accel_rejected, static_cast<std::uint64_t>(n));
  EXPECT_EQ(f.stats().steps, static_cast<std::uint64_t>(n));
  return max_sin_pitch;
}

// GIVEN a filter initialised level at yaw 30°, accelerometer and magnetometer refused
// WHEN it pitches up at 0.5 rad/s through exactly +90° (step 150) on to 171.9° (step 300)
// THEN the attitude is the integrated truth within 1e-6 rad at every step, P stays PD.
TEST(QuatEskfSingularity, GyroOnlyThroughPitchNinetyMatchesTruth) {
  const double dt = std::numbers::pi / 150.0;  // 150 steps of 0.5 rad/s reach exactly π/2
  const double max_sin_pitch =
      gyro_only_run(euler_deg(0.0, 0.0, 30.0), Vec3(0.0, 0.5, 0.0), dt, 300);
  EXPECT_NEAR(max_sin_pitch, 1.0, 1e-12);  // the nose went straight up (and over)
}

// GIVEN the same, with a rate about all three axes from a rolled, pitched start
// WHEN it tumbles for 6 s (the nose passes within a few degrees of vertical)
// THEN the attitude still follows the truth within 1e-6 rad.
TEST(QuatEskfSingularity, GyroOnlyTumbleMatchesTruth) {
  const double max_sin_pitch =
      gyro_only_run(euler_deg(20.0, 60.0, -170.0), Vec3(0.3, 0.8, -0.4), 0.02, 300);
  EXPECT_GT(max_sin_pitch, 0.99);
}

// GIVEN a known field (hard iron estimated) and exact readings of every sensor
// WHEN the vehicle pitches up at 0.5 rad/s through exactly +90° and on to 171.9°
// THEN the accelerometer and the 3-D magnetometer are fused at every step (E12 has no
//      singularity, unlike a levelled heading), the attitude follows the truth within 1e-6 rad
//      and P stays positive definite.
TEST(QuatEskfSingularity, MagnetometerFusedThroughPitchNinety) {
  const double dt = std::numbers::pi / 150.0;
  const Vec3 omega(0.0, 0.5, 0.0);
  const Quat q0 = euler_deg(0.0, 0.0, 30.0);
  QuatEskf f(known_field_params(earth_field_n()));
  ASSERT_TRUE(f.initialise(static_specific_force_b(q0), field_b(q0, earth_field_n())));
  for (int k = 1; k <= 300; ++k) {
    const Quat q_true = q0 * quat_exp(omega * (k * dt));
    AttitudeInput in = static_input(q_true, dt);
    in.omega_b_radps = omega;
    ASSERT_EQ(f.step(in), AttitudeStatus::kOk) << k;
    EXPECT_EQ(f.last_step().accel, UpdateStatus::kFused) << k;
    EXPECT_EQ(f.last_step().mag, UpdateStatus::kFused) << k;
    EXPECT_LT(attitude_error_angle(f.q_nb(), q_true), 1e-6) << k;
    EXPECT_TRUE(covariance_healthy(f)) << k;
  }
}

// ----------------------------------------------------------------------------------------
// 8. Invalid input and covariance health.

struct Snapshot {
  Quat q;
  Vec3 b;
  Vec3 h;
  MatN P;
};

Snapshot snapshot(const QuatEskf& f) {
  return {f.q_nb(), f.gyro_bias_b(), f.hard_iron_b(), f.covariance()};
}

bool bit_identical(const Snapshot& a, const Snapshot& b) {
  return (a.q.coeffs().array() == b.q.coeffs().array()).all() &&
         (a.b.array() == b.b.array()).all() && (a.h.array() == b.h.array()).all() &&
         (a.P.array() == b.P.array()).all();
}

// GIVEN a filter estimating the hard iron that has run a few steps on readings with one
// WHEN a step has NaN or Inf in any input, or dt ≤ 0
// THEN it returns kRejectedInvalid, counts it, and q, b_g, h_b and P are bit-identical.
TEST(QuatEskfInvalid, NanInfOrBadDtIsRejectedAndStateUntouched) {
  const Quat q_true = euler_deg(4.0, 7.0, -30.0);
  QuatEskf f = initialised_at(q_true, known_field_params(earth_field_n()));
  AttitudeInput good = static_input(q_true);
  good.m_b_tesla += kPoolHardIron;
  good.omega_b_radps = Vec3(0.001, -0.002, 0.003);
  for (int k = 0; k < 20; ++k) {
    ASSERT_EQ(f.step(good), AttitudeStatus::kOk);
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<AttitudeInput> bad;
  for (const double v : {nan, inf, -inf}) {
    for (int i = 0; i < 3; ++i) {
      AttitudeInput in = good;
      in.omega_b_radps(i) = v;
      bad.push_back(in);
      in = good;
      in.f_b_mps2(i) = v;
      bad.push_back(in);
      in = good;
      in.m_b_tesla(i) = v;
      bad.push_back(in);
      in = good;
      in.v_b_mps = Vec3(0.5, 0.0, 0.0);
      (*in.v_b_mps)(i) = v;
      bad.push_back(in);
      in = good;
      in.v_b_mps = Vec3(0.5, 0.0, 0.0);
      in.dv_b_mps2(i) = v;
      bad.push_back(in);
    }
    AttitudeInput in = good;
    in.dt_s = v;
    bad.push_back(in);
  }
  for (const double dt : {0.0, -0.05, -0.0}) {
    AttitudeInput in = good;
    in.dt_s = dt;
    bad.push_back(in);
  }
  ASSERT_NE(f.hard_iron_b(), Vec3::Zero());
  const Snapshot before = snapshot(f);
  const AttitudeStats stats_before = f.stats();
  for (std::size_t i = 0; i < bad.size(); ++i) {
    EXPECT_EQ(f.step(bad[i]), AttitudeStatus::kRejectedInvalid) << i;
    EXPECT_TRUE(bit_identical(snapshot(f), before)) << i;
  }
  EXPECT_EQ(f.stats().rejected_invalid, stats_before.rejected_invalid + bad.size());
  EXPECT_EQ(f.stats().steps, stats_before.steps + bad.size());
  EXPECT_EQ(f.stats().accel_rejected, stats_before.accel_rejected);
  EXPECT_EQ(f.stats().mag_rejected, stats_before.mag_rejected);

  // dv_b is only an input together with v_b: without v_b it is ignored.
  AttitudeInput ignored = good;
  ignored.dv_b_mps2 = Vec3::Constant(nan);
  EXPECT_EQ(f.step(ignored), AttitudeStatus::kOk);
}

// GIVEN a filter
// WHEN dt is finite but absurd (1e300 s) so the predicted covariance overflows
// THEN the step reports kNumericalFault, counts it and keeps the last good state.
TEST(QuatEskfInvalid, OverflowingPredictionIsANumericalFaultWithStateKept) {
  const Quat q_true = euler_deg(4.0, 7.0, -30.0);
  QuatEskf f = initialised_at(q_true, known_field_params(earth_field_n()));
  const Snapshot before = snapshot(f);
  AttitudeInput in = static_input(q_true);
  in.dt_s = 1e300;
  EXPECT_EQ(f.step(in), AttitudeStatus::kNumericalFault);
  EXPECT_TRUE(bit_identical(snapshot(f), before));
  EXPECT_EQ(f.stats().numerical_faults, 1u);
  in.dt_s = 0.05;
  EXPECT_EQ(f.step(in), AttitudeStatus::kOk);
}

// GIVEN bad first samples
// WHEN initialise() is called
// THEN it refuses NaN/Inf and a zero specific force.
TEST(QuatEskfInvalid, InitialiseRefusesNonFiniteOrZeroSpecificForce) {
  QuatEskf f{EskfParams{}};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(f.initialise(Vec3(0.0, 0.0, nan), earth_field_n()));
  EXPECT_FALSE(f.initialise(Vec3(0.0, 0.0, -kG0), Vec3(nan, 0.0, 0.0)));
  EXPECT_FALSE(f.initialise(Vec3::Zero(), earth_field_n()));
  EXPECT_TRUE(f.initialise(Vec3(0.0, 0.0, -kG0), earth_field_n()));
  EXPECT_EQ(f.kind(), AttitudeFilterKind::kEskf);
  EXPECT_NEAR(f.mag_reference_norm(), earth_field_n().norm(), 1e-18);
  EXPECT_NEAR(f.mag_reference_inclination(), std::atan2(4.0, 2.0), 1e-12);
  EXPECT_TRUE(covariance_healthy(f));
  // A known field is the reference whatever the first sample, and h is estimated.
  QuatEskf k(known_field_params(kPoolField));
  EXPECT_TRUE(k.initialise(Vec3(0.0, 0.0, -kG0), earth_field_n()));
  EXPECT_TRUE(k.estimates_hard_iron());
  EXPECT_EQ(k.mag_field_n(), kPoolField);
  EXPECT_NEAR(k.mag_reference_norm(), 50e-6, 1e-18);
  EXPECT_NEAR(k.mag_reference_inclination(), std::atan2(4.0, 3.0), 1e-12);
  EXPECT_TRUE(is_symmetric_pd(k.covariance()));
}

/// 5000 random but finite steps (seed 2024): rates up to 3 rad/s, dt 1 ms..0.5 s, specific
/// forces near and far from g, fields of any direction, DVL velocity half the time.
void random_steps_keep_covariance_healthy(const EskfParams& p) {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_real_distribution<double> u_dt(1e-3, 0.5);
  std::bernoulli_distribution coin(0.5);
  QuatEskf f(p);
  ASSERT_TRUE(f.initialise(Vec3(0.3, -0.2, -kG0), earth_field_n()));
  for (int k = 0; k < 5000; ++k) {
    AttitudeInput in;
    in.omega_b_radps = 3.0 * Vec3(u(rng), u(rng), u(rng));
    const Vec3 down_b = Vec3(u(rng), u(rng), u(rng)).normalized();
    const double f_scale = coin(rng) ? 1.0 + 0.1 * u(rng) : 2.0 + u(rng);
    in.f_b_mps2 = -kG0 * f_scale * down_b;
    in.m_b_tesla = 5e-5 * Vec3(u(rng), u(rng), u(rng));
    in.dt_s = u_dt(rng);
    if (coin(rng)) {
      in.v_b_mps = 2.0 * Vec3(u(rng), u(rng), u(rng));
      in.dv_b_mps2 = 0.5 * Vec3(u(rng), u(rng), u(rng));
    }
    ASSERT_EQ(f.step(in), AttitudeStatus::kOk) << k;
    ASSERT_TRUE(covariance_healthy(f)) << k << "\n" << f.covariance();
    ASSERT_NEAR(f.q_nb().norm(), 1.0, 1e-12) << k;
    ASSERT_TRUE(f.gyro_bias_b().allFinite() && f.hard_iron_b().allFinite()) << k;
    ASSERT_LE(f.gyro_bias_b().cwiseAbs().maxCoeff(), p.gyro_bias_limit_radps) << k;
  }
  EXPECT_EQ(f.stats().steps, 5000u);
  EXPECT_EQ(f.stats().numerical_faults, 0u);
  EXPECT_GT(f.stats().accel_rejected, 0u);
  EXPECT_GT(f.stats().mag_rejected, 0u);
}

// GIVEN the default parameters (Earth field unknown, h held at 0) with the NIS gate on
// WHEN 5000 random steps run
// THEN every step is kOk, P stays exactly symmetric and positive definite on (δθ, δb_g) with
//      zero δh rows, q stays unit.
TEST(QuatEskfHealth, RandomStepsKeepCovarianceSymmetricPositiveDefinite) {
  EskfParams p;
  p.mag_gate_nis = 11.34;  // χ²(3) 99 %: exercise the NIS path too
  random_steps_keep_covariance_healthy(p);
}

// GIVEN a known Earth field (h estimated, 9 × 9 P) with the NIS gate off and on
// WHEN 5000 random steps run
// THEN the same holds with all of P positive definite.
TEST(QuatEskfHealth, RandomStepsKeepCovarianceHealthyWhileEstimatingTheHardIron) {
  for (const double nis_gate : {0.0, 11.34}) {
    EskfParams p = known_field_params(earth_field_n());
    p.mag_gate_nis = nis_gate;
    random_steps_keep_covariance_healthy(p);
  }
}

// GIVEN navd's default FilterParams THEN they describe exactly the default EskfParams (the
// two sets of defaults live in two structs; this keeps them equal).
TEST(QuatEskfParams, FilterParamsDefaultsMapOntoTheEskfDefaults) {
  const EskfParams mapped = eskf_params(FilterParams{});
  const EskfParams d;
  EXPECT_EQ(mapped.gyro_noise_radps_rthz, d.gyro_noise_radps_rthz);
  EXPECT_EQ(mapped.gyro_bias_walk_radps2_rthz, d.gyro_bias_walk_radps2_rthz);
  EXPECT_EQ(mapped.initial_tilt_std_rad, d.initial_tilt_std_rad);
  EXPECT_EQ(mapped.initial_yaw_std_rad, d.initial_yaw_std_rad);
  EXPECT_EQ(mapped.initial_gyro_bias_std_radps, d.initial_gyro_bias_std_radps);
  EXPECT_EQ(mapped.gyro_bias_limit_radps, d.gyro_bias_limit_radps);
  EXPECT_EQ(mapped.accel_std_mps2, d.accel_std_mps2);
  EXPECT_EQ(mapped.accel_gate_mps2, d.accel_gate_mps2);
  EXPECT_EQ(mapped.mag_field_n_tesla, d.mag_field_n_tesla);
  EXPECT_EQ(mapped.initial_hard_iron_std_tesla, d.initial_hard_iron_std_tesla);
  EXPECT_EQ(mapped.hard_iron_walk_tesla_rts, d.hard_iron_walk_tesla_rts);
  EXPECT_EQ(mapped.mag_std_tesla, d.mag_std_tesla);
  EXPECT_EQ(mapped.mag_norm_gate, d.mag_norm_gate);
  EXPECT_EQ(mapped.mag_inclination_gate_rad, d.mag_inclination_gate_rad);
  EXPECT_EQ(mapped.mag_gate_nis, d.mag_gate_nis);
  EXPECT_EQ(mapped.declination_rad, d.declination_rad);
}

}  // namespace
}  // namespace nav::estimator
