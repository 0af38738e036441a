// SPDX-License-Identifier: MIT
// The 15-state error model of paper P1's aided INS (the model only; p1_ekf15.hpp is the
// filter): error dynamics F, its discretisation Φ, process noise Q, and the measurement models
// GPS δp, magnetometer δmⁿ and (for MFINS, p1_attitude_ekf.hpp) gravity δgⁿ.
//
// Reference: Hwang, Lee, Trans. KIEE 60(12), 2011, §3 (docs/papers.md, P1); error dynamics of
// a strapdown INS as in Titterton & Weston, "Strapdown Inertial Navigation Technology", 2nd
// ed., §12.3 (here with a flat, non-rotating NED frame: no Earth or transport rate); reset as
// Solà, arXiv:1711.02508, §7.2 (global error). Labels E1..E11 are this file's own.
//
// Nominal state (strapdown.hpp): p̂_n, v̂_n, q̂_nb, plus the bias estimates b̂_a, b̂_g (body).
// Error state δx ∈ R¹⁵, every error = true − estimate:
//   | symbol | meaning                                  | frame | unit  | slice      |
//   |--------|------------------------------------------|-------|-------|------------|
//   | δp     | p_n − p̂_n                                | NED   | m     | kDp  0..2  |
//   | δv     | v_n − v̂_n                                | NED   | m/s   | kDv  3..5  |
//   | ρ      | (ε_N, ε_E, ε_D): R_nb = Exp(ρ) R̂_nb       | NED   | rad   | kRho 6..8  |
//   |        |   ≈ (I + [ρ]×) R̂_nb                       |       |       |            |
//   | δb_a   | b_a − b̂_a, accelerometer bias            | body  | m/s²  | kDba 9..11 |
//   | δb_g   | b_g − b̂_g, gyro bias                     | body  | rad/s | kDbg 12..14|
// ρ is the paper's attitude error: ε_N, ε_E the tilt errors, ε_D the heading error. It is a
// rotation of the navigation frame applied on the left of the estimate, so: ε_D > 0 means the
// true heading is ε_D east of the estimate (for a level vehicle ψ_true = ψ̂ + ε_D); the
// correction is q̂ ← Exp(ρ̂) ⊗ q̂ (E10); and P_ρρ is directly the covariance $PNVBCOV wants
// (the NED rotation vector of R_true R̂ᵀ): no mapping.
//
// Sensors: ω̃ = ω + b_g + n_g, f̃ = f + b_a + n_a (body), white n_g, n_a with densities σ_g,
// σ_a; ḃ_a = n_ba, ḃ_g = n_bg (σ_ba, σ_bg). ω̂ = ω̃ − b̂_g, f̂ = f̃ − b̂_a.
// Continuous-time error dynamics (first order in δx; derivation: R f − R̂ f̂ =
// (I + [ρ]×) R̂ (f̂ − δb_a − n_a) − R̂ f̂ ≈ −[R̂ f̂]× ρ − R̂ δb_a − R̂ n_a, and from Ṙ = R [ω]×,
// R̂̇ = R̂ [ω̂]×: d/dt Exp(ρ) = [R (ω − ω̂)]× Exp(ρ), so ρ̇ ≈ −R̂ (δb_g + n_g)):
//   E1  δṗ = δv
//       δv̇ = −[R̂_nb f̂]× ρ − R̂_nb δb_a − R̂_nb n_a
//       ρ̇  = −R̂_nb δb_g − R̂_nb n_g
//       δḃ_a = n_ba,  δḃ_g = n_bg
//   E2  F = | 0  I  0           0     0    |      G n: noise columns −R̂ (δv ← n_a),
//           | 0  0  −[R̂ f̂]×    −R̂     0    |      −R̂ (ρ ← n_g), I (δb_a ← n_ba),
//           | 0  0  0           0     −R̂   |      I (δb_g ← n_bg)
//           | 0  0  0           0     0    |
//           | 0  0  0           0     0    |
// Discretisation over a step dt, F frozen at the nominal of the step's start:
//   E3  Φ = exp(F dt) = I + F dt + F² dt²/2 + F³ dt³/6      exact for the frozen F: F is
//       nilpotent (the only chain is δb_g → ρ → δv → δp, so F⁴ = 0). The terms beyond I + F dt
//       carry the attitude error into position within the step (F² dt²/2: ρ → δp). With
//       A = −[R̂ f̂]×, B = −R̂ (the δv row) and C = −R̂ (the ρ row), Φ − I has the blocks
//         δp: (δv) I dt, (ρ) A dt²/2, (δb_a) B dt²/2, (δb_g) A C dt³/6
//         δv: (ρ) A dt, (δb_a) B dt, (δb_g) A C dt²/2;   ρ: (δb_g) C dt
//   E4  Q_c = G diag(σ_a² I, σ_g² I, σ_ba² I, σ_bg² I) Gᵀ = diag(0, σ_a² I, σ_g² I, σ_ba² I,
//       σ_bg² I) (R̂ σ² I R̂ᵀ = σ² I);  Q = ½ (Φ Q_c Φᵀ + Q_c) dt   (trapezoid on the
//       Van Loan integral ∫ Φ(τ) Q_c Φ(τ)ᵀ dτ: keeps the δp–δv correlation of the noise)
// Measurements, each z = H δx + v with δx = 0 before the update (closed loop):
//   E5  GPS position: z = p̃_n − p̂_n = δp + v,  H = [I 0 0 0 0],  R = σ_p² I
//   E6  magnetometer: z = δmⁿ = R̂_nb m̃_b − mⁿ with m̃_b = R_nbᵀ mⁿ + n_m: R̂ R_nbᵀ =
//       (I − [ρ]×), so z ≈ −[ρ]× mⁿ + R̂ n_m = [mⁿ]× ρ + R̂ n_m
//   E7  H_m = [0 0 [mⁿ]× 0 0],  R = σ_m² I (isotropic, so R̂ n_m has it too). [mⁿ]× has the
//       null vector mⁿ: the field observes the two components of ρ across mⁿ (for
//       mⁿ = (m_N, 0, m_D): ε_E, and m_D ε_N − m_N ε_D), never a rotation about mⁿ; it sees
//       no bias directly (δb_g only through the ρ–δb_g covariance the prediction builds).
//   E8  gravity (MFINS): ĝⁿ = −(R̂_nb f̂ − â_motion), z = δgⁿ = ĝⁿ − g_n = â_motion − â_ins
//       with â_ins = R̂_nb f̂ + g_n the INS's acceleration. With δa = a_n − â_ins the
//       acceleration error of the INS, z = δa + (â_motion − a_n): the motion-acceleration
//       error is measurement noise (σ_grav covers it). To first order
//   E9  δa ≈ J_ρ ρ + J_ba δb_a − R̂ n_a,  J_ρ = −[R̂_nb f̂]×,  J_ba = −R̂_nb  (from E1's δv̇)
//       so H_g = [0 0 J_ρ J_ba 0] and R = σ_grav² I. J_ρ observes the tilt (at rest
//       R̂ f̂ ≈ −g_n, J_ρ ρ = g (−ε_E, ε_N, 0)), never the heading; the horizontal J_ba δb_a
//       is indistinguishable from tilt until the attitude changes.
// Error injection and reset after a fused update (closed loop):
//   E10 p̂ += δp̂, v̂ += δv̂, q̂_nb ← Exp(ρ̂) ⊗ q̂_nb, b̂_a += δb̂_a, b̂_g += δb̂_g, δx̂ ← 0
//   E11 P ← G_r P G_rᵀ,  G_r = diag(I, I, I + ½[ρ̂]×, I, I)  (Solà eq. 287, global error:
//       Exp(ρ) Exp(−ρ̂) ≈ Exp((I + ½[ρ̂]×)(ρ − ρ̂))); only the ρ rows and columns change
// One prediction (predict()): F, Φ, Q from the nominal at the step's start (E2..E4),
// P⁺ = Φ P Φᵀ + Q, then the nominal by strapdown_step with ω̂ = ω̃ − b̂_g, f̂ = f̃ − b̂_a
// (strapdown.hpp S1..S4); the bias estimates are constant.
#pragma once

