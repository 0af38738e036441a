// SPDX-License-Identifier: MIT
// Frames and attitude conventions.
//
// Navigation frame n: local tangent plane at the scenario datum, NED (x North, y East,
// z Down; depth = +z). Body frame b: FRD (x forward, y starboard, z down).
// Attitude: Hamilton unit quaternion q_nb, so v_n = q_nb * v_b. Euler angles are ZYX
// (yaw psi, pitch theta, roll phi): R_nb = Rz(psi) * Ry(theta) * Rx(phi); they appear only in
// I/O and reports. Angles are wrapped to (-pi, pi].
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

namespace nav {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

/// Roll, pitch, yaw (ZYX convention) [rad].
struct Euler {
  double roll = 0.0;   ///< phi, about body x [rad]
  double pitch = 0.0;  ///< theta, about the once-rotated y [rad]
  double yaw = 0.0;    ///< psi, about NED z, 0 = North, positive towards East [rad]
};

/// Wraps an angle to (-pi, pi] [rad].
inline double wrap_pi(double a) {
  a = std::remainder(a, 2.0 * std::numbers::pi);
  return a <= -std::numbers::pi ? a + 2.0 * std::numbers::pi : a;
}

/// q_nb from ZYX Euler angles.
inline Quat quat_from_euler(const Euler& e) {
  return Quat(Eigen::AngleAxisd(e.yaw, Vec3::UnitZ()) *
              Eigen::AngleAxisd(e.pitch, Vec3::UnitY()) *
              Eigen::AngleAxisd(e.roll, Vec3::UnitX()));
}

/// ZYX Euler kinematics: the body rate of a rotation ZYX(roll, pitch, yaw) whose angles change
/// at euler_dot = (roll', pitch', yaw') [rad/s].
inline Vec3 euler_rate_to_body(double roll, double pitch, const Vec3& euler_dot) {
  const double sr = std::sin(roll), cr = std::cos(roll);
  const double sp = std::sin(pitch), cp = std::cos(pitch);
  const double roll_dot = euler_dot.x(), pitch_dot = euler_dot.y(), yaw_dot = euler_dot.z();
  return Vec3{roll_dot - yaw_dot * sp,                 //
              pitch_dot * cr + yaw_dot * sr * cp,      //
              -pitch_dot * sr + yaw_dot * cr * cp};
}

/// ZYX Euler angles of q_nb; yaw and roll wrapped to (-pi, pi], pitch in [-pi/2, pi/2].
inline Euler euler_from_quat(const Quat& q_nb) {
  const Mat3 R = q_nb.normalized().toRotationMatrix();
  Euler e;
  e.pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  e.roll = std::atan2(R(2, 1), R(2, 2));
  e.yaw = std::atan2(R(1, 0), R(0, 0));
  return e;
}

/// Skew-symmetric matrix [v]x so that [v]x * w = v x w.
inline Mat3 skew(const Vec3& v) {
  Mat3 S;
  S << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return S;
}

/// Rotation angle between two attitudes [rad], in [0, pi].
inline double attitude_error_angle(const Quat& a, const Quat& b) {
  return a.angularDistance(b);
}

}  // namespace nav
