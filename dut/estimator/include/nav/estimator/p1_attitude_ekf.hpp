// SPDX-License-Identifier: MIT
// MFINS part (a) of paper P1: the 9-state attitude/AHRS error-state EKF, run at the IMU rate
// with the magnetometer δmⁿ (heading) and gravity δgⁿ (tilt) updates. A later "mfins"
// navigator pairs it with the 9-state position UPF [δp, δv, δa] (part (b)), handing it the
// corrected attitude, the INS acceleration and the acceleration error δa (A8).
//
// Reference: Hwang, Lee, Trans. KIEE 60(12), 2011, §4 (docs/papers.md, P1, "MFINS"); the
// model blocks are those of p1_error_model.hpp (E1, E6..E11), the update linear_kf.hpp
// (K3..K7). Labels A1..A8 are this file's own.
//
// Nominal state: q̂_nb (body→NED), b̂_a (body, m/s²), b̂_g (body, rad/s). Error state δx ∈ R⁹,
// every error = true − estimate:
//   | symbol | meaning                              | frame | unit  | slice      |
//   |--------|--------------------------------------|-------|-------|------------|
//   | ρ      | R_nb = Exp(ρ) R̂_nb (ε_N, ε_E, ε_D)   | NED   | rad   | kRho 0..2  |
//   | δb_a   | b_a − b̂_a                            | body  | m/s²  | kDba 3..5  |
//   | δb_g   | b_g − b̂_g                            | body  | rad/s | kDbg 6..8  |
// Prediction over dt with ω̂ = ω̃ − b̂_g:
//   A1  q̂_nb⁺ = q̂_nb ⊗ Exp(ω̂ dt)                        (strapdown.hpp S2)
//   A2  F = [[0, 0, −R̂_nb], [0, 0, 0], [0, 0, 0]]  (E1's ρ row); Φ = exp(F dt) = I + F dt,
//       exact for F frozen at the step's start (F² = 0)
//   A3  Q_c = diag(σ_g² I, σ_ba² I, σ_bg² I);  Q = ½ (Φ Q_c Φᵀ + Q_c) dt   (as E4)
//   A4  P⁺ = Φ P Φᵀ + Q
// Updates (each 3-D, δx = 0 before it, Joseph form, optional NIS gate):
//   A5  magnetometer, when the sample carries a field (m̃_b ≠ 0) and mⁿ ≠ 0:
//       z = R̂_nb m̃_b − mⁿ,  H = [[mⁿ]×, 0, 0],  R = σ_m² I                   (E6, E7)
//   A6  gravity, when a motion acceleration â_motion is given: f̂ = f̃ − b̂_a,
//       ĝⁿ = −(R̂_nb f̂ − â_motion),  z = δgⁿ = ĝⁿ − g_n,
//       H = [−[R̂_nb f̂]×, −R̂_nb, 0],  R = σ_grav² I + P_motion               (E8, E9)
//       (P_motion: the covariance of â_motion's error when its source states one, else 0)
//   A7  after each fused update: q̂_nb ← Exp(ρ̂) ⊗ q̂_nb, b̂_a += δb̂_a, b̂_g += δb̂_g, δx̂ ← 0,
//       P ← G P Gᵀ with G = diag(I + ½[ρ̂]×, I, I)                          (E10, E11)
// The motion acceleration (paper trap: the paper never defines it). â_motion is the vehicle's
// acceleration a_n, NED [m/s²], from outside this filter: the position part's estimate (e.g.
// differences of its GPS-corrected velocity over a window), a known manoeuvre, or zero for a
// vehicle assumed unaccelerated (then the centripetal and surge accelerations become tilt
// errors of about |a|/g rad, and σ_grav must cover |a|). It must not be the INS's own
// R̂ f̂ + g_n, nor anything integrated from it alone: then z ≡ 0 and the update is blind.
// Its error is measurement noise of A6 (E8: z = δa + (â_motion − a_n)): P_motion where the
// source knows it, and σ_grav for the rest and the accelerometer white noise at the sample
// rate (σ_a/√dt).
// Output to the position part:
//   A8  â_ins = R̂_nb f̂ + g_n with the state after this step's updates, NED [m/s²] — the
//       acceleration the position part integrates; δâ = â_ins(after) − â_ins(before the
//       updates): the acceleration error of the predicted state that this step's updates
//       estimated and removed (0 when none fused); Σ_δa = J P Jᵀ + (σ_a²/dt) I with
//       J = [−[R̂_nb f̂]×, −R̂_nb, 0] (E9): the covariance of the error δa = a_n − â_ins that
//       remains (attitude and bias uncertainty plus this sample's white accelerometer noise).
//       The position UPF keeps δa as its own state (the paper's decoupling); Σ_δa is what the
//       attitude part knows about it.
// Invalid input (NaN/Inf in the sample or â_motion, dt ∉ (0, max_dt_s]): refused, counted,
// state untouched. A failed update is skipped and counted in numerical_faults.
#pragma once

