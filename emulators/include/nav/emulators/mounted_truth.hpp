// SPDX-License-Identifier: MIT
// A device mounted on its vehicle: the vehicle's truth moved to the device's place and turned
// into the device's own axes, so that every generator measures what a device mounted that way
// would (a DVL's velocity at its transducer in its beam axes, a GPS fix at its antenna, an
// IMU's rates and specific force in its case axes, with the lever arm's centripetal and
// tangential accelerations).
//
// With d the device frame, b the vehicle body (FRD), l the lever arm (the device's origin
// from the body's reference point, in b) and R_bd the mounting rotation (device -> body):
//   p_d = p + R_nb l                                     (position of the device origin)
//   v_d = v + R_nb (omega_b x l)
//   a_d = a + R_nb (alpha_b x l + omega_b x (omega_b x l)),  alpha_b = d omega_b / dt
//   q_nd = q_nb * q_bd
//   omega_d = R_bd^T omega_b
//   f_d = R_bd^T (f_b + alpha_b x l + omega_b x (omega_b x l))
// (n treated as inertial, as in truth_kind.hpp.) alpha_b is the central difference of the
// body's omega_b over +-1 ms (one-sided at t < 1 ms); no truth kind provides it analytically
// yet. The distance travelled stays the vehicle's.
#pragma once

#include <memory>

#include "nav/common/frames.hpp"
#include "nav/emulators/truth_kind.hpp"

namespace nav::emulators {

/// Where and how a device sits on its vehicle (a scenario device's `mount`).
struct Mount {
  Vec3 lever_arm_b = Vec3::Zero();  ///< the device's origin from the body reference, in b [m]
  Quat q_bd = Quat::Identity();     ///< rotation device -> body (ZYX roll, pitch, yaw)
  /// No lever arm and no rotation: the device sees the vehicle's truth exactly.
  bool is_identity() const {
    return lever_arm_b == Vec3::Zero() && q_bd.coeffs() == Quat::Identity().coeffs();
  }
};

/// The truth of a mounted device, from its vehicle's.
class MountedTruth final : public Truth {
 public:
  MountedTruth(std::shared_ptr<const Truth> body, const Mount& mount);
  TruthSample at(Duration t) const override;
  /// The vehicle's water and wind: a device sees the sea its vehicle is in.
  Vec3 water_velocity_n(Duration t) const override { return body_->water_velocity_n(t); }
  Vec3 wind_velocity_n(Duration t) const override { return body_->wind_velocity_n(t); }
  double surface_depth_m(Duration t) const override { return body_->surface_depth_m(t); }

 private:
  /// The body's angular acceleration at t, in b [rad/s^2].
  Vec3 angular_acceleration_b(Duration t) const;

  std::shared_ptr<const Truth> body_;
  Mount mount_;
  Mat3 R_bd_;
};

}  // namespace nav::emulators
