// SPDX-License-Identifier: MIT
// Navigator "upf15" of paper P1: nominal strapdown INS + the 15-state error state of ekf15,
// estimated by an unscented particle filter instead of an EKF, closed loop.
//
// Reference: Hwang, Lee, Trans. KIEE 60(12), 2011, §3 (docs/papers.md, P1, "Aided INS
// baseline", run as "UPF"); the model (state table, E1..E11) is p1_error_model.hpp, the filter
// upf.hpp (P1..P12) with its shared-covariance path (upf_shared.hpp, P13..P16); the structure
// is p1_ekf15.hpp's (B1..B5). Labels U15-1..U15-6 are this file's own.
//
// Processing:
//   U15-1 on_imu: refuse invalid input (counted, state untouched). Φ and Q of the step from
//         the nominal at its start (E2..E4), the nominal by strapdown_step (S1..S4), the
//         particles by P1UpfErrorProcess: δx_i ← Φ δx_i, one shared P ← Φ P Φᵀ + Q (P13).
//   U15-2 then the magnetometer update z = δmⁿ = R̂_nb m̃_b − mⁿ, h = [mⁿ]× ρ, R = σ_m² I
//         (E6, E7) at every sample that carries a field, as ekf15 (B2): fused into every
//         particle's filter without a draw or a weight change (upf.hpp C1; the paper weighs by
//         the GPS likelihood only), NIS gate mag_gate_nis.
//   U15-3 on_gps_position: z = p̃_n − p̂_n, h = δp, R = σ_p² I (E5), NIS gate gps_gate_nis:
//         each particle's filter updates, draws δx̃_i from N(δx̂_i, P̂), is weighted by
//         N(z; δp̃_i, R) and keeps P̂ (upf.hpp L5, L6, the paper's weighting); systematic
//         resampling below ESS < resample_ess_fraction × N_p (P9).
//   U15-4 after each fused update: δx̂ = Σ w_i δx_i (P10) is injected into the nominal and the
//         biases (E10) and every particle is shifted by −δx̂ (P12), so the particles stay
//         centred on zero and the linearisation of E1..E9 holds as for ekf15.
//   U15-5 the reset E11 (P ← G_r P G_rᵀ, G_r = I + ½[ρ̂]× on ρ) is not applied: shift() alone
//         takes G_r = I, for the particles and for their shared P. Exactly, particle i's
//         attitude error after the injection is Log(Exp(ρ_i) Exp(−ρ̂)) ≈ (I + ½[ρ̂]×)(ρ_i − ρ̂):
//         the neglected term is second order (correction × spread); converged, with the
//         magnetometer at the IMU rate, |ρ̂| ~ 1e-4 rad per update.
//   U15-6 solution: p̂_n, v̂_n, q̂_nb of the nominal; P_position_n and P_attitude_n the δp
//         and ρ blocks of the filter's mixture covariance (P11: the shared P̂ plus the spread
//         of the particles; ρ needs no mapping, B5).
// Process noise. The UPF needs Q positive definite (upf.hpp). E4's Q = ½ (Φ Q_c Φᵀ + Q_c) dt
// has a δp block already (its Φ Q_c Φᵀ term: ½ σ_a² dt³ I per axis, with δp–δv covariance
// ½ σ_a² dt² and δv variance σ_a² dt: determinant ¼ σ_a⁴ dt⁴ > 0, no Van Loan block needs
// adding), so Q is positive definite whenever every density is positive. validate() allows
// σ_ba = 0 and σ_bg = 0 (constant biases); a zero bias walk is replaced by kBiasWalkFloor
// times the bias's initial σ per √s (the bias may move 1e-6 of its prior σ in a second:
// nothing, but Q stays PD).
// Everything the update sees is linear in δx (h = H δx), and the process is Φ δx, so every
// particle's UKF is exactly a Kalman filter with the same P: upf15 runs entirely on the
// shared-covariance path (tested: shares_covariance()), one P for all particles, the
// particles differing in their means only. With the same seed two runs are bit-identical; the
// filter's generator is its own (P1Params::seed).
// Why not the reference UPF's weighting (upf.hpp P5, P6): it turns every particle into a point
// at each fused update, and with the magnetometer fused at the IMU rate a GPS fix then finds
// each particle's prior to be one IMU step of Q: the proposal cannot move a particle towards
// the fix, the fix only reweights, and the cloud's bias/tilt diversity is lost to resampling
// within ~0.25 s; the position then drifts unobserved (measured: seed 7, 50 particles, 0.5 km
// after 30 s).
// A failed factorisation or a non-finite result skips that step or update (state untouched)
// and is counted in numerical_faults; nothing throws on data. No allocation per step.
#pragma once

#include "nav/estimator/p1_error_model.hpp"
#include "nav/estimator/p1_types.hpp"
#include "nav/estimator/strapdown.hpp"
#include "nav/estimator/update_report.hpp"
#include "nav/estimator/upf.hpp"

