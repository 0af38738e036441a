// SPDX-License-Identifier: MIT
#include "nav/estimator/complementary_attitude.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace nav::estimator {
namespace {

using testing::earth_field_n;
using testing::field_b;
using testing::static_specific_force_b;

constexpr double kPi = std::numbers::pi;

FilterParams no_feedback() {
  FilterParams p;
  p.attitude_kp_per_s = 0.0;
  p.attitude_ki_per_s2 = 0.0;
  return p;
}

struct AlignmentCase {
  const char* name;
  Euler truth;
  double declination_rad;
};

class StaticAlignment : public ::testing::TestWithParam<AlignmentCase> {};

TEST_P(StaticAlignment, RecoversRollPitchYaw) {
  // GIVEN a vehicle at rest with a known attitude, in a field `declination` east of North
  const AlignmentCase c = GetParam();
  const Quat q_true = quat_from_euler(c.truth);
  const Vec3 m_n = Eigen::AngleAxisd(c.declination_rad, Vec3::UnitZ()) * earth_field_n();
  // WHEN it aligns from one accelerometer and one magnetometer sample
  const auto q = ComplementaryAttitude::align(static_specific_force_b(q_true),
                                              field_b(q_true, m_n), c.declination_rad);
  // THEN roll, pitch and (true) yaw are the truth
  ASSERT_TRUE(q.has_value());
  const Euler e = euler_from_quat(*q);
  EXPECT_NEAR(e.roll, c.truth.roll, 1e-9);
  EXPECT_NEAR(e.pitch, c.truth.pitch, 1e-9);
  EXPECT_NEAR(wrap_pi(e.yaw - c.truth.yaw), 0.0, 1e-9);
  EXPECT_NEAR(attitude_error_angle(*q, q_true), 0.0, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(
    Attitudes, StaticAlignment,
    ::testing::Values(AlignmentCase{"Level", {0.0, 0.0, 0.0}, 0.0},
                      AlignmentCase{"Tilted", {0.1, -0.2, 0.7}, 0.0},
                      AlignmentCase{"TiltedSouthWest", {-0.3, 0.25, -2.5}, 0.0},
                      AlignmentCase{"NearSouth", {0.05, 0.02, 3.1}, 0.0},
                      AlignmentCase{"EastDeclination", {0.2, 0.1, -1.2}, 0.15},
                      AlignmentCase{"WestDeclinationYawWraps", {-0.1, -0.3, 3.0}, -0.3}),
    [](const ::testing::TestParamInfo<AlignmentCase>& p) { return std::string(p.param.name); });

TEST(ComplementaryAttitude, LevelNorthAlignmentIsIdentity) {
  // GIVEN a level sensor pointing North: f = (0, 0, -g), m = (0.2, 0, 0.4) G (protocols.md
  // worked 0xCB example); WHEN aligned; THEN the attitude is the identity.
  const auto q = ComplementaryAttitude::align(Vec3(0.0, 0.0, -9.80665), Vec3(0.2, 0.0, 0.4), 0.0);
  ASSERT_TRUE(q.has_value());
  EXPECT_NEAR(attitude_error_angle(*q, Quat::Identity()), 0.0, 1e-12);
}

TEST(ComplementaryAttitude, ConstantRateSingleStepHandComputed) {
  // GIVEN q0 = identity, ω = (0, 0, 0.5) rad/s, dt = 0.2 s and no accel/mag feedback
  ComplementaryAttitude f(no_feedback());
  f.reset(Quat::Identity());
  // WHEN one step is taken
  ASSERT_EQ(f.step(Vec3(0.0, 0.0, 0.5), Vec3(0, 0, -9.80665), Vec3(0.2, 0, 0.4), 0.2),
            StepStatus::kApplied);
  // THEN q = [cos(0.05), 0, 0, sin(0.05)] = [0.99875026039, 0, 0, 0.04997916927]
  const Quat& q = f.q_nb();
  EXPECT_NEAR(q.w(), 0.99875026039496628, 1e-12);
  EXPECT_NEAR(q.x(), 0.0, 1e-12);
  EXPECT_NEAR(q.y(), 0.0, 1e-12);
  EXPECT_NEAR(q.z(), 0.049979169270678331, 1e-12);
  EXPECT_NEAR(euler_from_quat(q).yaw, 0.1, 1e-12);
}

TEST(ComplementaryAttitude, ConstantRateFromTiltedAttitude) {
  // GIVEN q0 = Euler(0.1, 0.2, 0.3), ω = (0.3, −0.4, 1.2) rad/s (|ω| = 1.3), dt = 0.1 s
  ComplementaryAttitude f(no_feedback());
  const Quat q0 = quat_from_euler({0.1, 0.2, 0.3});
  f.reset(q0);
  f.step(Vec3(0.3, -0.4, 1.2), Vec3(0, 0, -9.8), Vec3(1, 0, 0), 0.1);
  // THEN q = q0 ⊗ [cos(0.065), sin(0.065) ω/|ω|] (body-frame rotation by |ω| dt = 0.13 rad)
  const double half = 0.065;
  const Quat dq(std::cos(half), std::sin(half) * 0.3 / 1.3, std::sin(half) * -0.4 / 1.3,
                std::sin(half) * 1.2 / 1.3);
  EXPECT_NEAR(attitude_error_angle(f.q_nb(), q0 * dq), 0.0, 1e-12);
}

TEST(ComplementaryAttitude, ManySmallStepsIntegrateExactly) {
  // GIVEN 100 steps of 10 ms at a constant yaw rate of 0.5 rad/s; THEN yaw = 0.5 rad.
  ComplementaryAttitude f(no_feedback());
  f.reset(Quat::Identity());
  for (int k = 0; k < 100; ++k) f.step(Vec3(0, 0, 0.5), Vec3(0, 0, -9.8), Vec3(1, 0, 0), 0.01);
  EXPECT_NEAR(euler_from_quat(f.q_nb()).yaw, 0.5, 1e-12);
  EXPECT_NEAR(f.q_nb().norm(), 1.0, 1e-15);
}

TEST(ComplementaryAttitude, FeedbackRemovesAnInitialError) {
  // GIVEN a static vehicle (roll 0.1, pitch −0.05, yaw 1.0) and an estimate 10° off in
  // roll and 20° off in yaw, at 100 Hz
  const Quat q_true = quat_from_euler({0.1, -0.05, 1.0});
  const Vec3 f_b = static_specific_force_b(q_true);
  const Vec3 m_b = field_b(q_true, earth_field_n());
  const Quat q_start = quat_from_euler({0.1 + 10.0 * kPi / 180.0, -0.05, 1.0 + 20.0 * kPi / 180.0});
  // WHEN the proportional filter (k_I = 0) runs 30 s: 15 time constants of 1/k_P = 2 s
  FilterParams p;
  p.attitude_ki_per_s2 = 0.0;
  ComplementaryAttitude f(p);
  f.reset(q_start);
  for (int k = 0; k < 3000; ++k) f.step(Vec3::Zero(), f_b, m_b, 0.01);
  // THEN the error is below 0.01°
  EXPECT_LT(attitude_error_angle(f.q_nb(), q_true), 0.01 * kPi / 180.0);
  // AND with the default integral gain the error is below 0.5° after 60 s (the integral
  // term winds up during the transient and unwinds with its slow pole k_I/k_P)
  ComplementaryAttitude g{FilterParams{}};
  g.reset(q_start);
  for (int k = 0; k < 6000; ++k) g.step(Vec3::Zero(), f_b, m_b, 0.01);
  EXPECT_LT(attitude_error_angle(g.q_nb(), q_true), 0.5 * kPi / 180.0);
}

TEST(ComplementaryAttitude, MagnetometerCorrectsHeadingOnly) {
  // GIVEN a level estimate 30° off in yaw and no accelerometer feedback
  FilterParams p;
  p.accel_weight = 0.0;
  p.attitude_ki_per_s2 = 0.0;
  ComplementaryAttitude f(p);
  const Quat q_true = quat_from_euler({0.0, 0.0, 0.5});
  f.reset(quat_from_euler({0.0, 0.0, 0.5 + 30.0 * kPi / 180.0}));
  // WHEN it runs 30 s with a steeply inclined field (63° dip)
  for (int k = 0; k < 3000; ++k) {
    f.step(Vec3::Zero(), static_specific_force_b(q_true), field_b(q_true, earth_field_n()), 0.01);
  }
  // THEN yaw is right and roll/pitch were never disturbed
  const Euler e = euler_from_quat(f.q_nb());
  EXPECT_NEAR(e.yaw, 0.5, 1e-6);
  EXPECT_NEAR(e.roll, 0.0, 1e-12);
  EXPECT_NEAR(e.pitch, 0.0, 1e-12);
}

TEST(ComplementaryAttitude, IntegralTermEstimatesAConstantGyroBias) {
  // GIVEN a static vehicle whose gyro reads a constant bias b = (0.004, −0.003, 0.005) rad/s
  const Quat q_true = quat_from_euler({-0.05, 0.08, -2.0});
  const Vec3 bias(0.004, -0.003, 0.005);
  FilterParams p;
  p.attitude_ki_per_s2 = 0.05;
  ComplementaryAttitude f(p);
  f.reset(q_true);
  // WHEN it runs 300 s at 100 Hz
  const Vec3 f_b = static_specific_force_b(q_true);
  const Vec3 m_b = field_b(q_true, earth_field_n());
  for (int k = 0; k < 30000; ++k) f.step(bias, f_b, m_b, 0.01);
  // THEN the bias estimate matches and the attitude does not drift
  EXPECT_LT((f.gyro_bias_b() - bias).norm(), 1e-5);
  EXPECT_LT(attitude_error_angle(f.q_nb(), q_true), 1e-4);
}

TEST(ComplementaryAttitude, AccelerationAboveTheGateDoesNotTilt) {
  // GIVEN a level vehicle accelerating forward at 3 m/s²: |f| = 10.2553 m/s², 0.449 m/s²
  // above g0, and an accel gate of 0.4 m/s²
  const Vec3 f_b(3.0, 0.0, -9.80665);
  ASSERT_GT(f_b.norm() - 9.80665, 0.4);
  FilterParams gated;
  gated.accel_gate_mps2 = 0.4;
  // WHEN steps run with that specific force (magnetometer consistent with level North)
  ComplementaryAttitude g(gated);
  g.reset(Quat::Identity());
  for (int k = 0; k < 500; ++k) g.step(Vec3::Zero(), f_b, earth_field_n(), 0.01);
  // THEN the attitude stays level (the accelerometer was ignored)
  EXPECT_LT(attitude_error_angle(g.q_nb(), Quat::Identity()), 1e-12);
}

TEST(ComplementaryAttitude, NanInputsAreRejected) {
  ComplementaryAttitude f{FilterParams{}};
  const Quat q0 = quat_from_euler({0.1, 0.2, 0.3});
  f.reset(q0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(f.step(Vec3(nan, 0, 0), Vec3(0, 0, -9.8), Vec3(1, 0, 0), 0.01),
            StepStatus::kRejectedInvalid);
  EXPECT_EQ(f.step(Vec3::Zero(), Vec3(0, inf, -9.8), Vec3(1, 0, 0), 0.01),
            StepStatus::kRejectedInvalid);
  EXPECT_EQ(f.step(Vec3::Zero(), Vec3(0, 0, -9.8), Vec3(1, nan, 0), 0.01),
            StepStatus::kRejectedInvalid);
  EXPECT_EQ(f.q_nb().coeffs(), q0.normalized().coeffs());
  EXPECT_FALSE(ComplementaryAttitude::align(Vec3(nan, 0, -9.8), Vec3(1, 0, 0), 0.0));
  EXPECT_FALSE(ComplementaryAttitude::align(Vec3(0, 0, -9.8), Vec3(1, 0, inf), 0.0));
  EXPECT_FALSE(ComplementaryAttitude::align(Vec3::Zero(), Vec3(1, 0, 0), 0.0));
}

TEST(ComplementaryAttitude, NonPositiveDtIsAContractViolation) {
  ComplementaryAttitude f{FilterParams{}};
  EXPECT_THROW(f.step(Vec3::Zero(), Vec3(0, 0, -9.8), Vec3(1, 0, 0), 0.0), std::logic_error);
}

TEST(QuatExp, MatchesAngleAxisAndTinyAngles) {
  const Vec3 phi(0.2, -0.1, 0.3);
  EXPECT_NEAR(attitude_error_angle(quat_exp(phi),
                                   Quat(Eigen::AngleAxisd(phi.norm(), phi.normalized()))),
              0.0, 1e-15);
  const Quat tiny = quat_exp(Vec3(1e-14, 0, 0));
  EXPECT_NEAR(tiny.norm(), 1.0, 1e-15);
  EXPECT_NEAR(tiny.x(), 0.5e-14, 1e-20);
}

}  // namespace
}  // namespace nav::estimator
