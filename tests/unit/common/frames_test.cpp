// SPDX-License-Identifier: MIT
// Frames and attitude conventions: ZYX Euler <-> quaternion, wrap_pi, skew.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "nav/common/frames.hpp"

namespace nav {
namespace {

constexpr double kPi = std::numbers::pi;

Mat3 rot_x(double a) {
  Mat3 R;
  R << 1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a);
  return R;
}
Mat3 rot_y(double a) {
  Mat3 R;
  R << std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a);
  return R;
}
Mat3 rot_z(double a) {
  Mat3 R;
  R << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
  return R;
}

TEST(Frames, QuatFromEulerIsRzRyRx) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-kPi, kPi);
  for (int i = 0; i < 1000; ++i) {
    const Euler e{u(rng), 0.5 * u(rng), u(rng)};
    const Mat3 R = rot_z(e.yaw) * rot_y(e.pitch) * rot_x(e.roll);
    ASSERT_LT((quat_from_euler(e).toRotationMatrix() - R).norm(), 1e-14);
  }
}

TEST(Frames, EulerQuatRoundTrip) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-kPi, kPi);
  for (int i = 0; i < 10000; ++i) {
    const Euler e{u(rng), 0.4999 * u(rng), u(rng)};
    const Euler back = euler_from_quat(quat_from_euler(e));
    ASSERT_NEAR(wrap_pi(back.roll - e.roll), 0.0, 1e-12) << i;
    ASSERT_NEAR(back.pitch, e.pitch, 1e-12) << i;
    ASSERT_NEAR(wrap_pi(back.yaw - e.yaw), 0.0, 1e-12) << i;
  }
  // And quaternion -> Euler -> quaternion for random unit quaternions (any attitude).
  std::normal_distribution<double> n(0.0, 1.0);
  for (int i = 0; i < 10000; ++i) {
    const Quat q = Quat(n(rng), n(rng), n(rng), n(rng)).normalized();
    ASSERT_LT(attitude_error_angle(quat_from_euler(euler_from_quat(q)), q), 1e-7) << i;
  }
}

TEST(Frames, BodyAxesInNed) {
  // Yaw 90 deg: the nose points East; pitch +: nose up (NED z negative); roll +: starboard
  // wing down.
  EXPECT_LT((quat_from_euler({0.0, 0.0, kPi / 2}) * Vec3::UnitX() - Vec3::UnitY()).norm(),
            1e-15);
  EXPECT_LT(
      (quat_from_euler({0.0, kPi / 6, 0.0}) * Vec3::UnitX() - Vec3{std::cos(kPi / 6), 0, -0.5})
          .norm(),
      1e-15);
  EXPECT_GT((quat_from_euler({0.2, 0.0, 0.0}) * Vec3::UnitY()).z(), 0.0);
}

TEST(Frames, EulerAnglesStayInRange) {
  std::mt19937_64 rng(13);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int i = 0; i < 10000; ++i) {
    const Euler e = euler_from_quat(Quat(n(rng), n(rng), n(rng), n(rng)));  // not normalised
    ASSERT_GT(e.roll, -kPi);
    ASSERT_LE(e.roll, kPi);
    ASSERT_GT(e.yaw, -kPi);
    ASSERT_LE(e.yaw, kPi);
    ASSERT_GE(e.pitch, -kPi / 2);
    ASSERT_LE(e.pitch, kPi / 2);
  }
}

TEST(Frames, WrapPiRange) {
  EXPECT_DOUBLE_EQ(wrap_pi(0.0), 0.0);
  EXPECT_DOUBLE_EQ(wrap_pi(kPi), kPi);
  EXPECT_DOUBLE_EQ(wrap_pi(-kPi), kPi);
  EXPECT_NEAR(wrap_pi(3 * kPi), kPi, 1e-15);
  EXPECT_NEAR(wrap_pi(-3 * kPi + 1e-9), -kPi + 1e-9, 1e-14);
  EXPECT_NEAR(wrap_pi(2 * kPi + 0.25), 0.25, 1e-15);
  EXPECT_NEAR(wrap_pi(-2 * kPi - 0.25), -0.25, 1e-15);
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> u(-1e4, 1e4);
  for (int i = 0; i < 100000; ++i) {
    const double a = u(rng);
    const double w = wrap_pi(a);
    ASSERT_GT(w, -kPi);
    ASSERT_LE(w, kPi);
    const double turns = (a - w) / (2 * kPi);
    ASSERT_NEAR(turns, std::round(turns), 1e-9) << a;
  }
}

TEST(Frames, SkewIsTheCrossProductMatrix) {
  std::mt19937_64 rng(15);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 v{n(rng), n(rng), n(rng)};
    const Vec3 w{n(rng), n(rng), n(rng)};
    ASSERT_LT((skew(v) * w - v.cross(w)).norm(), 1e-14);
    ASSERT_EQ(skew(v).transpose(), -skew(v));
    ASSERT_LT((skew(v) * v).norm(), 1e-14);
  }
}

TEST(Frames, AttitudeErrorAngle) {
  const Quat a = quat_from_euler({0.1, -0.2, 0.3});
  const Vec3 axis = Vec3(1.0, 2.0, -0.5).normalized();
  const Quat b = a * Quat(Eigen::AngleAxisd(0.05, axis));
  EXPECT_NEAR(attitude_error_angle(a, b), 0.05, 1e-14);
  EXPECT_NEAR(attitude_error_angle(a, Quat(-a.coeffs())), 0.0, 1e-7);  // q and -q: same
}

}  // namespace
}  // namespace nav
