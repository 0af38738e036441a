// SPDX-License-Identifier: MIT
// The conversion is stated in p2_fix.hpp.
#include "p2_fix.hpp"

#include <cmath>

namespace nav::dut {

using estimator::P2Observation;

Result<P2Fix> p2_fix(const protocols::evologics::UsblLong& l,
                     const protocols::evologics::RelativeAttitude& a, const Vec3& v_n,
                     const Quat& q_bd, const Vec3& l_b) {
  if (a.measurement_time_s != l.measurement_time_s || a.remote_address != l.remote_address) {
    return fail(ErrorCode::kInvalidArgument,
                "NVBRELATT of another ping than the USBLLONG before it (measurement time or "
                "address differ)");
  }
  const Vec3 xyz(l.x_m, l.y_m, l.z_m);
  if (!xyz.allFinite() || !std::isfinite(l.roll_rad) || !std::isfinite(l.pitch_rad) ||
      !std::isfinite(l.yaw_rad) || !std::isfinite(l.measurement_time_s) ||
      !std::isfinite(a.relative_heading_rad) || !std::isfinite(a.relative_pitch_rad) ||
      !v_n.allFinite() || !q_bd.coeffs().allFinite() || !l_b.allFinite()) {
    return fail(ErrorCode::kInvalidArgument, "iUSBL fix with a value that is not finite");
  }
  if (l.propagation_time_us < 0) {
    return fail(ErrorCode::kInvalidArgument, "iUSBL fix with a negative propagation time");
  }
  if (xyz.norm() == 0.0) {
    return fail(ErrorCode::kInvalidArgument, "iUSBL fix at the device itself (X = Y = Z = 0)");
  }
  const Quat q_nd = quat_from_euler(Euler{l.roll_rad, l.pitch_rad, l.yaw_rad});
  const double tau_s = l.propagation_time_us * 1e-6;
  const Quat q_nb = q_nd * q_bd.conjugate();  // R_nb = R_nd R_bdᵀ
  const double psi_b = euler_from_quat(q_nb).yaw;
  const Vec3 d_n = q_nd * xyz + q_nb * l_b;  // from the reference point
  const Vec3 d_n_at_emission = d_n + v_n * tau_s;
  const Vec3 d_h = Eigen::AngleAxisd(psi_b, Vec3::UnitZ()).toRotationMatrix().transpose() *
                   d_n_at_emission;
  P2Fix f;
  f.t_emitted_s = l.measurement_time_s - tau_s;
  f.remote_address = l.remote_address;
  const double horizontal = d_h.head<2>().norm();
  f.z(static_cast<int>(P2Observation::kDistance2d)) = horizontal;
  f.z(static_cast<int>(P2Observation::kDistance3d)) = d_h.norm();
  f.z(static_cast<int>(P2Observation::kBearing)) = std::atan2(d_h.y(), d_h.x());
  f.z(static_cast<int>(P2Observation::kHeading)) = wrap_pi(a.relative_heading_rad);
  f.z(static_cast<int>(P2Observation::kElevation)) = std::atan2(d_h.z(), horizontal);
  f.z(static_cast<int>(P2Observation::kPitch)) = a.relative_pitch_rad;
  return f;
}

}  // namespace nav::dut
