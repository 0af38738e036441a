// SPDX-License-Identifier: MIT
// Attitude from gyro, accelerometer and magnetometer: quaternion form of the explicit
// complementary filter with gyro-bias estimation (proportional-integral feedback of the
// direction errors), plus the static alignment that initialises it.
//
// Reference: R. Mahony, T. Hamel, J.-M. Pflimlin, "Nonlinear Complementary Filters on the
// Special Orthogonal Group", IEEE Trans. Automatic Control 53(5), 2008 ("explicit
// complementary filter with bias correction"). The magnetometer term is restricted to
// heading (a rotation about the NED z axis), as PX4's attitude_estimator_q does, so that a
// magnetic disturbance cannot tilt roll/pitch and the heading gain does not shrink with the
// field's inclination. Alignment as in papers.md P0, eqs 1-3. Equation labels A1..A9 are
// this file's own.
//
// State:
//   | symbol | meaning                                | frame     | unit  |
//   |--------|----------------------------------------|-----------|-------|
//   | q_nb   | attitude, Hamilton unit quaternion     | body→NED  | -     |
//   | b_g    | gyro bias estimate                     | body FRD  | rad/s |
// Inputs per AHRS sample: ω_b gyro [rad/s], f_b specific force [m/s²], m_b magnetic field
// (any unit, only its direction is used), dt [s]. The AHRS sensor frame is the body frame.
//
// Alignment (first sample, vehicle assumed at rest):
//   A1  φ = atan2(−f_y, −f_z),   θ = atan2(f_x, √(f_y² + f_z²))
//   A2  m_l = Ry(θ) Rx(φ) m_b   (field levelled by roll and pitch)
//   A3  ψ = atan2(−m_l,y, m_l,x) + δ       (δ magnetic declination, east positive)
// Step (R = R_nb of q_nb):
//   A4  v_a = −f_b/|f_b|,  v̂_a = Rᵀ e_z             measured / estimated "down" in b
//   A5  h_n = R m_b,  ĥ_n = [h_x, h_y, 0]ᵀ/‖h_xy‖,  b_n = [cos δ, sin δ, 0]ᵀ
//                                                    field heading as estimated / reference
//   A6  e = k_a (v_a × v̂_a) + k_m Rᵀ (ĥ_n × b_n)    direction error (ω_mes in the reference)
//   A7  b_g⁺ = clamp(b_g − k_I e dt, ±b_max)        integral term (bias estimate)
//   A8  ω = ω_b − b_g⁺ + k_P e                       corrected rate
//   A9  q_nb⁺ = q_nb ⊗ Exp(ω dt),  Exp(φ) = [cos(|φ|/2), sin(|φ|/2) φ/|φ|]   then normalise
// The accelerometer term is skipped while | |f_b| − g0 | > accel gate (it then sees more than
// gravity); the magnetometer term is skipped when the field has no horizontal component.
// A9 is exact for a constant ω over dt. For small errors the loop is linear with gain k_P
// per axis; the integral term adds a slow pole near k_I/k_P.
#pragma once

#include <optional>

#include "nav/common/frames.hpp"
#include "nav/estimator/filter_params.hpp"
#include "nav/estimator/update_report.hpp"

namespace nav::estimator {

/// Mahony-style complementary attitude filter on the unit quaternion q_nb.
class ComplementaryAttitude {
 public:
  /// Uses the attitude_*, accel_*, mag_weight, gyro_bias_limit_radps and
  /// magnetic_declination_rad fields of params (validated).
  explicit ComplementaryAttitude(const FilterParams& params);

  /// Static alignment (A1..A3) from specific force f_b [m/s², body] and magnetic field m_b
  /// [any unit, body]: roll and pitch from gravity, yaw from the tilt-compensated field.
  /// nullopt when an input is not finite or f_b is zero; a field without horizontal
  /// component gives yaw = declination.
  static std::optional<Quat> align(const Vec3& f_b_mps2, const Vec3& m_b,
                                   double magnetic_declination_rad);

  /// Sets the attitude and zeroes the bias estimate.
  void reset(const Quat& q_nb);

  /// One filter step (A4..A9) over dt_s > 0 [s] with gyro ω_b [rad/s, body], specific force
  /// f_b [m/s², body], field m_b [any unit, body]. NaN/Inf input: rejected, no change.
  StepStatus step(const Vec3& omega_b_radps, const Vec3& f_b_mps2, const Vec3& m_b,
                  double dt_s);

  const Quat& q_nb() const { return q_nb_; }            ///< attitude body→NED
  const Vec3& gyro_bias_b() const { return b_g_; }      ///< bias estimate, body [rad/s]
  const Vec3& last_error() const { return e_; }         ///< e of the last step (A6) [-]

 private:
  FilterParams params_;
  Quat q_nb_ = Quat::Identity();
  Vec3 b_g_ = Vec3::Zero();
  Vec3 e_ = Vec3::Zero();
};

/// Exp map of SO(3) as a unit quaternion: rotation by |phi| about phi/|phi| [rad] (A9).
Quat quat_exp(const Vec3& phi_rad);

}  // namespace nav::estimator
