// SPDX-License-Identifier: MIT
// Equations A1..A9 are stated in complementary_attitude.hpp.
#include "nav/estimator/complementary_attitude.hpp"

#include <cmath>

#include "nav/common/ensure.hpp"
#include "nav/common/units.hpp"

namespace nav::estimator {

Quat quat_exp(const Vec3& phi_rad) {
  const double angle = phi_rad.norm();
  if (angle < 1e-12) {
    // Second-order series keeps the result unit-norm to machine precision for tiny angles.
    return Quat(1.0, 0.5 * phi_rad.x(), 0.5 * phi_rad.y(), 0.5 * phi_rad.z()).normalized();
  }
  return Quat(Eigen::AngleAxisd(angle, phi_rad / angle));  // (A9)
}

ComplementaryAttitude::ComplementaryAttitude(const FilterParams& params) : params_(params) {
  NAV_ENSURE(validate(params).has_value(), "filter parameters must be validated first");
}

std::optional<Quat> ComplementaryAttitude::align(const Vec3& f_b_mps2, const Vec3& m_b,
                                                 double magnetic_declination_rad) {
  if (!f_b_mps2.allFinite() || !m_b.allFinite() || !std::isfinite(magnetic_declination_rad) ||
      f_b_mps2.norm() <= 0.0) {
    return std::nullopt;
  }
  const Vec3& f = f_b_mps2;
  Euler e;
  e.roll = std::atan2(-f.y(), -f.z());                              // (A1)
  e.pitch = std::atan2(f.x(), std::hypot(f.y(), f.z()));            // (A1)
  const Mat3 R_levelled = (Eigen::AngleAxisd(e.pitch, Vec3::UnitY()) *
                           Eigen::AngleAxisd(e.roll, Vec3::UnitX())).toRotationMatrix();
  const Vec3 m_l = R_levelled * m_b;                                // (A2)
  const double yaw_mag = std::hypot(m_l.x(), m_l.y()) > 0.0 ? std::atan2(-m_l.y(), m_l.x())
                                                             : 0.0;
  e.yaw = wrap_pi(yaw_mag + magnetic_declination_rad);             // (A3)
  return quat_from_euler(e);
}

void ComplementaryAttitude::reset(const Quat& q_nb) {
  NAV_ENSURE(q_nb.coeffs().allFinite() && q_nb.norm() > 0.0, "attitude must be a rotation");
  q_nb_ = q_nb.normalized();
  b_g_.setZero();
  e_.setZero();
}

StepStatus ComplementaryAttitude::step(const Vec3& omega_b_radps, const Vec3& f_b_mps2,
                                       const Vec3& m_b, double dt_s) {
  NAV_ENSURE(dt_s > 0.0, "attitude step needs dt > 0; the caller filters bad intervals");
  if (!omega_b_radps.allFinite() || !f_b_mps2.allFinite() || !m_b.allFinite() ||
      !std::isfinite(dt_s)) {
    return StepStatus::kRejectedInvalid;
  }
  const Mat3 R = q_nb_.toRotationMatrix();
  Vec3 e = Vec3::Zero();

  const double f_norm = f_b_mps2.norm();
  if (params_.accel_weight > 0.0 && f_norm > 0.0 &&
      std::abs(f_norm - units::kStandardGravity) <= params_.accel_gate_mps2) {
    const Vec3 v_a = -f_b_mps2 / f_norm;                          // measured down (A4)
    const Vec3 v_a_hat = R.transpose() * Vec3::UnitZ();           // estimated down (A4)
    e += params_.accel_weight * v_a.cross(v_a_hat);               // (A6)
  }

  if (params_.mag_weight > 0.0) {
    const Vec3 h_n = R * m_b;                                     // field in NED (A5)
    const double h_xy = std::hypot(h_n.x(), h_n.y());
    if (h_xy > 0.0) {
      const Vec3 h_hat_n(h_n.x() / h_xy, h_n.y() / h_xy, 0.0);   // estimated heading (A5)
      const double decl = params_.magnetic_declination_rad;
      const Vec3 b_n(std::cos(decl), std::sin(decl), 0.0);        // reference heading (A5)
      e += params_.mag_weight * (R.transpose() * h_hat_n.cross(b_n));  // (A6)
    }
  }

  const double b_max = params_.gyro_bias_limit_radps;
  b_g_ = (b_g_ - params_.attitude_ki_per_s2 * e * dt_s).cwiseMax(-b_max).cwiseMin(b_max);  // (A7)
  const Vec3 omega = omega_b_radps - b_g_ + params_.attitude_kp_per_s * e;                  // (A8)
  q_nb_ = (q_nb_ * quat_exp(omega * dt_s)).normalized();                                    // (A9)
  e_ = e;
  return StepStatus::kApplied;
}

}  // namespace nav::estimator