#include "nav/common/frames.hpp"
#include "nav/estimator/linear_kf.hpp"
#include "nav/estimator/p1_types.hpp"
#include "nav/estimator/strapdown.hpp"

namespace nav::estimator {

/// A named slice of an error state (PX4 IdxDof style).
struct StateSlice {
  int idx;  ///< first index
  int dof;  ///< length
};

/// The 15-state error model of the file comment (E1..E11).
struct P1ErrorModel {
  static constexpr int kN = 15;  ///< error-state dimension
  static constexpr StateSlice kDp{0, 3};    ///< δp, NED [m]
  static constexpr StateSlice kDv{3, 3};    ///< δv, NED [m/s]
  static constexpr StateSlice kRho{6, 3};   ///< ρ = (ε_N, ε_E, ε_D), NED [rad]
  static constexpr StateSlice kDba{9, 3};   ///< δb_a, body [m/s²]
  static constexpr StateSlice kDbg{12, 3};  ///< δb_g, body [rad/s]
  using VecN = Vec<kN>;
  using MatN = Mat<kN, kN>;

  /// F of E2 at the nominal attitude R̂_nb and bias-corrected specific force f̂ [m/s², body].
  static MatN system_matrix(const Mat3& R_nb, const Vec3& f_hat_b_mps2);
  /// Φ = exp(F dt) of E3 (exact series, F⁴ = 0), from F's blocks [-].
  static MatN transition(const MatN& F, double dt_s);
  /// G_r P G_rᵀ of E11 in place, for the attitude block G_ρ of reset_jacobian_rho.
  static void apply_reset(const Mat3& G_rho, MatN& P);
  /// Q_c of E4: the noise densities mapped into δx [per second].
  static MatN continuous_noise(const P1Params& p);
  /// Q = ½ (Φ Q_c Φᵀ + Q_c) dt of E4.
  static MatN process_noise(const MatN& Phi, const MatN& Q_c, double dt_s);
  /// P₀ = diag(σ_p², σ_v², σ_tilt², σ_tilt², σ_heading², σ_ba², σ_bg²).
  static MatN initial_covariance(const P1Params& p);
  /// The nominal state at the start: the configured position, velocity and attitude.
  static NavState initial_state(const P1Params& p) {
    return NavState{p.initial_p_n_m, p.initial_v_n_mps, p.initial_q_nb.normalized()};
  }

