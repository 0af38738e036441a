// SPDX-License-Identifier: MIT
// Error-state quaternion EKF for attitude, beyond paper P0: no Euler singularity, gyro-bias
// and magnetometer hard-iron estimation, a 3-D magnetometer update whose attitude correction
// is heading-only (the accelerometer alone levels) and which is refused when the field looks
// disturbed, and an accelerometer compensated for the vehicle's own acceleration with the DVL
// velocity.
//
// Reference: J. Solà, "Quaternion kinematics for the error-state Kalman filter",
// arXiv:1711.02508, 2017 (§5 and §6: local error, ESKF prediction, reset); the 3-D field
// measurement with a body-frame hard-iron state follows PX4 EKF2's "mag 3D" fusion (there
// the Earth field is a state too; here it is given). Equation labels E1..E14 are this file's
// own.
//
// Nominal state x:
//   | symbol | meaning                                   | frame      | unit  |
//   |--------|-------------------------------------------|------------|-------|
//   | q_nb   | attitude, Hamilton, body→NED              | b → n      | -     |
//   | b_g    | gyro bias                                 | body (FRD) | rad/s |
//   | h_b    | magnetometer hard iron (vehicle's magnet) | body (FRD) | T     |
// Error state δx ∈ R⁹ (kDTheta, kDBias, kDHardIron slices in the .cpp):
//   | δθ   | local attitude error, q_true = q_nb ⊗ Exp(δθ) | body | rad   | 0..2 |
//   | δb_g | b_true = b_g + δb_g                           | body | rad/s | 3..5 |
//   | δh   | h_true = h_b + δh                             | body | T     | 6..8 |
// Prediction over dt with ω_m the gyro reading, ω = ω_m − b_g:
//   E1  q_nb⁺ = q_nb ⊗ Exp(ω dt)
//   E2  b_g⁺ = b_g,  h_b⁺ = h_b                      (random walks: only P grows)
//   E3  F = [[Exp(ω dt)ᵀ, −J_r(ω dt) dt, 0], [0, I, 0], [0, 0, I]]   J_r the right Jacobian
//       of SO(3), J_r(φ) = I − (1 − cos|φ|)/|φ|² [φ]× + (|φ| − sin|φ|)/|φ|³ [φ]×²  (Solà
//       eq. 183; the exact first-order bias column: −I dt is its small-angle limit)
//   E4  Q = diag(σ_g² dt I, σ_b² dt I, σ_h² dt I)  σ_g gyro noise density, σ_b bias random
//       walk, σ_h hard-iron random walk (0 when h is not estimated, see "Earth field")
//   E5  P⁺ = F P Fᵀ + Q
// Accelerometer (gravity direction), with the DVL's body velocity v_b and its rate v̇_b:
//   E6  f_c = f_m − (v̇_b + ω × v_b)                 specific force of gravity alone
//   E7  h_a(x) = R_nbᵀ g_n;  H_a = [[R_nbᵀ g_n]×, 0, 0]   (g_n = (0, 0, −g0))
//       fused (3-D, std σ_a, Joseph form) only while | |f_c| − g0 | ≤ accel_gate
// Magnetometer, a 3-D field measurement that corrects heading, gyro bias and hard iron:
//   E8  m_b = R_nbᵀ m_n + h_b + v,  v ~ N(0, σ_m² I)    m_n the local Earth field, NED [T]
//   E9  h_m(x) = R_nbᵀ m_n + h_b;  y = m_b − h_m(x)
//   E10 ∂h_m/∂δθ: R_true = R_nb Exp(δθ) ≈ R_nb (I + [δθ]×), so
//       R_trueᵀ m_n ≈ R_nbᵀ m_n − [δθ]× R_nbᵀ m_n = R_nbᵀ m_n + [R_nbᵀ m_n]× δθ,
//       i.e. J_m = [R_nbᵀ m_n]× (the same form as H_a); ∂h_m/∂δh = I.
//   E11 Π = u uᵀ, u = R_nbᵀ e_z (NED down seen in the body frame). A local error along u is a
//       rotation about the vertical: q_nb ⊗ Exp(α u) = Exp(α e_z) ⊗ q_nb, a pure heading
//       change with roll and pitch untouched; Π keeps only that part of δθ.
//   E12 H_m = [J_m Π, 0, I]   (3×9), std σ_m per axis, optional NIS gate (3 dof)
//       Heading-only by design: the field direction also carries tilt, but the accelerometer
//       is the tilt reference, and letting the magnetometer tilt the attitude would turn
//       every unmodelled field error (soft iron, a residual hard iron, nearby steel) into a
//       roll/pitch error that the DVL dead reckoning then integrates. With Π the measurement
//       model has no roll/pitch sensitivity: the components of y that a heading change
//       cannot explain go to h (and to the gyro bias through its covariance with heading);
//       roll/pitch can only move through a tilt–heading covariance in P, which is zero at
//       initialise() and stays small because the accelerometer pins the tilt. Being 3-D, the
//       update (unlike a levelled heading) has no singularity at pitch ±90°.
//       σ_m is set well above the sensor's white noise on purpose: while the heading holds,
//       the heading and the hard iron across the field are unobservable (one direction of
//       δx), and an EKF that linearises at an estimate turned by gyro noise gains spurious
//       information along it and wanders (the EKF-SLAM inconsistency); a larger σ_m slows
//       that down to well below what a real turn brings (1 µT against the GX3-25's 0.2 µT
//       halves the P0 pool runs' worst attitude error; a turn of a few tens of degrees
//       still pins h).
//   Disturbance gates, before E12, on the hard-iron-corrected field m_c = m_b − h_b: refused
//   when | |m_c| / |m_n| − 1 | > mag_norm_gate + 3 σ_n / |m_n| or
//   | I(m_c) − I(m_n) | > mag_inclination_gate + 3 σ_I, with I(m_c) = asin((R_nb m_c)_z /
//   |m_c|) (estimated attitude) and I(m_n) = asin(m_n,z / |m_n|).
//   E8a The widening by the hard iron's uncertainty: σ_n² = m̂ᵀ P_hh m̂ and
//       σ_I² = ŵᵀ P_hh ŵ / |m_c|², the variances of |m_c| and I(m_c) due to δh, with the
//       gradients m̂ = m_c / |m_c| and ŵ = (R_nbᵀ e_z − sin I m̂) / cos I (body frame). Until
//       h has converged the gates cannot tell a disturbance from the hard iron (which moves
//       |m_b| and I(m_b) by up to |h|); once it has, they are the configured ones.
// Update and reset (after every fused measurement):
//   E13 δx = K y (K = P Hᵀ S⁻¹ with an LDLᵀ solve, Joseph-form P, as linear_kf.hpp)
//   E14 q_nb ← q_nb ⊗ Exp(δθ), b_g ← clamp(b_g + δb_g, ±b_max), h_b ← h_b + δh, δx ← 0; the
//       reset Jacobian G = diag(I − ½[δθ]×, I, I) is applied to P: P ← G P Gᵀ.
// Earth field m_n (mag_field_n_tesla):
//   - known (non-zero, e.g. from the World Magnetic Model): h is estimated when
//     initial_hard_iron_std_tesla > 0. Its declination atan2(m_E, m_N) is the one used (the
//     declination_rad parameter is then ignored).
//   - unknown (zero, the default): m_n = R_nb0 m_b0 is taken at initialise() (the first field
//     seen with the initial attitude, declination_rad applied), and h is held at 0 with zero
//     covariance: h is unobservable without the true field, so the filter is then a heading
//     filter whose reference is the first sample's field (any hard iron stays in the heading
//     error, as in the P0 filters).
// Initialise: roll, pitch from the accelerometer and yaw from the levelled field (P0 eqs
// 1-4, ComplementaryAttitude::align), b_g = 0, h_b = 0,
//   P = diag(R_nbᵀ diag(σ_tilt², σ_tilt², σ_yaw²) R_nb, σ_b0² I₃, σ_h0² I₃ or 0)
// (tilt and yaw are about the NED axes; δθ is local, δθ = R_nbᵀ δθ_n). When h is estimated
// the initial yaw carries the hard iron's heading error, asin(h_across / |m_n,horizontal|)
// with h_across its horizontal part across the field: σ_yaw must cover it, σ_yaw ≳ σ_h0 /
// |m_n,horizontal|; the yaw–h correlation then resolves as the heading changes (at rest the
// field cannot tell a heading error from a hard iron across the field).
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
  double initial_yaw_std_rad = 0.1;            ///< σ_yaw [rad], ≳ σ_h0 / |m_n,horizontal|
  double initial_gyro_bias_std_radps = 0.005;  ///< σ_b0 [rad/s]
  double gyro_bias_limit_radps = 0.05;         ///< b_max, clamp of each bias axis [rad/s]
  double accel_std_mps2 = 0.1;                 ///< σ_a per axis [m/s²]
  double accel_gate_mps2 = 2.0;                ///< gate on | |f_c| − g0 | [m/s²]
  /// m_n, local Earth field, NED [T]; zero = unknown (taken at initialise, h not estimated).
  Vec3 mag_field_n_tesla = Vec3::Zero();
  double initial_hard_iron_std_tesla = 3.0e-6;  ///< σ_h0 per axis [T]; 0 = h not estimated
  double hard_iron_walk_tesla_rts = 1.0e-9;     ///< σ_h, hard-iron random walk [T/√s]
  double mag_std_tesla = 1.0e-6;                ///< σ_m per axis [T] (see E12)
  double mag_norm_gate = 0.01;             ///< gate on |m_c| / |m_n| − 1 (+ E8a) [-]; 0 = off
  double mag_inclination_gate_rad = 0.02;  ///< inclination gate (+ E8a) [rad]; 0 = off
  double mag_gate_nis = 0.0;                    ///< NIS gate of the field (3 dof) [-]; 0 = off
  double declination_rad = 0.0;  ///< east positive [rad]; used only when m_n is unknown
};

