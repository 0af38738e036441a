// SPDX-License-Identifier: MIT
// Error-state quaternion EKF for attitude, beyond paper P0: no Euler singularity, gyro-bias
// estimation, a magnetometer that only ever corrects heading and is refused when the field
// looks disturbed, and an accelerometer compensated for the vehicle's own acceleration with
// the DVL velocity.
//
// Reference: J. Solà, "Quaternion kinematics for the error-state Kalman filter",
// arXiv:1711.02508, 2017 (§5 and §6: local error, ESKF prediction, reset); the heading-only
// magnetometer fusion follows PX4 EKF2's "mag heading" mode. Equation labels E1..E12 are this
// file's own.
//
// Nominal state: q_nb (Hamilton, body→NED), b_g (gyro bias, body) [rad/s].
// Error state δx = (δθ, δb_g) ∈ R⁶, with the attitude error local (in the body frame):
//   q_true = q_nb ⊗ Exp(δθ),   b_true = b_g + δb_g.
// Prediction over dt with ω_m the gyro reading, ω = ω_m − b_g:
//   E1  q_nb⁺ = q_nb ⊗ Exp(ω dt)
//   E2  b_g⁺ = b_g
//   E3  F = [[Exp(ω dt)ᵀ, −J_r(ω dt) dt], [0, I]]   J_r the right Jacobian of SO(3),
//       J_r(φ) = I − (1 − cos|φ|)/|φ|² [φ]× + (|φ| − sin|φ|)/|φ|³ [φ]×²  (Solà eq. 183; the
//       exact first-order bias column: −I dt is its small-angle limit)
//   E4  Q = diag(σ_g² dt I, σ_b² dt I)      σ_g gyro noise density, σ_b bias random walk
//   E5  P⁺ = F P Fᵀ + Q
// Accelerometer (gravity direction), with the DVL's body velocity v_b and its rate v̇_b:
//   E6  f_c = f_m − (v̇_b + ω × v_b)                 specific force of gravity alone
//   E7  h_a(x) = R_nbᵀ (0, 0, −g0);  H_a = [[R_nbᵀ g_n]×, 0]   (g_n = (0, 0, −g0))
//       fused (3-D, std σ_a, Joseph form) only while | |f_c| − g0 | ≤ accel_gate
// Magnetometer, heading only:
//   E8  ψ_m = heading of m_b levelled with the *estimated* roll and pitch + declination
//   E9  h_m(x) = ψ(q_nb) = atan2(R10, R00) (ZYX yaw);  H_m = [∂ψ/∂δθ, 0] with
//       ∂ψ/∂δθ = (0, sinφ, cosφ)/cosθ = (0, R21, R22) / (R00² + R10²)
//       (the yaw row of the ZYX rate map, ψ̇ = (q sinφ + r cosφ)/cosθ, since δθ is a body
//       rotation; the code uses the R_nb form and a test checks it against finite differences)
//       Undefined at pitch ±90°: the update is skipped when R00² + R10² < 1e-6, and when the
//       levelled field's horizontal part is below 1e-3 |m_b| (info: mag = kRejectedInvalid).
//   E10 innovation y = wrap(ψ_m − ψ(q_nb)), std σ_m, optional NIS gate
//   Disturbance gates, before E10: refused when | |m_b| / m_ref − 1 | > mag_norm_gate or
//   | inclination(m_b) − I_ref | > mag_inclination_gate, the inclination taken with the
//   estimated attitude: asin((R_nb m_b)_z / |m_b|). m_ref and I_ref are taken at initialise().
// Update and reset (after every fused measurement):
//   E11 δx = K y (K = P Hᵀ S⁻¹ with an LDLᵀ solve, Joseph-form P, as linear_kf.hpp)
//   E12 q_nb ← q_nb ⊗ Exp(δθ), b_g ← clamp(b_g + δb_g, ±b_max), δx ← 0; the reset Jacobian
//       G = diag(I − ½[δθ]×, I) is applied to P: P ← G P Gᵀ.
// Initialise: roll, pitch from the accelerometer and yaw from the levelled field (P0 eqs
// 1-4, ComplementaryAttitude::align), b_g = 0,
//   P = diag(R_nbᵀ diag(σ_tilt², σ_tilt², σ_yaw²) R_nb, σ_b0² I₃)
// (tilt and yaw are about the NED axes; δθ is local, δθ = R_nbᵀ δθ_n).
// Step outcome: kRejectedInvalid (state untouched) when dt is not finite or ≤ 0 or any input
// is NaN/Inf (v_b and dv_b only when v_b is given); kNumericalFault when an update failed
// (that measurement skipped) or the prediction overflowed (state untouched); else kOk.
#pragma once

