// SPDX-License-Identifier: MIT
// MFINS part (b) of paper P1, the model only: the 9-state position error model [δp, δv, δa]
// of the position/velocity nominal, its exact discretisation and Van Loan process noise, and
// the GPS position measurement, in the form the generic UnscentedParticleFilter<9> (upf.hpp)
// consumes. The filter and the nominal are in p1_mfins.hpp.
//
// Reference: Hwang, Lee, Trans. KIEE 60(12), 2011, §4 (docs/papers.md, P1, "MFINS" (b)); the
// Gauss–Markov acceleration error as in Maybeck, "Stochastic Models, Estimation and Control"
// vol. 1, §4.11 (first-order Gauss–Markov, q = 2σ²/τ); Van Loan, "Computing integrals
// involving the matrix exponential", IEEE TAC 23(3), 1978 (Q = ∫ Φ(s) G Q_c Gᵀ Φ(s)ᵀ ds).
// Labels G1..G7 are this file's own.
//
// Nominal (p1_mfins.hpp): p̂_n, v̂_n and the acceleration correction ĉ_n, integrated with
// â_nom = â_ins + ĉ_n (â_ins = R̂_nb f̂ + g_n from the attitude part). Error state δx ∈ R⁹,
// every error = true − nominal:
//   | symbol | meaning                                   | frame | unit | slice     |
//   |--------|-------------------------------------------|-------|------|-----------|
//   | δp     | p_n − p̂_n                                 | NED   | m    | kDp 0..2  |
//   | δv     | v_n − v̂_n                                 | NED   | m/s  | kDv 3..5  |
//   | δa     | a_n − â_nom, the acceleration error        | NED   | m/s² | kDa 6..8  |
// Continuous-time model (β = 1/τ):
//   G1  δṗ = δv
//       δv̇ = δa + n_v          n_v: the accelerometer's white noise in NED, density σ_a² I
//       δȧ = −β δa + n_a       first-order Gauss–Markov, density Q_a = 2β Σ_c
//   Σ_c is what the attitude part says about the correlated part of its acceleration error:
//   Σ_c = J P_att Jᵀ, J = [−[R̂ f̂]×, −R̂, 0] (p1_attitude_ekf.hpp A8 without its white term,
//   which is n_v here), so the Gauss–Markov δa has the stationary covariance Σ_c: the
//   tilt / accelerometer-bias error of part (a), correlated over τ. Why Gauss–Markov and not
//   a random walk: part (a)'s error is bounded (its δgⁿ and δmⁿ updates hold it), a random
//   walk would let δa grow without bound in a GPS outage and ask a time constant anyway to
//   turn Σ_c into a density. τ is a tuning value (P1MfinsTuning), not the paper's.
// Per NED axis the model is the same scalar 3×3 system, so every matrix below is
// C ⊗ M: block (i, j) = C(i, j) M, C the per-axis 3×3, M a 3×3 NED matrix.
//   G2  Φ = exp(F dt) per axis = | 1  dt  φ_p(dt) |     φ_a(s) = e^{−βs}
//                               | 0  1   φ_v(dt) |     φ_v(s) = (1 − e^{−βs})/β
//                               | 0  0   φ_a(dt) |     φ_p(s) = (βs − 1 + e^{−βs})/β²
//       (exact; φ_p by its Taylor series below βs = 0.05, where the closed form cancels)
//   G3  Q = Q_v + Q_a (Van Loan):
//       Q_v = C_v ⊗ σ_a² I,  C_v = | dt³/3  dt²/2  0 |   (δp's block dt³/3: exact)
//                                  | dt²/2  dt     0 |
//                                  | 0      0      0 |
//       Q_a = C_a ⊗ Q_a,  C_a(i, j) = ∫₀^dt φ_i(s) φ_j(s) ds, i, j ∈ {p, v, a}, by 5-point
//       Gauss–Legendre quadrature (exact for polynomials of degree 9; for β dt ≤ 0.1 the
//       error is below 1e-12 relative). C_a is a Gram matrix of three independent
//       functions, hence positive definite, so Q is positive definite whenever Σ_c is, as
//       the UPF requires (upf.hpp); δp's block is σ_a² dt³/3 + C_a(p,p) Q_a.
//   G4  several steps k = 1..K compose exactly (the model is linear):
//       Φ_acc ← Φ_k Φ_acc,  Q_acc ← Φ_k Q_acc Φ_kᵀ + Q_k
//   G5  GPS position: z = p̃_n − p̂_n = δp + v,  h(δx) = δp,  R = σ_p² I
// Nominal, consistent with G1/G2 (the nominal's ĉ follows the mean of the Gauss–Markov δa):
//   G6  over a step: v̂ += (strapdown S3 of â_ins) + φ_v(dt) ĉ,
//       p̂ += (strapdown S4) + φ_p(dt) ĉ,  ĉ ← φ_a(dt) ĉ
//   G7  feedback of a mean δx̄: p̂ += δp̄, v̂ += δv̄, ĉ += δā, particles shifted by −δx̄.
// The model is linear in δx (f = Φ δx, h = δp) and says so (kSharedCovariance, kLinear): every
// particle's UKF is exactly a Kalman filter with the same P, and the UPF runs on its
// shared-covariance path (upf_shared.hpp), the particles differing in their means only.
#pragma once