/// The EskfParams that navd's FilterParams (eskf_* fields, accel_gate_mps2,
/// gyro_bias_limit_radps, magnetic_declination_rad) describe; FilterParams{} maps onto
/// EskfParams{} (a test keeps the two sets of defaults equal).
EskfParams eskf_params(const FilterParams& p);

/// Which measurements the last step fused (for tests and diagnostics).
struct EskfStepInfo {
  UpdateStatus accel = UpdateStatus::kRejectedInvalid;  ///< kRejectedGate when gated out
  UpdateStatus mag = UpdateStatus::kRejectedInvalid;    ///< kRejectedGate when gated out
  double mag_norm_ratio = 0.0;       ///< |m_c| / |m_n| of the sample [-]
  double mag_inclination_rad = 0.0;  ///< inclination of m_c [rad]
  double mag_nis = 0.0;              ///< NIS of the field update (when not gated before) [-]
};

/// The error-state quaternion EKF of the file comment.
class QuatEskf final : public AttitudeFilter {
 public:
  static constexpr int kN = 9;  ///< error-state dimension

  explicit QuatEskf(const EskfParams& params);

  bool initialise(const Vec3& f_b_mps2, const Vec3& m_b_tesla) override;
  AttitudeStatus step(const AttitudeInput& in) override;
  Quat q_nb() const override { return q_nb_; }
  AttitudeFilterKind kind() const override { return AttitudeFilterKind::kEskf; }