#include <optional>
#include <vector>

#include "nav/common/frames.hpp"
#include "nav/estimator/linear_kf.hpp"
#include "nav/estimator/p1_error_model.hpp"
#include "nav/estimator/p1_types.hpp"
#include "nav/estimator/update_report.hpp"

namespace nav::estimator {

/// A8: what the attitude part hands the position part after a step.
struct P1AccelerationError {
  Vec3 a_ins_n_mps2 = Vec3::Zero();    ///< â_ins = R̂_nb f̂ + g_n after the updates, NED [m/s²]
  Vec3 delta_a_n_mps2 = Vec3::Zero();  ///< δâ removed by this step's updates, NED [m/s²]
  Mat3 P_delta_a_n = Mat3::Zero();     ///< Σ_δa of the remaining error, NED [m²/s⁴]
};

/// The 9-state attitude EKF of MFINS (file comment).
class P1AttitudeEkf {
 public:
  static constexpr int kN = 9;                ///< error-state dimension
  static constexpr StateSlice kRho{0, 3};     ///< ρ, NED [rad]
  static constexpr StateSlice kDba{3, 3};     ///< δb_a, body [m/s²]
  static constexpr StateSlice kDbg{6, 3};     ///< δb_g, body [rad/s]
  using VecN = Vec<kN>;
  using MatN = Mat<kN, kN>;

  /// Starts at params.initial_q_nb, zero biases, P = diag(σ_tilt², σ_tilt², σ_heading²,
  /// σ_ba² I, σ_bg² I). params must pass validate() (contract, NAV_ENSURE).
  explicit P1AttitudeEkf(const P1Params& params);

  /// One step (A1..A8) with the sample and, when known, the motion acceleration â_motion,
  /// NED [m/s²] (nullopt: no gravity update) with the covariance of its error P_motion
  /// [m²/s⁴] (A6). kRejectedInvalid: state untouched.
  StepStatus step(const ImuSample& sample, const std::optional<Vec3>& a_motion_n_mps2,
                  const Mat3& P_motion = Mat3::Zero());

  const Quat& q_nb() const { return q_nb_; }           ///< q̂_nb, body→NED
  const Vec3& accel_bias_b() const { return b_a_; }    ///< b̂_a, body [m/s²]
  const Vec3& gyro_bias_b() const { return b_g_; }     ///< b̂_g, body [rad/s]
  const MatN& covariance() const { return P_; }        ///< P of δx
  /// P_ρρ: the NED rotation-vector covariance $PNVBCOV wants (ρ is it) [rad²].
  Mat3 attitude_covariance_n() const;
  /// A8 of the last accepted step (zeros before the first).
  const P1AccelerationError& acceleration_error() const { return accel_error_; }
  /// Status of the last step's magnetometer / gravity update (kRejectedInvalid: none made).
  UpdateStatus last_mag_status() const { return last_mag_; }
  UpdateStatus last_gravity_status() const { return last_gravity_; }
  /// The updates of the last step ("mag" [T], "gravity" [m/s²]).
  const std::vector<Innovation>& innovations() const { return innovations_; }
  /// Counters (imu_*, mag_*, gravity_*, numerical_faults are used).
  const P1Stats& stats() const { return stats_; }

  // The model's pieces, public for the finite-difference tests.
  /// Φ of A2 at the attitude R̂_nb before the step.
  static MatN transition(const Mat3& R_nb, double dt_s);
  /// H of A5 (3×9).
  static Mat<3, kN> mag_jacobian(const Vec3& m_n_tesla);
  /// H of A6 and J of A8 (3×9) at R̂_nb and f̂ = f̃ − b̂_a [m/s², body].
  static Mat<3, kN> gravity_jacobian(const Mat3& R_nb, const Vec3& f_hat_b_mps2);

 private:
  UpdateStatus update(const char* source, const Vec3& z, const Mat<3, kN>& H, const Mat3& R,
                      double gate);

  P1Params params_;
  Quat q_nb_ = Quat::Identity();
  Vec3 b_a_ = Vec3::Zero();
  Vec3 b_g_ = Vec3::Zero();
  MatN P_ = MatN::Zero();
  MatN Q_c_ = MatN::Zero();
  P1AccelerationError accel_error_;
  UpdateStatus last_mag_ = UpdateStatus::kRejectedInvalid;
  UpdateStatus last_gravity_ = UpdateStatus::kRejectedInvalid;
  std::vector<Innovation> innovations_;
  P1Stats stats_;
};

}  // namespace nav::estimator