#include "nav/common/frames.hpp"
#include "nav/estimator/linear_kf.hpp"
#include "nav/estimator/p1_error_model.hpp"

namespace nav::estimator {

/// The position error model of MFINS part (b) (file comment, G1..G7).
struct P1PositionModel {
  static constexpr int kN = 9;             ///< error-state dimension
  static constexpr StateSlice kDp{0, 3};   ///< δp, NED [m]
  static constexpr StateSlice kDv{3, 3};   ///< δv, NED [m/s]
  static constexpr StateSlice kDa{6, 3};   ///< δa, NED [m/s²]
  using VecN = Vec<kN>;
  using MatN = Mat<kN, kN>;

  /// (φ_p, φ_v, φ_a)(s) of G2 for β = 1/τ: the response of (p, v, a) to a unit initial
  /// acceleration error after s seconds ([s²], [s], [-]).
  static Vec3 gm_response(double s, double tau_s);
  /// F of G1 (9×9) for the time constant τ [s]; for the tests.
  static MatN system_matrix(double tau_s);
  /// Φ = exp(F dt) of G2 [-].
  static MatN transition(double dt_s, double tau_s);
  /// C_v of G3, per axis [s³, s², s].
  static Mat3 white_noise_coefficients(double dt_s);
  /// C_a of G3, per axis, 5-point Gauss–Legendre [s⁵ .. s].
  static Mat3 gm_noise_coefficients(double dt_s, double tau_s);
  /// Q = C_v ⊗ σ_a² I + C_a ⊗ (2/τ) Σ_c of G3, for the accelerometer density σ_a
  /// [m/s²/√Hz] and the attitude part's correlated acceleration covariance Σ_c, NED [m²/s⁴].
  static MatN process_noise(double dt_s, double tau_s, double accel_noise_mps2_rthz,
                            const Mat3& Sigma_c_n);
  /// C ⊗ M: block (i, j) = C(i, j) M.
  static MatN kron(const Mat3& C, const Mat3& M);

  /// G4: a linear step (or several composed) handed to the UPF in one predict.
  struct Step {
    MatN Phi = MatN::Identity();  ///< Φ_acc [-]
    MatN Q = MatN::Zero();        ///< Q_acc, the δx units² [m², m²/s², m²/s⁴ ...]
  };

  /// The UPF process model (upf.hpp UpfSharedCovarianceProcess): f = Φ_acc δx, Q = Q_acc.
  struct Process {
    using Input = Step;
    static constexpr bool kSharedCovariance = true;
    MatN Phi(const Step& u, double /*dt_s*/) const { return u.Phi; }
    VecN f(const VecN& x, const Step& u, double /*dt_s*/) const { return u.Phi * x; }
    MatN Q(const Step& u, double /*dt_s*/) const { return u.Q; }
    bool input_valid(const Step& u) const { return u.Phi.allFinite() && u.Q.allFinite(); }
  };

  /// The UPF measurement model of G5 (upf.hpp UpfMeasurementModel).
  struct GpsPosition {
    static constexpr int kMeasDim = 3;
    static constexpr bool kLinear = true;
    double std_m = 0.2;  ///< σ_p per NED axis [m]
    Vec3 h(const VecN& x) const { return x.segment<kDp.dof>(kDp.idx); }
    Mat3 R() const { return std_m * std_m * Mat3::Identity(); }
    Mat<3, kN> H() const {
      Mat<3, kN> H_p = Mat<3, kN>::Zero();
      H_p.block<3, 3>(0, kDp.idx) = Mat3::Identity();
      return H_p;
    }
  };
};

}  // namespace nav::estimator