  const Vec3& gyro_bias_b() const { return b_g_; }      ///< b_g [rad/s]
  const Vec3& hard_iron_b() const { return h_b_; }      ///< h_b, body [T]
  const Mat<kN, kN>& covariance() const { return P_; }  ///< P of δx
  /// The local (body) error δθ_b is δθ_n = R_nb δθ_b in NED (q ⊗ Exp(δθ_b) =
  /// Exp(R_nb δθ_b) ⊗ q), so the contract's covariance is R_nb P_θθ R_nbᵀ.
  std::optional<Mat3> attitude_covariance_n() const override;
  const EskfStepInfo& last_step() const { return info_; }
  /// True when h is estimated (m_n known and σ_h0 > 0); else h_b stays 0.
  bool estimates_hard_iron() const { return estimate_h_; }
  const Vec3& mag_field_n() const { return m_n_; }                ///< m_n in use, NED [T]
  double mag_reference_norm() const { return m_ref_; }            ///< |m_n| [T]
  double mag_reference_inclination() const { return incl_ref_; }  ///< I(m_n) [rad]

  // The model's pieces, public for the finite-difference tests.
  /// F of E3 for ω = ω_m − b_g over dt.
  static Mat<kN, kN> transition(const Vec3& omega_radps, double dt_s);
  /// h_a of E7 at q [m/s²].
  static Vec3 accel_model(const Quat& q_nb);
  /// ∂h_a/∂δθ of E7 at q.
  static Mat3 accel_jacobian(const Quat& q_nb);
  /// h_m of E9: R_nbᵀ m_n + h_b [T].
  static Vec3 mag_model(const Quat& q_nb, const Vec3& m_n_tesla, const Vec3& h_b_tesla);
  /// Π of E11: projector onto local rotations about the vertical, u uᵀ with u = R_nbᵀ e_z.
  static Mat3 heading_projector(const Quat& q_nb);
  /// H_m of E12 (3×9): [[R_nbᵀ m_n]× Π, 0, I].
  static Mat<3, kN> mag_jacobian(const Quat& q_nb, const Vec3& m_n_tesla);

 private:
  EskfParams params_;
  Quat q_nb_ = Quat::Identity();
  Vec3 b_g_ = Vec3::Zero();
  Vec3 h_b_ = Vec3::Zero();
  Mat<kN, kN> P_ = Mat<kN, kN>::Zero();
  Vec3 m_n_ = Vec3::Zero();  ///< the m_n in use (the parameter or the initialise estimate)
  bool estimate_h_ = false;
  double m_ref_ = 0.0;
  double incl_ref_ = 0.0;
  EskfStepInfo info_;
};

}  // namespace nav::estimator