  /// H of E5 (3×15).
  static Mat<3, kN> gps_jacobian();
  /// z of E6: R̂_nb m̃_b − mⁿ, NED [T].
  static Vec3 mag_residual(const Mat3& R_nb, const Vec3& m_b_tesla, const Vec3& m_n_tesla);
  /// ∂z/∂ρ of E6: [mⁿ]× [T/rad].
  static Mat3 mag_jacobian_rho(const Vec3& m_n_tesla);
  /// H_m of E7 (3×15).
  static Mat<3, kN> mag_jacobian(const Vec3& m_n_tesla);
  /// z of E8: â_motion − (R̂_nb f̂ + g_n) = ĝⁿ − g_n, NED [m/s²].
  static Vec3 gravity_residual(const Mat3& R_nb, const Vec3& f_hat_b_mps2,
                               const Vec3& a_motion_n_mps2, const Vec3& g_n_mps2);
  /// J_ρ of E9: ∂δa/∂ρ = −[R̂_nb f̂]× [m/s²/rad].
  static Mat3 accel_error_jacobian_rho(const Mat3& R_nb, const Vec3& f_hat_b_mps2);
  /// J_ba of E9: ∂δa/∂δb_a = −R̂_nb [-].
  static Mat3 accel_error_jacobian_dba(const Mat3& R_nb);

  /// Exp(ρ) ⊗ q_nb: the attitude correction of E10.
  static Quat inject_attitude(const Quat& q_nb, const Vec3& rho_n_rad);
  /// G_r of E11's attitude block: I + ½[ρ̂]× [-].
  static Mat3 reset_jacobian_rho(const Vec3& rho_n_rad);

  /// One prediction over s.dt_s (file comment) of the nominal x with the bias estimates b̂_a
  /// [m/s², body] and b̂_g [rad/s, body], and of P. The caller has checked s (is_valid).
  /// Returns false, and changes nothing, when the result is not finite.
  static bool predict(NavState& x, const Vec3& b_a_mps2, const Vec3& b_g_radps, MatN& P,
                      const ImuSample& s, const MatN& Q_c, const Vec3& g_n_mps2);

  /// Injects δx̂ into the nominal and the biases and resets P (E10, E11).
  static void inject_and_reset(const VecN& dx, NavState& x, Vec3& b_a_mps2, Vec3& b_g_radps,
                               MatN& P);
};

}  // namespace nav::estimator