#include "nav/common/frames.hpp"
#include "nav/estimator/attitude_filter.hpp"
#include "nav/estimator/linear_kf.hpp"

namespace nav::estimator {

/// Tunables of QuatEskf; make_attitude_filter fills them from FilterParams (eskf_* fields).
struct EskfParams {
  double gyro_noise_radps_rthz = 5.0e-4;       ///< σ_g, angle random walk [rad/s/√Hz]
  double gyro_bias_walk_radps2_rthz = 2.0e-6;  ///< σ_b, bias random walk [rad/s²/√Hz]
  double initial_tilt_std_rad = 0.05;          ///< σ_tilt [rad]
  double initial_yaw_std_rad = 0.2;            ///< σ_yaw [rad]
  double initial_gyro_bias_std_radps = 0.005;  ///< σ_b0 [rad/s]
  double gyro_bias_limit_radps = 0.05;         ///< b_max, clamp of each bias axis [rad/s]
  double accel_std_mps2 = 0.1;                 ///< σ_a per axis [m/s²]
  double accel_gate_mps2 = 2.0;                ///< gate on | |f_c| − g0 | [m/s²]
  double mag_heading_std_rad = 0.05;           ///< σ_m [rad]
  double mag_norm_gate = 0.01;                 ///< relative field-magnitude gate [-]; 0 = off
  double mag_inclination_gate_rad = 0.02;      ///< inclination gate [rad]; 0 = off
  double mag_heading_gate_nis = 0.0;           ///< NIS gate of the heading (1 dof); 0 = off
  double declination_rad = 0.0;                ///< east positive [rad]
};

/// Which measurements the last step fused (for tests and diagnostics).
struct EskfStepInfo {
  UpdateStatus accel = UpdateStatus::kRejectedInvalid;  ///< kRejectedGate when gated out
  UpdateStatus mag = UpdateStatus::kRejectedInvalid;    ///< kRejectedGate when gated out
  double mag_norm_ratio = 0.0;       ///< |m_b| / m_ref of the sample [-]
  double mag_inclination_rad = 0.0;  ///< inclination of the sample [rad]
};

/// The error-state quaternion EKF of the file comment.
class QuatEskf final : public AttitudeFilter {
 public:
  static constexpr int kN = 6;  ///< error-state dimension

  explicit QuatEskf(const EskfParams& params);

  bool initialise(const Vec3& f_b_mps2, const Vec3& m_b_tesla) override;
  AttitudeStatus step(const AttitudeInput& in) override;
  Quat q_nb() const override { return q_nb_; }
  AttitudeFilterKind kind() const override { return AttitudeFilterKind::kEskf; }

  const Vec3& gyro_bias_b() const { return b_g_; }      ///< b_g [rad/s]
  const Mat<kN, kN>& covariance() const { return P_; }  ///< P of δx
  const EskfStepInfo& last_step() const { return info_; }
  double mag_reference_norm() const { return m_ref_; }          ///< m_ref [T]
  double mag_reference_inclination() const { return incl_ref_; }  ///< I_ref [rad]

  // The model's pieces, public for the finite-difference tests.
  /// F of E3 for ω = ω_m − b_g over dt.
  static Mat<kN, kN> transition(const Vec3& omega_radps, double dt_s);
  /// h_a of E7 at q [m/s²].
  static Vec3 accel_model(const Quat& q_nb);
  /// ∂h_a/∂δθ of E7 at q.
  static Mat3 accel_jacobian(const Quat& q_nb);
  /// ψ(q) of E9 [rad].
  static double heading_model(const Quat& q_nb);
  /// ∂ψ/∂δθ of E9 at q (a row).
  static Eigen::RowVector3d heading_jacobian(const Quat& q_nb);

 private:
  EskfParams params_;
  Quat q_nb_ = Quat::Identity();
  Vec3 b_g_ = Vec3::Zero();
  Mat<kN, kN> P_ = Mat<kN, kN>::Zero();
  double m_ref_ = 0.0;
  double incl_ref_ = 0.0;
  EskfStepInfo info_;
};

}  // namespace nav::estimator
