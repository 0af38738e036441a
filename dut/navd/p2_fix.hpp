// SPDX-License-Identifier: MIT
// An iUSBL's fix (USBLLONG and NVBRELATT of one ping, docs/scenario.md `iusbl`) as paper P2's
// relative observations at the ping's time of validity. Pure.
//
// The device reports the other vehicle in its own frame (X, Y, Z) with its own attitude
// (roll, pitch, yaw: R_nd). With the device's mounting on this vehicle (rotation R_bd, lever
// arm l_b from the reference point):
//
//   R_nb = R_nd R_bdᵀ,  ψ_b = yaw(R_nb)             this vehicle's heading, by the device
//   d_n  = R_nd [X, Y, Z]ᵀ + R_nb l_b               where the ping came from, NED, from the
//                                                   vehicle's reference point
//   t_e  = measurement_time − propagation_time      when the ping left the other vehicle
//   τ    = propagation_time
//   d_n' = d_n + v_n τ                              the other vehicle from where this one was
//                                                   at t_e (v_n: this vehicle's velocity)
//   d_h  = Rz(ψ_b)ᵀ d_n'                            in the level frame of this heading
//
// and the observations of papers.md P2 (O1..O6 of p2_observations.hpp) follow:
//   2-D distance |d_h.xy|, 3-D distance |d_h|, bearing atan2(d_h.y, d_h.x),
//   elevation atan2(d_h.z, |d_h.xy|), heading and pitch from NVBRELATT.
// The bearing is relative to the heading the device's attitude gives, which the filter's
// model compares with its own ψ_i: the two agree when the device's AHRS and the filter agree.
#pragma once

#include <optional>
#include <string>

#include "nav/common/frames.hpp"
#include "nav/common/result.hpp"
#include "nav/estimator/p2_joint_ekf.hpp"
#include "nav/protocols/evologics_usbl.hpp"

namespace nav::dut {

/// One ping's relative observations and the time they are valid at.
struct P2Fix {
  double t_emitted_s = 0.0;  ///< t_e on the device clock (the common time base) [s]
  int remote_address = 0;    ///< the other vehicle's acoustic address
  /// The observations by kind (P2Observation order); which are filled: all six.
  Eigen::Matrix<double, estimator::kP2ObservationKinds, 1> z =
      Eigen::Matrix<double, estimator::kP2ObservationKinds, 1>::Zero();
};

/// The fix of a USBLLONG and the NVBRELATT of the same ping (same measurement time and
/// address), with this vehicle's velocity v_n [m/s, NED] and the device's mounting: rotation
/// q_bd (device → body) and lever arm l_b (the device's origin from the reference point, body
/// FRD) [m].
/// Errors (one line): the two lines are not of one ping, a non-finite value, a propagation
/// time < 0 or a position at the device itself.
Result<P2Fix> p2_fix(const protocols::evologics::UsblLong& l,
                     const protocols::evologics::RelativeAttitude& a, const Vec3& v_n,
                     const Quat& q_bd = Quat::Identity(), const Vec3& l_b = Vec3::Zero());

}  // namespace nav::dut