namespace nav::estimator {

/// One IMU step of the error state: Φ and Q (E3, E4) from the nominal at the step's start.
struct P1ErrorStep {
  P1ErrorModel::MatN Phi = P1ErrorModel::MatN::Identity();  ///< Φ [-, mixed units]
  P1ErrorModel::MatN Q = P1ErrorModel::MatN::Zero();        ///< Q [δx units²]
  bool allFinite() const { return Phi.allFinite() && Q.allFinite(); }
};

/// upf15's process model (upf.hpp UpfSharedCovarianceProcess): δx_k = Φ δx_{k−1} + w,
/// w ~ N(0, Q), linear with a state-independent Q.
struct P1UpfErrorProcess {
  using Input = P1ErrorStep;
  static constexpr bool kSharedCovariance = true;
  P1ErrorModel::VecN f(const P1ErrorModel::VecN& dx, const Input& u, double) const {
    return u.Phi * dx;
  }
  P1ErrorModel::MatN Q(const Input& u, double) const { return u.Q; }
  P1ErrorModel::MatN Phi(const Input& u, double) const { return u.Phi; }
};

/// upf15's GPS position model (E5, upf.hpp UpfLinearMeasurement): h = δp [m].
struct P1UpfGpsMeasurement {
  static constexpr int kMeasDim = 3;
  static constexpr bool kLinear = true;
  double std_m = 0.2;  ///< σ_p per NED axis [m]
  Vec3 h(const P1ErrorModel::VecN& dx) const {
    return dx.segment<P1ErrorModel::kDp.dof>(P1ErrorModel::kDp.idx);
  }
  Mat<3, P1ErrorModel::kN> H() const { return P1ErrorModel::gps_jacobian(); }
  Mat3 R() const { return std_m * std_m * Mat3::Identity(); }
};

/// upf15's magnetometer model (E6, E7, upf.hpp UpfLinearMeasurement): h = [mⁿ]× ρ [T].
struct P1UpfMagMeasurement {
  static constexpr int kMeasDim = 3;
  static constexpr bool kLinear = true;
  Mat3 J_rho = Mat3::Zero();  ///< [mⁿ]× [T/rad]
  double std_tesla = 2e-7;    ///< σ_m per axis [T]
  Vec3 h(const P1ErrorModel::VecN& dx) const {
    return J_rho * dx.segment<P1ErrorModel::kRho.dof>(P1ErrorModel::kRho.idx);
  }
  Mat<3, P1ErrorModel::kN> H() const {
    Mat<3, P1ErrorModel::kN> H_m = Mat<3, P1ErrorModel::kN>::Zero();
    H_m.block<3, 3>(0, P1ErrorModel::kRho.idx) = J_rho;
    return H_m;
  }
  Mat3 R() const { return std_tesla * std_tesla * Mat3::Identity(); }
};

/// Strapdown + 15-state error UPF (file comment).
class P1Upf15 final : public P1Navigator {
 public:
  static constexpr int kN = P1ErrorModel::kN;  ///< error-state dimension
  /// A zero bias random walk is replaced by this × the bias's initial σ per √s [1/√s].
  static constexpr double kBiasWalkFloor = 1e-6;

  /// params must pass validate() (contract, NAV_ENSURE).
  explicit P1Upf15(const P1Params& params);

  void on_imu(const ImuSample& sample) override;
  void on_gps_position(const Vec3& p_n_measured_m) override;
  P1Solution solution() const override;
  std::string_view name() const override { return "upf15"; }

  const NavState& nominal() const { return x_; }      ///< p̂_n, v̂_n, q̂_nb
  const Vec3& accel_bias_b() const { return b_a_; }   ///< b̂_a, body [m/s²]
  const Vec3& gyro_bias_b() const { return b_g_; }    ///< b̂_g, body [rad/s]
  /// The filter's mixture covariance of δx (P11).
  P1ErrorModel::MatN covariance() const { return upf_.covariance(); }
  /// The particle filter (particles, weights, shares_covariance()).
  const UnscentedParticleFilter<kN>& filter() const { return upf_; }
  /// Status of the last GPS update (kRejectedInvalid before the first one).
  UpdateStatus last_gps_status() const { return last_gps_; }
  /// Status of the magnetometer update of the last IMU sample (kRejectedInvalid when it made
  /// none).
  UpdateStatus last_mag_status() const { return last_mag_; }

  /// Q_c of E4 with the zero bias walks floored (file comment) [per second].
  static P1ErrorModel::MatN continuous_noise(const P1Params& params);

 private:
  /// Applies a 3-D update (U15-4): fuses (weighted: L5, L6; not: C1), injects, shifts,
  /// records the innovation.
  template <class Meas>
  UpdateStatus update(const char* source, const Meas& meas, const Vec3& z, double gate,
                      bool weighted);

  P1Params params_;
  NavState x_;
  Vec3 b_a_ = Vec3::Zero();
  Vec3 b_g_ = Vec3::Zero();
  P1ErrorModel::MatN Q_c_;
  UnscentedParticleFilter<kN> upf_;
  UpdateStatus last_gps_ = UpdateStatus::kRejectedInvalid;
  UpdateStatus last_mag_ = UpdateStatus::kRejectedInvalid;
};

}  // namespace nav::estimator
